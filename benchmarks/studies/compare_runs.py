"""Two finished runs of the same queries, each learner against itself: what changed between them
(where the learners were fitted, one setting) does what to each learner's fraction correct, with
the pipeline's paired test along the route and Holm per table (seasonloop.reporting.across_runs).

    python -m benchmarks.studies.compare_runs FIRST SECOND --names NAME NAME

FIRST and SECOND are clones that ran `dvc repro` to the end, each its commit with at most a preset
applied (tools.run_state.finished_run), with the same values of every param the evaluate and
compare stages read (dvc.yaml); their per-query outcomes (data/outcomes) must be of the same query
places. Learners whose `learns` is False are the same model in both runs and are left out. Writes
benchmarks/results/compare_runs_<NAME>_<NAME>.json: the comparisons, each run's commit and preset,
where a run fitted elsewhere took its models from (that clone's commit), and the code that differs
between the two commits. docs/real-data.md's table is `--names here elsewhere` over the real half
(presets/real_half.yaml) and the real half described by a default run's learners
(presets/real_elsewhere.yaml).
"""

from __future__ import annotations

import argparse
import json
import re
import subprocess
from pathlib import Path
from typing import Any

import yaml

from seasonloop.evaluation.matchers import evaluations
from seasonloop.models.core.lookup import get_learner
from seasonloop.params.seasons import available_pairs, pair_name
from seasonloop.params.settings import EvaluateConfig, StatisticsConfig
from seasonloop.registries.choices import value_of
from seasonloop.reporting.across_runs import runs_against, runs_against_markdown
from seasonloop.reporting.comparisons import claims_markdown, csv_reader
from tools.records import machine, write_result
from tools.repository import REPO
from tools.run_state import applied_preset, finished_run, git

# the stages whose params decide a run's outcomes and their statistics (dvc.yaml's own lists)
READ_BY = ("evaluate", "compare")
NAME = re.compile(r"[a-z0-9_-]+")


def shared_params(folder: Path) -> list[str]:
    """The params the evaluate and compare stages of the run in `folder` read (its dvc.yaml)."""
    stages = yaml.safe_load((folder / "dvc.yaml").read_text())["stages"]
    return list(dict.fromkeys(key for stage in READ_BY for key in stages[stage]["params"]))


def param_value(params: dict, key: str, source: Path) -> Any:
    """params' value at dotted `key` (seasonloop.registries.choices.value_of), or one line naming the file."""
    try:
        return value_of(params, key)
    except (KeyError, TypeError):
        raise SystemExit(f"{source}: no key {key}") from None


def models_source(folder: Path, params: dict) -> dict[str, Any] | None:
    """Where a run fitted elsewhere (train.fitted) took its models from: the clone holding
    train.models_dir, its commit and preset; None for a run that fitted its own."""
    if params["train"]["fitted"] != "elsewhere":
        return None
    models = (folder / params["train"]["models_dir"]).resolve()
    clone = Path(git(models, "rev-parse", "--show-toplevel").strip())
    return {
        "folder": str(models),
        "commit": git(clone, "rev-parse", "--short", "HEAD").strip(),
        "preset": applied_preset(clone),
    }


def code_between(folders: list[Path], commits: list[str]) -> list[str] | None:
    """The files of src/, stages/ and dvc.yaml that differ between the two runs' commits (None:
    neither clone holds both commits)."""
    for folder in folders:
        changed = subprocess.run(
            ["git", "-C", str(folder), "diff", "--name-only", *commits, "--", "src", "stages", "dvc.yaml"],
            capture_output=True,
            text=True,
        )
        if changed.returncode == 0:
            return changed.stdout.split()
    return None


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("runs", type=Path, nargs=2)
    parser.add_argument("--names", nargs=2, required=True, help="each run's name in the tables and the record's")
    args = parser.parse_args()
    if args.names[0] == args.names[1] or not all(NAME.fullmatch(name) for name in args.names):
        raise SystemExit(f"--names {' '.join(args.names)}: two different names of a-z, 0-9, _ and -")
    folders = [folder.resolve() for folder in args.runs]
    params = [yaml.safe_load((folder / "params.yaml").read_text()) for folder in folders]
    for key in shared_params(folders[0]):
        values = [param_value(run, key, folder / "params.yaml") for run, folder in zip(params, folders)]
        if values[0] != values[1]:
            raise SystemExit(f"{folders[1]}/params.yaml: {key} differs from {folders[0]}'s: not the same evaluations")
    states = {
        name: {**finished_run(folder), "models": models_source(folder, run)}
        for name, folder, run in zip(args.names, folders, params)
    }
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
    code = code_between(folders, [state["commit"] for state in states.values()])
    path = write_result(
        f"compare_runs_{'_'.join(args.names)}", {**record, "run_states": states, "code_between": code}, machine()
    )
    print(runs_against_markdown(record))
    print(f"wrote {path}")


def _runs_against(path: Path) -> str:
    """compare_runs' record as runs_against_markdown's tables, with the runs it compared."""
    record = json.loads(path.read_text())

    def made(name: str, state: dict[str, Any]) -> str:
        preset = f", presets/{state['preset']}.yaml" if state["preset"] else ""
        models = state.get("models")
        source = f", its models a run at commit {models['commit']}" if models else ""
        return f"{name}: commit {state['commit']}{preset}{source}"

    code = record.get("code_between")
    between = "not known" if code is None else ", ".join(code) or "none"
    runs = "; ".join(made(name, state) for name, state in record["run_states"].items())
    return runs_against_markdown(record) + f"\nRuns: {runs}. Code that differs between the two commits: {between}.\n"


def _transfer_claims(path: Path) -> str:
    """The claims of docs/claims.yaml with `run: transfer` on the docs' record (real-data.md)."""
    claims = yaml.safe_load((REPO / "docs" / "claims.yaml").read_text())
    return claims_markdown(
        json.loads(path.read_text()), {name: claim for name, claim in claims.items() if claim.get("run") == "transfer"}
    )


# docs/write_tables.py's tables of the docs' record (real-data.md: the real half's learners trained
# here against themselves trained elsewhere): name -> (record, snapshot, how it is written)
RECORD, SNAPSHOT = "benchmarks/results/compare_runs_here_elsewhere.json", "real_here_against_elsewhere.json"
TABLES = {
    "real_here_against_elsewhere": (RECORD, SNAPSHOT, _runs_against),
    "transfer_claims": (RECORD, SNAPSHOT, _transfer_claims),
}


if __name__ == "__main__":
    main()
