"""Cost against size: presets/full.yaml's pipeline at fractions of the study's places, stage by
stage (wall time and peak memory), and how each stage grows.

    python -m benchmarks.speed.bench_scaling ROOT [--fractions 0.125 0.25 0.5] [--capped]

Each fraction f runs the full preset with synthetic.seconds = 35,768 f places a season and
split.section_length = 3,000 f (the same 12 sections, so the test fraction keeps its meaning) in its
own folder ROOT/<f>, made and resumed as bench_full_run.py's (a session that stops part way goes on
where it stopped). The full size (f = 1) is benchmarks/results/bench_full_run.json, the run of
bench_full_run.py. Prints every stage's seconds and peak memory against places and its growth
exponent (the least-squares slope of log seconds on log places; 1 = linear), and names the stages
growing faster than linearly (exponent above SUPERLINEAR) with their share of the full run. Writes
benchmarks/results/bench_scaling.json.
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import numpy as np

from benchmarks.common import where_measured
from benchmarks.speed.bench_full_run import run
from seasonloop.preset import composed_params
from tools.records import RESULTS_DIR, write_result
from tools.repository import REPO

PRESET = REPO / "presets" / "full.yaml"
SUPERLINEAR = 1.15  # a slope this far above 1 over an 8x range is more than timing noise


def overrides(fraction: float) -> dict[str, int]:
    params = composed_params(PRESET.stem, REPO / "params.yaml", PRESET.parent)
    return {
        "synthetic.seconds": round(params["synthetic"]["seconds"] * fraction),
        "split.section_length": round(params["split"]["section_length"] * fraction),
    }


def growth(places: list[int], values: list[float]) -> float | None:
    """Slope of log value on log places (None with fewer than two positive values)."""
    points = [(np.log(p), np.log(v)) for p, v in zip(places, values) if v > 0]
    if len(points) < 2:
        return None
    x, y = np.array(points).T
    return float(np.polyfit(x, y, 1)[0])


def scaling_table(runs: dict[int, dict]) -> tuple[dict[str, dict], dict[str, dict]]:
    """places -> a run's record (bench_full_run.run's; the largest is the full run) to every
    stage's seconds and peak memory by places, their growth exponents and the stage's share of
    the full run; and the stages growing faster than linearly. A stage missing at a size counts 0."""
    sizes = sorted(runs)
    full = runs[sizes[-1]]
    stages = sorted({stage for result in runs.values() for stage in result["stages"]})
    table = {}
    for stage in stages:
        seconds = [runs[size]["stages"].get(stage, {}).get("seconds", 0.0) for size in sizes]
        memory = [runs[size]["stages"].get(stage, {}).get("peak_rss_mb", 0.0) for size in sizes]
        table[stage] = {
            "seconds": seconds,
            "peak_rss_mb": memory,
            "time_exponent": growth(sizes, seconds),
            "memory_exponent": growth(sizes, memory),
            "share_of_full_run": seconds[-1] / full["total_seconds"],
        }
    superlinear = {
        stage: row
        for stage, row in table.items()
        if row["time_exponent"] is not None and row["time_exponent"] > SUPERLINEAR
    }
    return table, superlinear


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("root", type=Path, help="a folder for the runs (ROOT/<fraction>)")
    parser.add_argument("--fractions", type=float, nargs="+", default=[0.125, 0.25, 0.5])
    parser.add_argument("--capped", action="store_true", help="an AVX2-only CPU's kernels (ISA_CAP)")
    args = parser.parse_args()
    full_places = composed_params(PRESET.stem, REPO / "params.yaml", PRESET.parent)["synthetic"]["seconds"]
    full_path = RESULTS_DIR / "bench_full_run.json"
    if not full_path.is_file():
        raise SystemExit(f"{full_path}: missing; the full size is bench_full_run.py's run (run it first)")
    full_run = json.loads(full_path.read_text())
    full_capped = any((full_run["calls"][-1]["machine"].get("isa_cap") or {}).values())
    if full_capped != args.capped:
        raise SystemExit(
            f"{full_path}: its run was {'' if full_capped else 'not '}capped; run these sizes the same way"
        )
    runs = {full_places: full_run}
    for fraction in args.fractions:
        result = run(args.root / f"{fraction:g}", PRESET, args.capped, overrides(fraction))
        runs[overrides(fraction)["synthetic.seconds"]] = result
        print(f"HEADLINE ({fraction:g}): {result['headline']}")
    sizes = sorted(runs)
    table, superlinear = scaling_table(runs)
    print(f"{'stage':34s} " + " ".join(f"{size:>9d}" for size in sizes) + "  exponent  share")
    for stage, row in sorted(table.items(), key=lambda item: -item[1]["seconds"][-1]):
        exponent = "-" if row["time_exponent"] is None else f"{row['time_exponent']:.2f}"
        print(
            f"{stage:34s} "
            + " ".join(f"{value:9.0f}" for value in row["seconds"])
            + f"  {exponent:>8s}  {100 * row['share_of_full_run']:4.0f}%"
        )
    names = ", ".join(
        f"{stage} ({row['time_exponent']:.2f}, {100 * row['share_of_full_run']:.0f}%)"
        for stage, row in superlinear.items()
    )
    headline = f"places {sizes}: stages growing faster than linearly: {names or 'none'}"
    result = {"places": sizes, "runs": {str(size): runs[size] for size in sizes}, "stages": table, "headline": headline}
    path = write_result("bench_scaling", result, runs[sizes[0]]["calls"][-1]["machine"])
    print(f"wrote {path}\nHEADLINE: {headline}")


def _bench_scaling(path: Path) -> str:
    """benchmarks/speed/bench_scaling.py's record: every stage's seconds and peak memory against places,
    its growth exponents and share of the full run, the commit each size ran from, and where."""
    record = json.loads(path.read_text())
    places = record["places"]
    lines = [
        "| stage | "
        + " | ".join(f"s at {size:,}" for size in places)
        + " | time exponent | peak MB at "
        + f"{places[0]:,} / {places[-1]:,} | memory exponent | share of the full run |",
        "|---|" + "---|" * (len(places) + 4),
    ]
    for stage, row in sorted(record["stages"].items(), key=lambda item: -item[1]["seconds"][-1]):

        def exponent(value: float | None) -> str:
            return "-" if value is None else f"{value:.2f}"

        lines.append(
            f"| {stage} | "
            + " | ".join(f"{value:.0f}" for value in row["seconds"])
            + f" | {exponent(row['time_exponent'])} | {row['peak_rss_mb'][0]:,.0f} / {row['peak_rss_mb'][-1]:,.0f} "
            + f"| {exponent(row['memory_exponent'])} | {100 * row['share_of_full_run']:.1f}% |"
        )
    runs = [(size, record["runs"][str(size)]) for size in places]
    made_from = ", ".join(f"{size:,}: {run.get('made_from', {}).get('commit', '?')}" for size, run in runs)
    notes = [f"{size:,}: {call['load_note']}" for size, run in runs for call in run["calls"] if call.get("load_note")]
    where = where_measured({**record["runs"][str(places[-1])]["calls"][-1], "load_note": "; ".join(notes)})
    return (
        "\n".join(lines)
        + f"\n\n{record['headline']}. Places a season per run and the commit its folder was made from: "
        + f"{made_from}. {where}\n"
    )


# docs/write_tables.py's table of this benchmark's record: name -> (record, snapshot, how it is written)
TABLES = {"bench_scaling": ("benchmarks/results/bench_scaling.json", "bench_scaling.json", _bench_scaling)}


if __name__ == "__main__":
    main()
