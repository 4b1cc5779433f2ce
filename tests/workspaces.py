"""Workspaces of the end-to-end tests: copies of the repository with tiny params, and the one tiny
run that most of them start from.

One run of SMALL, then of TINY, is made once per test session (the seed: built in the background
from the first moment, tests/conftest.py). A test that starts from a finished run copies the seed's
workspace and DVC cache (committed_run) and runs only what it changes. TINY's phase starts in a
fresh workspace from SMALL's cache, whose run cache restores the stages the two share
(test_pipeline checks that it does). A test about a fresh clone, or about other data, starts from
nothing.

Run as a script (with the repository root on PYTHONPATH, for tools/), it builds the seed:
PYTHONPATH=. python tests/workspaces.py SEED_FOLDER
"""

from __future__ import annotations

import fcntl
import os
import re
import shutil
import subprocess
import sys
import time
from pathlib import Path

import yaml

from tools.repository import commit_all, copy_sources, dvc, git, tool_env, write_params
from tools.small_runs import SMALL, TINY

# the test modules whose workspaces start from the seed's cache, in the order they run: SMALL's
# longest first, then test_pipeline, which waits for TINY (tests/conftest.py starts the seed early
# when any of them is selected)
SEEDED_MODULES = (
    "test_remote",
    "test_experiments",
    "test_fresh_clone",
    "test_new_learner",
    "test_extending",
    "test_folds",
    "test_pipeline",
)


def make_workspace(root: Path, overrides: dict, cache: Path | None = None) -> Path:
    """A fresh git + DVC copy of the repository at `root` with params.yaml merged with `overrides`;
    with `cache` (a seed phase's cache, build_seed), its DVC cache starts as a hard-linked copy of it."""
    copy_sources(root)
    write_params(root, overrides)
    if cache is not None:
        # hard links: DVC never changes a cache file in place (it writes new ones and makes them
        # read-only), so a workspace adds to its own copy without touching the seed's
        shutil.copytree(cache, root / ".dvc" / "cache", copy_function=os.link)
    commit_all(root)
    return root


def committed_run(root: Path, seed_cache: Path) -> Path:
    """The seed phase's run (`seed_cache`: small_seed_cache or tiny_seed_cache) in a workspace of its
    own with its dvc.lock committed: the run that experiments, clones and replicate routes start
    from. A copy of the seed's workspace after its `dvc repro` (sources, git history, outputs,
    dvc.lock; the phase's frozen cache hard-linked), so nothing is run or restored: restoring the
    same stages from the run cache in a new workspace costs DVC ~0.36 s of CPU a stage."""
    seed_workspace = seed_cache.parent / seed_cache.name.replace("cache-", "repo-", 1)

    def dvc_internals(folder: str, names: list[str]) -> list[str]:
        # the cache comes from the frozen copy below; DVC's tmp/ (locks, its state database) stays
        return ["cache", "tmp"] if Path(folder) == seed_workspace / ".dvc" else []

    shutil.copytree(seed_workspace, root, ignore=dvc_internals)
    shutil.copytree(seed_cache, root / ".dvc" / "cache", copy_function=os.link)
    git(root, "add", "-A")
    assert git(root, "commit", "-qm", "run").returncode == 0
    return root


def repro_with(root: Path, *settings: str, targets: tuple[str, ...] = ()) -> subprocess.CompletedProcess:
    """What `dvc exp run -S key=value ... [targets]` does in the workspace, without saving an
    experiment: each setting written into params.yaml (the value read as YAML, as DVC reads it;
    `++key=value` may add a key the file lacks), then `dvc repro`. For the tests of data and
    layouts: `dvc exp run` also stages every dependency in git after each stage, ~4 s of DVC's CPU
    more on a 16-stage run (test_experiments, test_real_frames and test_remote run it)."""
    path = root / "params.yaml"
    params = yaml.safe_load(path.read_text())
    for setting in settings:
        dotted, value = setting.split("=", 1)
        adds = dotted.startswith("++")
        *parents, key = dotted.removeprefix("++").split(".")
        section = params
        for name in parents:
            section = section.setdefault(name, {}) if adds else section[name]
        if not adds and key not in section:
            raise KeyError(f"{dotted}: not in params.yaml (++{dotted} adds it)")
        section[key] = yaml.safe_load(value)
    path.write_text(yaml.safe_dump(params, sort_keys=False))
    return dvc(root, "repro", *targets)


def in_a_terminal(root: Path, columns: int, *args: str) -> str:
    """What a dvc command prints in a terminal `columns` wide (rich fits its tables to it)."""
    env = tool_env(COLUMNS=str(columns))
    return subprocess.run(
        [str(Path(sys.executable).parent / "dvc"), *args], cwd=root, env=env, capture_output=True, text=True
    ).stdout


# a finished experiment's ref: refs/exps/<baseline commit split 2/38>/<name> (DVC's queue stash and
# executor refs live under refs/exps/celery/, refs/exps/exec/ and others)
EXPERIMENT_REF = re.compile(r"refs/exps/[0-9a-f]{2}/[0-9a-f]{38}/[^/]+")


def wait_for_the_queue(root: Path, experiments: int, timeout_s: float = 1200) -> str:
    """`dvc queue status` once nothing is queued or running any more.

    Each `dvc queue status` costs ~0.8 s of CPU (DVC's start-up), so between its calls the wait
    looks every second at what costs nothing: the git refs of experiments finished since it began
    (refs/exps), and asks DVC again once all `experiments` have one, or every ~8 s (a failed one
    leaves no ref)."""

    def finished() -> set[str]:
        refs = git(root, "for-each-ref", "--format=%(refname)", "refs/exps").stdout.split()
        return {ref for ref in refs if EXPERIMENT_REF.fullmatch(ref)}

    before = finished()
    deadline = time.monotonic() + timeout_s
    last_asked = -float("inf")
    while time.monotonic() < deadline:
        if len(finished() - before) >= experiments or time.monotonic() - last_asked > 8:
            status, last_asked = dvc(root, "queue", "status").stdout, time.monotonic()
            if not any(word in status for word in ("Queued", "Running")):
                return status
        time.sleep(1)
    raise AssertionError(f"the queue did not finish in {timeout_s:.0f} s:\n{status}")


# the seed's phases in the order they are built: SMALL's stages are a subset of TINY's, so the
# tests that need only SMALL's (the longest ones) start after its phase, while TINY's goes on
PHASES = {"small": SMALL, "tiny": TINY}


def _build_phases(folder: Path, upto: str) -> None:
    """Run the phases not done yet, in order, up to and including `upto`; after each, its
    workspace (folder/repo-<phase>) and what `dvc repro` printed (folder/repro-<phase>.log), a
    frozen hard-linked copy of the cache (folder/cache-<phase>) and the file folder/done-<phase>.

    Each phase runs in a fresh workspace of its own, starting from the cache of the phase before
    (whose stages its run cache restores): run on top of the phase before, the .gitignore files DVC
    keeps beside its outputs (data/outcomes/.gitignore, ...) would list the learners in the order
    the phases ran them, not in `learners` order, and a folder dep's hash reads them (the stages
    after evaluate would then differ from a fresh run's)."""
    previous = None
    for phase, overrides in PHASES.items():
        repo = folder / f"repo-{phase}"
        if not (folder / f"done-{phase}").exists():
            shutil.rmtree(repo, ignore_errors=True)
            make_workspace(repo, overrides, cache=previous)
            result = dvc(repo, "repro")
            assert result.returncode == 0, result.stdout[-3000:] + result.stderr[-3000:]
            # what DVC said of each stage (run, or restored from the phase before's run cache):
            # test_pipeline reads it
            (folder / f"repro-{phase}.log").write_text(result.stdout)
            # a copy that no later phase writes into: workspaces copy it while the next phase runs
            shutil.rmtree(folder / f"cache-{phase}", ignore_errors=True)
            shutil.copytree(repo / ".dvc" / "cache", folder / f"cache-{phase}", copy_function=os.link)
            (folder / f"done-{phase}").write_text("")
        previous = folder / f"cache-{phase}"
        if phase == upto:
            return


def build_seed(folder: Path, phase: str = "tiny") -> Path:
    """The seed's DVC cache after `phase` (folder/cache-<phase>), built once: whoever holds
    folder/lock (the background build of tests/conftest.py, or a worker when nobody is building)
    builds the phases in order; others wait for folder/done-<phase>. A failed build leaves no done
    file and releases the lock, and the next caller tries again (and shows the failure)."""
    folder.mkdir(parents=True, exist_ok=True)
    done = folder / f"done-{phase}"
    with open(folder / "lock", "w") as lock:
        while not done.exists():
            try:
                fcntl.flock(lock, fcntl.LOCK_EX | fcntl.LOCK_NB)
            except BlockingIOError:  # being built: wait for this phase's done file
                time.sleep(1)
                continue
            try:
                _build_phases(folder, phase)
            finally:
                fcntl.flock(lock, fcntl.LOCK_UN)
    return folder / f"cache-{phase}"


def seed_folder(basetemp: Path) -> Path:
    """Where the seed of this test session lives: beside the xdist workers' own temporary folders
    (a worker's basetemp is <session basetemp>/<worker id>), so every worker finds the same one."""
    return (basetemp.parent if os.environ.get("PYTEST_XDIST_WORKER") else basetemp) / "seed"


if __name__ == "__main__":
    build_seed(Path(sys.argv[1]), "tiny")
