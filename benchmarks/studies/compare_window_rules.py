"""How SeqSLAM's contrast-enhancement window should meet a break in the database: the three rules
of `sequence.window_at_breaks` (ignore: OpenSeqSLAM's, clipped at the database's ends only;
shift: a fixed-size window shifted inside the segment; clip: clipped at the segment's ends) on a
finished run's own descriptors and ground truth.

    python -m benchmarks.studies.compare_window_rules WORKSPACE [WORKSPACE ...]

For each WORKSPACE (a clone that ran `dvc repro`: data/features, data/ground_truth, params.yaml),
every learner, pair and metric of its params is matched with `+seq` under each rule through the
pipeline's own functions (seasonloop.evaluation.matchers.match_distances); single images do not
depend on the rule. Prints each rule's fraction correct against `clip` (cells up / down, mean and
range of the difference in points) and writes benchmarks/results/compare_window_rules.json.
Whichever rule, the window holds only database columns of the query's own row: no ground truth
and no other query enters the enhancement, so no rule leaks.
"""

from __future__ import annotations

import argparse
import dataclasses
import json
from pathlib import Path

import numpy as np
import yaml

from seasonloop.data.ground_truth import PairTruth, truth_file
from seasonloop.evaluation.distances import distance_matrix
from seasonloop.evaluation.matchers import match_distances
from seasonloop.io import load_array
from seasonloop.params.choices import WINDOW_RULES
from seasonloop.params.seasons import available_pairs, pair_name
from seasonloop.params.settings import EvaluateConfig, SequenceConfig
from tools.records import machine, write_result

BASELINE = "clip"


def workspace_fractions(workspace: Path) -> dict[str, dict[str, float]]:
    """'<learner>/<pair>@<metric>' -> rule -> `+seq` fraction correct (%) in one finished run."""
    params = yaml.safe_load((workspace / "params.yaml").read_text())
    params["sequence"].setdefault("window_at_breaks", BASELINE)  # a run from before the key
    evaluate, sequence = EvaluateConfig.from_params(params), SequenceConfig.from_params(params)
    pairs = available_pairs(params["data"]["seasons"], evaluate.pairs)
    found: dict[str, dict[str, float]] = {}
    for learner in sorted(path.name for path in (workspace / "data/features").iterdir() if path.is_dir()):
        features = workspace / "data/features" / learner
        for database, query in pairs:
            truth = PairTruth.load(truth_file(workspace / "data/ground_truth", database, query))
            descriptors = [load_array(features / f"{season}.npy") for season in (database, query)]
            for metric in [evaluate.metric, *evaluate.extra_metrics]:
                distances = distance_matrix(descriptors[0], descriptors[1], metric=metric)
                cell = found.setdefault(f"{learner}/{pair_name(database, query)}@{metric}", {})
                for rule in WINDOW_RULES:
                    ruled = dataclasses.replace(sequence, window_at_breaks=rule)
                    metrics, _, _ = match_distances(distances, truth, "sequence", evaluate, ruled)
                    cell[rule] = 100 * float(metrics["fraction_correct"])
    return found


def against_baseline(fractions: dict[str, dict[str, float]]) -> dict[str, dict[str, float]]:
    """rule -> cells up, down, equal, and the mean, least and largest difference (points) from BASELINE."""
    summary = {}
    for rule in WINDOW_RULES:
        differences = np.array([cell[rule] - cell[BASELINE] for cell in fractions.values()])
        summary[rule] = {
            "cells": int(differences.size),
            "up": int((differences > 1e-9).sum()),
            "down": int((differences < -1e-9).sum()),
            "mean_points": float(differences.mean()),
            "min_points": float(differences.min()),
            "max_points": float(differences.max()),
        }
    return summary


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("workspaces", type=Path, nargs="+")
    args = parser.parse_args()
    runs = {}
    for workspace in args.workspaces:
        fractions = workspace_fractions(workspace.resolve())
        summary = against_baseline(fractions)
        runs[str(workspace)] = {"fractions": fractions, "against_clip": summary}
        print(f"{workspace}: +seq fraction correct against '{BASELINE}' over {len(fractions)} learner x pair x metric")
        for rule, row in summary.items():
            print(
                f"  {rule:7s} up {row['up']:3d}  down {row['down']:3d}  mean {row['mean_points']:+.2f}  "
                f"range {row['min_points']:+.1f} .. {row['max_points']:+.1f} points"
            )
    means = {
        rule: np.mean([run["against_clip"][rule]["mean_points"] for run in runs.values()]) for rule in WINDOW_RULES
    }
    headline = "mean +seq difference from 'clip' (points): " + ", ".join(
        f"{rule} {value:+.2f}" for rule, value in means.items()
    )
    path = write_result("compare_window_rules", {"runs": runs, "headline": headline}, machine())
    print(f"wrote {path}\nHEADLINE: {headline}")


def _compare_window_rules(path: Path) -> str:
    """benchmarks/studies/compare_window_rules.py's record: per run, each rule's +seq fraction correct against 'clip'."""
    record = json.loads(path.read_text())
    lines = [
        "| run | cells | `ignore`: mean points, up / down | `shift`: mean points, up / down |",
        "|---|---|---|---|",
    ]
    for workspace, run in record["runs"].items():
        folder = Path(workspace)
        name = folder.parent.name if folder.name == "repo" else folder.name  # a test's workspace: its test
        cells = [
            f"{row['mean_points']:+.2f}, {row['up']} / {row['down']}"
            for row in (run["against_clip"][rule] for rule in ("ignore", "shift"))
        ]
        lines.append(f"| {name} | {run['against_clip']['clip']['cells']} | " + " | ".join(cells) + " |")
    return "\n".join(lines) + f"\n\nComputed on {record['machine']['cpu']} (fractions correct; no timing).\n"


# docs/write_tables.py's tables of this study's record: name -> (record, snapshot, how it is
# written); two runs (the record is rewritten by each): the full preset run's outputs, then the
# default run's and the tests' non-aligned workspaces
TABLES = {
    "compare_window_rules_full": (
        "benchmarks/results/compare_window_rules.json",
        "compare_window_rules_full.json",
        _compare_window_rules,
    ),
    "compare_window_rules": (
        "benchmarks/results/compare_window_rules.json",
        "compare_window_rules.json",
        _compare_window_rules,
    ),
}


if __name__ == "__main__":
    main()
