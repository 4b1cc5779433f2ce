"""How long the README's default run takes, stage by stage: `dvc repro` from nothing in a fresh copy
of the repository (as a new user's clone), with this CPU's own kernels or, with --capped, those of
an AVX2-only CPU (ISA_CAP: an estimate of the slowest CPU the project meets).

    python -m benchmarks.speed.bench_default_run [--capped]

Writes benchmarks/results/bench_default_run.json (or bench_default_run_capped.json): the total, each
stage's seconds (from DVC's "Running stage" lines) and the largest resident memory of any stage
process; README.md and docs/results.md show them (docs/write_tables.py). Nothing else should run
meanwhile: the load before and after is recorded, and a busy CPU is named in the headline.
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import tempfile
from pathlib import Path

from benchmarks.common import capped_environment, copy_repository, load_note, machine_line, save_and_report
from benchmarks.pipeline_run import timed_repro
from tools.records import ISA_CAP, git_state, machine


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--capped", action="store_true", help="run with an AVX2-only CPU's kernels (ISA_CAP)")
    parser.add_argument("--keep", type=Path, help="run in this new folder and keep it (its dvc.lock and DVC cache)")
    args = parser.parse_args()
    env = capped_environment(ISA_CAP, args.capped)
    if args.capped:
        os.environ.update(ISA_CAP)  # so that machine() records the cap
    measured_on = machine()
    if args.keep:
        args.keep.mkdir(parents=True)
        copy_repository(args.keep)
        # the commit the copy was made from: docs/write_tables.py --from names it, not the copy's own
        (args.keep / "bench_source.json").write_text(json.dumps({"made_from": git_state()}) + "\n")
        total, measured = timed_repro(args.keep, env)
    else:
        with tempfile.TemporaryDirectory(prefix="default-run-") as folder:
            copy_repository(Path(folder))
            total, measured = timed_repro(Path(folder), env)
    stages = {stage: record["seconds"] for stage, record in measured.items()}
    # the largest resident set of any stage process (Linux: kilobytes)
    peak_mb = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss / 1024
    note = load_note(measured_on)
    name = "bench_default_run_capped" if args.capped else "bench_default_run"
    headline = (
        f"the default dvc repro took {total / 60:.1f} min ({len(stages)} stages, largest stage process "
        f"{peak_mb:.0f} MB) on {measured_on['cpu']}{', ISA capped to AVX2' if args.capped else ''}"
    )
    record = {
        "capped": args.capped,
        "total_seconds": total,
        "stages": stages,
        "stage_peak_rss_mb": {stage: record["peak_rss_mb"] for stage, record in measured.items()},
        "peak_memory_mb": peak_mb,
        "load_note": note,
        "headline": headline,
    }
    for stage, seconds in sorted(stages.items(), key=lambda item: -item[1]):
        print(f"  {stage:32s} {seconds:7.1f} s")
    save_and_report(name, record, measured_on)


def _default_run_time(path: Path) -> str:
    """One sentence: how long the default run took from a fresh copy, where, and its slowest stages."""
    record = json.loads(path.read_text())
    slowest = sorted(record["stages"].items(), key=lambda item: -item[1])[:3]
    load = f" ({record['load_note']})" if record.get("load_note") else ", nothing else running"
    return (
        f"`dvc repro` from a fresh clone took **{record['total_seconds'] / 60:.1f} min** on {machine_line(record)}{load}; "
        f"largest stage process {record['peak_memory_mb']:.0f} MB; slowest stages "
        + ", ".join(f"{stage} {seconds:.0f} s" for stage, seconds in slowest)
        + ".\n"
    )


def _default_run_stages(path: Path) -> str:
    """Every stage's seconds, slowest first, and its share of the run."""
    record = json.loads(path.read_text())
    total = record["total_seconds"]
    lines = [_default_run_time(path), "| stage | seconds | share |", "|---|---|---|"]
    for stage, seconds in sorted(record["stages"].items(), key=lambda item: -item[1]):
        lines.append(f"| {stage} | {seconds:.1f} | {100 * seconds / total:.0f}% |")
    return "\n".join(lines) + "\n"


# docs/write_tables.py's tables of this benchmark's records (uncapped, and capped to AVX2): name ->
# (record, snapshot, how it is written)
TABLES = {
    "default_run_stages": ("benchmarks/results/bench_default_run.json", "bench_default_run.json", _default_run_stages),
    "default_run_stages_capped": (
        "benchmarks/results/bench_default_run_capped.json",
        "bench_default_run_capped.json",
        _default_run_stages,
    ),
}


if __name__ == "__main__":
    main()
