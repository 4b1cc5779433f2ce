"""The study's scale in one piece: a preset's `dvc repro` in a folder of its own, timed stage by
stage (seconds and peak memory), resumable across sessions.

    python -m benchmarks.speed.bench_full_run FOLDER [--preset presets/full.yaml] [--capped]

The first call makes FOLDER a copy of this repository as a fresh clone has it (uncommitted changes
included) with the preset applied to its params.yaml (python -m seasonloop.preset), committed once, and records the commit it was made
from; every later call with the same FOLDER goes on where the last one stopped (DVC restarts at the
first unfinished stage, and benchmarks/pipeline_run.py keeps the stages timed before), so the
whole run is one commit's. When `dvc repro` finishes, writes benchmarks/results/bench_full_run.json
(each stage's seconds and peak memory, their sum, every call's machine and load, the learners'
convergence) and prints the command that writes docs/full-scale.md's tables from FOLDER's outputs.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
from pathlib import Path
from typing import Any

import yaml

from benchmarks.common import capped_environment, cell_text, copy_repository, load_note
from benchmarks.pipeline_run import timed_repro
from seasonloop.models.core.lookup import get_learner
from seasonloop.preset import apply_preset, composed_params
from tools.records import ISA_CAP, git_state, machine, write_result
from tools.repository import REPO

SOURCE = "bench_source.json"  # in FOLDER: the commit it was made from, and each call's machine
FULL_SCALE_TABLES = (
    "full_fraction_correct full_pr_landmarks full_autoencoder_training full_training_seasons full_cae_widths "
    "full_ica_basis full_claims"
)


def prepare(folder: Path, preset: Path, overrides: dict[str, Any] | None = None) -> dict:
    """FOLDER made (first call) or found (later calls); its source record. `overrides`: dotted
    keys of the preset set to other values in the folder's params.yaml (bench_scaling's sizes)."""
    source = folder / SOURCE
    if source.is_file():
        return json.loads(source.read_text())
    if folder.exists() and any(folder.iterdir()):
        raise SystemExit(f"{folder}: exists and holds no {SOURCE}: not a run of this script (choose a new folder)")
    folder.mkdir(parents=True, exist_ok=True)
    copy_repository(folder)
    if overrides:
        params = composed_params(preset.stem, folder / "params.yaml", preset.parent)
        for dotted, value in overrides.items():
            *parents, key = dotted.split(".")
            section = params
            for name in parents:
                section = section[name]
            if key not in section:
                raise SystemExit(f"{preset}: no key {dotted} to override")
            section[key] = value
        (folder / "params.yaml").write_text(yaml.safe_dump(params, sort_keys=False))
    else:  # the preset applied as a user applies it, params.yaml's comments kept
        apply_preset(preset.stem, folder / "params.yaml", preset.parent)
    record = {
        "made_from": git_state(),
        "preset": str(preset.relative_to(REPO) if preset.is_relative_to(REPO) else preset),
        "overrides": overrides or {},
        "calls": [],
    }
    source.write_text(json.dumps(record, indent=2) + "\n")
    # the preset as the folder's committed params (a fresh clone of it would run the same)
    subprocess.run(
        ["git", "-c", "user.name=t", "-c", "user.email=t@t", "commit", "-qam", f"params: {preset.name}"],
        cwd=folder,
        check=True,
    )
    return record


def convergence(folder: Path) -> dict[str, dict]:
    """learner -> how its fit ended (metrics/fit/<learner>.json; the learner's how_fit_ended), and
    "<learner> on <seasons>" for every fit of the training-season ablation that records it."""
    found = {}
    for path in sorted((folder / "metrics" / "fit").glob("*.json")):
        found[path.stem] = get_learner(path.stem).how_fit_ended(json.loads(path.read_text()).get("info", {}))
    for path in sorted((folder / "metrics" / "training_seasons").glob("*.json")):
        for seasons, ended in json.loads(path.read_text()).get("fits", {}).items():
            found[f"{path.stem} on {seasons}"] = ended
    return found


def run(folder: Path, preset: Path, capped: bool, overrides: dict[str, Any] | None = None) -> dict:
    """Make or resume FOLDER's run to its end; the record of every stage timed there (see module doc)."""
    folder = folder.resolve()
    record = prepare(folder, preset.resolve(), overrides)
    if capped:
        os.environ.update(ISA_CAP)  # so that machine() records the cap
    measured_on = machine()
    seconds, stages = timed_repro(folder, capped_environment(ISA_CAP, capped))
    record["calls"].append({"machine": measured_on, "seconds": seconds, "load_note": load_note(measured_on)})
    (folder / SOURCE).write_text(json.dumps(record, indent=2) + "\n")
    total = sum(stage["seconds"] for stage in stages.values())
    peak = max(stage["peak_rss_mb"] for stage in stages.values())
    made_from = record["made_from"]
    headline = (
        f"{record['preset']}{' with ' + str(record['overrides']) if record['overrides'] else ''} ran in "
        f"{total / 3600:.2f} h of stage time ({len(stages)} stages, {len(record['calls'])} call(s)), largest stage "
        f"{peak / 1024:.1f} GiB, from commit {made_from['commit']}{' + uncommitted changes' if made_from['dirty'] else ''}"
    )
    return {
        "folder": str(folder),
        "preset": record["preset"],
        "overrides": record["overrides"],
        "made_from": made_from,
        "calls": record["calls"],
        "stages": stages,
        "total_seconds": total,
        "peak_memory_mb": peak,
        "convergence": convergence(folder),
        "headline": headline,
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("folder", type=Path, help="the run's folder (made on the first call, resumed after)")
    parser.add_argument("--preset", type=Path, default=REPO / "presets" / "full.yaml")
    parser.add_argument("--capped", action="store_true", help="an AVX2-only CPU's kernels (ISA_CAP)")
    args = parser.parse_args()
    result = run(args.folder, args.preset, args.capped)
    # the commit measured is the folder's source, not this checkout's now
    path = write_result("bench_full_run", result, {**result["calls"][-1]["machine"], "source": result["made_from"]})
    print(f"wrote {path}\nHEADLINE: {result['headline']}")
    print(
        f"tables: python docs/write_tables.py --snapshot full_run_stages && python docs/write_tables.py --snapshot {FULL_SCALE_TABLES} --from {result['folder']}"
    )


def _full_run_stages(path: Path) -> str:
    """benchmarks/speed/bench_full_run.py's record: the headline, each call, and every stage's seconds and peak memory."""
    record = json.loads(path.read_text())
    calls = "; ".join(
        f"{call['seconds'] / 60:.0f} min on {call['machine']['cpu']}{' (' + call['load_note'] + ')' if call['load_note'] else ''}"
        for call in record["calls"]
    )
    lines = [
        f"{record['headline']}. Calls: {calls}.",
        "",
        "| stage | seconds | share | peak memory MB |",
        "|---|---|---|---|",
    ]
    total = record["total_seconds"]
    for stage, measured in sorted(record["stages"].items(), key=lambda item: -item[1]["seconds"]):
        lines.append(
            f"| {stage} | {measured['seconds']:.0f} | {100 * measured['seconds'] / total:.0f}% | {measured['peak_rss_mb']:.0f} |"
        )
    lines += ["", "| learner | how its fit ended |", "|---|---|"]
    for learner, ended in record["convergence"].items():
        shown = ", ".join(f"{key} {cell_text(value)}" for key, value in ended.items()) or "closed form (no iterations)"
        lines.append(f"| {learner} | {shown} |")
    return "\n".join(lines) + "\n"


# docs/write_tables.py's table of this run's timing record (its outputs are tables of the run's own
# folder, written with --from FOLDER): name -> (record, snapshot, how it is written)
TABLES = {"full_run_stages": ("benchmarks/results/bench_full_run.json", "bench_full_run.json", _full_run_stages)}


if __name__ == "__main__":
    main()
