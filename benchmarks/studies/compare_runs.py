"""Two finished runs of the same queries, each learner against itself: what changed between them
(where the learners were fitted, one setting) does what to each learner's fraction correct, with
the pipeline's paired test along the route and Holm per table (seasonloop.reporting.across_runs).

    python -m benchmarks.studies.compare_runs FIRST SECOND [--names NAME NAME]

FIRST and SECOND are clones that ran `dvc repro` to the end (`dvc status` clean) with the same
learners, pairs, evaluations and statistics settings; their per-query outcomes (data/outcomes)
must be of the same query places; each is its commit with at most a preset applied
(tools.run_state.finished_run). Training-free learners (raw_patchnorm, hog, precomputed) are the
same model in both runs and are left out: each table holds the learners that learn. Writes benchmarks/results/compare_runs.json, naming each run's
commit and preset. Used for docs/real-data.md: the real half with learners fitted on it against the same
learners fitted on the synthetic route (presets/real_half.yaml, presets/real_elsewhere.yaml).
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import yaml

from seasonloop.evaluation.matchers import evaluations
from seasonloop.models.core.lookup import get_learner
from seasonloop.params.seasons import available_pairs, pair_name
from seasonloop.params.settings import EvaluateConfig, StatisticsConfig
from seasonloop.reporting.across_runs import runs_against, runs_against_markdown
from seasonloop.reporting.comparisons import csv_reader
from tools.records import machine, write_result
from tools.run_state import finished_run

# what both runs must share for their outcomes to be compared query by query
SHARED = ("learners", "data.seasons", "evaluate", "statistics")


def shared_value(params: dict, key: str):
    value = params
    for part in key.split("."):
        value = value[part]
    return value


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("runs", type=Path, nargs=2)
    parser.add_argument("--names", nargs=2, default=["first", "second"], help="each run's name in the tables")
    args = parser.parse_args()
    folders = [folder.resolve() for folder in args.runs]
    params = [yaml.safe_load((folder / "params.yaml").read_text()) for folder in folders]
    for key in SHARED:
        if shared_value(params[0], key) != shared_value(params[1], key):
            raise SystemExit(f"{folders[1]}/params.yaml: {key} differs from {folders[0]}'s: not the same evaluations")
    states = {name: finished_run(folder) for name, folder in zip(args.names, folders)}
    evaluate = EvaluateConfig.from_params(params[0])
    pairs = [pair_name(a, b) for a, b in available_pairs(params[0]["data"]["seasons"], evaluate.pairs)]
    learning = [name for name in params[0]["learners"] if get_learner(name).learns]
    record = runs_against(
        {name: csv_reader(folder / "data/outcomes") for name, folder in zip(args.names, folders)},
        learning,
        evaluations(evaluate),
        pairs,
        StatisticsConfig.from_params(params[0]),
    )
    path = write_result("compare_runs", {**record, "run_states": states}, machine())
    print(runs_against_markdown(record))
    print(f"wrote {path}")


def _runs_against(path: Path) -> str:
    """compare_runs' record as runs_against_markdown's tables, with the runs it compared."""
    record = json.loads(path.read_text())
    made = "; ".join(
        f"{name}: commit {state['commit']}" + (f", presets/{state['preset']}.yaml" if state["preset"] else "")
        for name, state in record["run_states"].items()
    )
    return runs_against_markdown(record) + f"\nRuns: {made}.\n"


# docs/write_tables.py's table of this study's record: name -> (record, snapshot, how it is written)
TABLES = {
    "real_here_against_elsewhere": (
        "benchmarks/results/compare_runs.json",
        "real_here_against_elsewhere.json",
        _runs_against,
    )
}


if __name__ == "__main__":
    main()
