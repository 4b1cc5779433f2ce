"""Replicate routes kept in the repository, so that routes run on different machines or days pool
as one set.

A route's experiment lives in one machine's DVC cache and git experiment refs. `python -m
tools.replicate_routes keep` writes what the replicate record reads of each route into
docs/results/routes/<route>/, which git carries: its metrics/summary.json and
metrics/training_seasons.json, its per-query outcomes as outcomes.npz (each pair's query places
and, per learner and evaluation, which queries were right: the columns the paired tests read;
seasonloop.reporting.comparisons) and route.json (seed, preset, experiment, commit, and the
pipeline it ran: `fingerprint`, and the params it ran with). `collect` pools kept routes with the experiments it finds when
every fingerprint is the same, and refuses one that differs with a line naming the route, the stage
and what differs.
"""

from __future__ import annotations

import json
import shutil
import subprocess
import tempfile
from collections.abc import Iterable, Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np
import yaml

from seasonloop.reporting.comparisons import Reader, csv_reader
from tools.repository import REPO

KEPT = REPO / "docs" / "results" / "routes"
SUMMARY, TRAINING = "metrics/summary.json", "metrics/training_seasons.json"
CODE = ("src/", "stages/")  # a stage's dependencies that are code (always part of the fingerprint)


def without_seed(params: Mapping[str, Any]) -> dict[str, Any]:
    """A stage's params from dvc.lock but the route's seed (declared as the section `synthetic` or
    as `synthetic.seed`)."""
    kept = {key: value for key, value in params.items() if key != "synthetic.seed"}
    if isinstance(kept.get("synthetic"), Mapping):
        kept["synthetic"] = {key: value for key, value in kept["synthetic"].items() if key != "seed"}
    return kept


def overlap(out: str, dep: str) -> bool:
    """Whether a stage that writes path `out` writes some of what path `dep` reads (the same path,
    one inside the other)."""
    return dep == out or dep.startswith(out.rstrip("/") + "/") or out.startswith(dep.rstrip("/") + "/")


def upstream(lock: Mapping[str, Any], stages: Iterable[str]) -> list[str]:
    """`stages` and every stage of a dvc.lock whose outputs they read, directly or not, sorted."""
    entries = lock["stages"]
    found, todo = set(), list(stages)
    while todo:
        name = todo.pop()
        if name in found:
            continue
        found.add(name)
        deps = [dep["path"] for dep in entries[name].get("deps", [])]
        todo += [
            other
            for other, entry in entries.items()
            if any(overlap(out["path"], dep) for out in entry.get("outs", []) for dep in deps)
        ]
    return sorted(found)


def fingerprint(lock: Mapping[str, Any], stages: Iterable[str]) -> dict[str, dict[str, Any]]:
    """stage -> {cmd, code: {path: its hash entry}, params} of `stages` (those the lock has) and the
    stages upstream of them in a route's dvc.lock, its seed left out: what two routes must share to
    pool as one set. "code" holds every dependency no stage of the lock writes (code under src/ and
    stages/, and data from outside: data/nordland/...); one another stage writes is followed upstream."""
    entries = lock["stages"]
    written = [out["path"] for entry in entries.values() for out in entry.get("outs", [])]

    def from_outside(path: str) -> bool:
        return path.startswith(CODE) or not any(overlap(out, path) for out in written)

    return {
        name: {
            "cmd": entries[name]["cmd"],
            "code": {
                dep["path"]: {key: value for key, value in dep.items() if key != "path"}
                for dep in entries[name].get("deps", [])
                if from_outside(dep["path"])
            },
            "params": {file: without_seed(values) for file, values in entries[name].get("params", {}).items()},
        }
        for name in upstream(lock, [stage for stage in stages if stage in entries])
    }


def yaml_at(rev: str, path: str, root: Path = REPO) -> dict[str, Any]:
    """A YAML file of a git revision (an experiment's dvc.lock or params.yaml)."""
    shown = subprocess.run(["git", "show", f"{rev}:{path}"], cwd=root, capture_output=True, text=True)
    if shown.returncode:
        raise SystemExit(f"replicate_routes: no {path} at {rev[:7]}: {shown.stderr.strip()}")
    return yaml.safe_load(shown.stdout)


def difference(first: Mapping[str, Any], other: Mapping[str, Any]) -> str | None:
    """What differs between two fingerprints, in a few words (None: the same pipeline)."""
    for stage in sorted(set(first) | set(other)):
        if stage not in first or stage not in other:
            return f"stage {stage} is in one route's pipeline only"
        for part in ("cmd", "code", "params"):
            mine, theirs = first[stage][part], other[stage][part]
            if mine == theirs:
                continue
            if part == "code":
                changed = sorted(path for path in set(mine) | set(theirs) if mine.get(path) != theirs.get(path))
                return f"stage {stage}: code {', '.join(changed)}"
            return f"stage {stage}: {part}"
    return None


def write_outcomes(
    outcomes_dir: Path, path: Path, learners: Sequence[str], suffixes: Sequence[str], pairs: Sequence[str]
) -> None:
    """outcomes_dir/<learner>/<pair><suffix>.csv as one npz: "<pair>" -> its query places (the same
    for every evaluation of the pair, checked), "<learner>/<pair><suffix>" -> which were right."""
    read = csv_reader(outcomes_dir)
    arrays: dict[str, np.ndarray] = {}
    for pair in pairs:
        for learner in learners:
            for suffix in suffixes:
                places, correct = read(learner, pair, suffix)
                if pair in arrays and not np.array_equal(arrays[pair], places):
                    raise ValueError(f"{outcomes_dir / learner / (pair + suffix)}.csv: other queries than {pair}'s")
                arrays.setdefault(pair, places)
                arrays[f"{learner}/{pair}{suffix}"] = correct
    np.savez_compressed(path, **arrays)


def npz_reader(path: Path) -> Reader:
    """The reader of an outcomes.npz (write_outcomes): (query places, correct) of an evaluation."""
    with np.load(path) as stored:
        arrays = {key: stored[key] for key in stored.files}

    def read(learner: str, pair: str, suffix: str) -> tuple[np.ndarray, np.ndarray]:
        return arrays[pair], arrays[f"{learner}/{pair}{suffix}"]

    return read


def keep(name: str, fetched: Path, route: Mapping[str, Any], outcomes: Mapping[str, Sequence[str]]) -> Path:
    """Write route `name` (its outputs fetched into `fetched`; route: seed, preset, rev, commit,
    fingerprint, params, queue) into KEPT/name, replacing a route kept before under that name; outcomes: the
    learners, evaluation suffixes and pairs whose outcomes the record reads."""
    target = KEPT / name
    KEPT.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory(dir=KEPT) as tmp:  # nothing half-written under `target`
        staged = Path(tmp) / name
        staged.mkdir()
        for source in (SUMMARY, TRAINING):
            shutil.copyfile(fetched / source, staged / Path(source).name)
        write_outcomes(
            fetched / "data" / "outcomes",
            staged / "outcomes.npz",
            outcomes["learners"],
            outcomes["suffixes"],
            outcomes["pairs"],
        )
        (staged / "route.json").write_text(json.dumps(route, indent=1, sort_keys=True) + "\n")
        if target.exists():  # the route kept before stays until the new one is in place
            target.rename(Path(tmp) / "replaced")
        staged.rename(target)
    return target


def kept_routes(preset: str | None, root: Path = KEPT) -> dict[str, dict[str, Any]]:
    """name -> route.json (with its folder) of the routes kept under `preset` (None: the committed
    params'), by seed."""
    found = {}
    for file in sorted(root.glob("*/route.json")):
        route = json.loads(file.read_text())
        if route["preset"] == preset:
            found[file.parent.name] = {**route, "folder": file.parent}
    return dict(sorted(found.items(), key=lambda item: item[1]["seed"]))
