"""How many queries the sequence descriptors (`+delta`, `+smoothed`) can get right at most, under
each rule of `sequence.descriptor_window_at_breaks`, on a finished run's own test blocks.

    python -m benchmarks.studies.window_ceiling WORKSPACE [WORKSPACE ...]

A query's sequence descriptor is computed over its window (seasonloop.evaluation.
descriptor_sequences.sequence_windows); queries that share a window share one descriptor, so at
most one of them can match its own place. For each WORKSPACE (a clone that ran `dvc repro` to the end, its commit with at most a
preset applied: tools.run_state.finished_run; its data/split, every fold's, and sequence.length) this counts the distinct windows of
each fold's test places and writes the ceiling, distinct windows / queries, with the test blocks
(runs of consecutive place ids) behind it, to benchmarks/results/window_ceiling.json.
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import numpy as np
import yaml

from seasonloop.data.datasets import count_folds, fold_dirs, read_split
from seasonloop.evaluation.descriptor_sequences import sequence_windows
from seasonloop.evaluation.sequence import segment_offsets
from seasonloop.params.choices import DESCRIPTOR_WINDOW_RULES
from tools.records import machine, write_result
from tools.run_state import finished_run


def run_ceiling(workspace: Path) -> dict:
    """One run's test blocks (count, median length) and, per rule, its distinct windows and ceiling:
    a bound where a query is right at its own place alone (aligned, tolerance_frames 0); with a
    tolerance, queries that share a window can all be right, and the run is refused."""
    params = yaml.safe_load((workspace / "params.yaml").read_text())
    if params["data"]["ground_truth"] != "aligned" or params["evaluate"]["tolerance_frames"] != 0:
        raise ValueError(
            f"{workspace}/params.yaml: a ceiling needs data.ground_truth aligned and evaluate.tolerance_frames 0 "
            "(one right place a query)"
        )
    length = int(params["sequence"]["length"])
    split = workspace / "data" / "split"
    places = [np.asarray(read_split(folder)["test"]) for folder in fold_dirs(split, count_folds(split))]
    blocks: list[int] = []
    for test in places:
        since_start, to_end = segment_offsets(test, len(test), "places")
        blocks += (to_end[since_start == 0] + 1).tolist()
    queries = sum(len(test) for test in places)
    rules = {}
    for rule in DESCRIPTOR_WINDOW_RULES:
        distinct = sum(len(set(zip(*sequence_windows(test, length, rule)))) for test in places)
        rules[rule] = {"distinct_windows": distinct, "ceiling": distinct / queries}
    return {
        "sequence_length": length,
        "folds": len(places),
        "queries": queries,
        "blocks": len(blocks),
        "median_block": float(np.median(blocks)),
        "rules": rules,
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("workspaces", type=Path, nargs="+")
    args = parser.parse_args()
    runs = {
        str(workspace): {**finished_run(workspace.resolve()), **run_ceiling(workspace.resolve())}
        for workspace in args.workspaces
    }
    for workspace, run in runs.items():
        ceilings = ", ".join(f"{rule} {100 * row['ceiling']:.1f}%" for rule, row in run["rules"].items())
        print(
            f"{workspace}: {run['queries']} queries in {run['blocks']} blocks (median {run['median_block']:g}): {ceilings}"
        )
    print(f"wrote {write_result('window_ceiling', {'runs': runs}, machine())}")


def _window_ceiling(path: Path) -> str:
    """window_ceiling's record: per run, its test blocks and the most queries each rule lets be right."""
    record = json.loads(path.read_text())
    rules = list(next(iter(record["runs"].values()))["rules"])
    lines = [
        "| run | commit | L | queries | test blocks | median block | "
        + " | ".join(f"ceiling, `{r}`" for r in rules)
        + " |",
        "|---|---|---|---|---|---|" + "---|" * len(rules),
    ]
    for run in record["runs"].values():
        cells = " | ".join(f"{100 * run['rules'][rule]['ceiling']:.1f}%" for rule in rules)
        lines.append(
            f"| {run['preset'] or 'default'} | {run['commit']} | {run['sequence_length']} | {run['queries']} | {run['blocks']} "
            f"| {run['median_block']:g} | {cells} |"
        )
    return "\n".join(lines) + "\n"


# docs/write_tables.py's table of this study's record: name -> (record, snapshot, how it is written)
TABLES = {"window_ceiling": ("benchmarks/results/window_ceiling.json", "window_ceiling.json", _window_ceiling)}


if __name__ == "__main__":
    main()
