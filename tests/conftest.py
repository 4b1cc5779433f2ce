"""Test order and the end-to-end tests' seed.

Order for the two workers (xdist hands out whole files in collection order: pyproject.toml turns
off its reordering by file size): the longest first, so that the short ones fill the gaps at the
end. First the end-to-end files that need no seed (a minute or more each), then those that start
from the seed's SMALL phase (built in the first ~40 s), longest first, then test_pipeline (the
TINY phase, ~2 minutes in), then the unit tests.

The seed (tests/workspaces.py): one tiny `dvc repro` whose DVC cache the end-to-end workspaces
start from. When a seeded module is selected, the controller starts building it in the background
at once, so that it runs beside the tests that need no seed instead of holding a worker while the
other waits; the `small_seed_cache` and `tiny_seed_cache` fixtures wait for its phases (or build
them, if the background build failed).
"""

from __future__ import annotations

import os
import signal
import subprocess
import sys
from pathlib import Path

import pytest

from workspaces import SEEDED_MODULES, build_seed, seed_folder

SEED_PROCESS = "_seasonloop_seed_process"

# One thread per process for torch's OpenMP, OpenBLAS and MKL, in the workers and in every stage
# the end-to-end tests start (they inherit it): two workers and the seed's stages share two cores,
# and OpenMP threads that spin waiting for a descheduled sibling made small fits 20x slower
# (test_training's plateau test: 1.2 s alone, 29 s in the suite). Set here, before any of them is
# imported; a variable already set is the user's choice and kept.
for variable in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(variable, "1")


def pytest_collection_modifyitems(items: list[pytest.Item]) -> None:
    def rank(item: pytest.Item) -> int:
        if item.get_closest_marker("e2e") is None:
            return 1 + len(SEEDED_MODULES)
        module = item.module.__name__ if item.module else ""
        return 1 + SEEDED_MODULES.index(module) if module in SEEDED_MODULES else 0

    items.sort(key=rank)  # stable: within a rank, as collected


def seeded_modules_selected(config: pytest.Config) -> bool:
    """Whether this run may reach a test that starts from the seed: e2e not deselected, and a
    folder or a seeded module among the paths asked for."""
    if "not e2e" in (config.option.markexpr or ""):
        return False
    paths = [Path(arg.split("::")[0]) for arg in config.args]
    return any(path.is_dir() or path.stem in SEEDED_MODULES for path in paths)


@pytest.hookimpl(trylast=True)  # after the tmp_path plugin has set the session's basetemp
def pytest_configure(config: pytest.Config) -> None:
    if hasattr(config, "workerinput"):
        # an xdist worker: below the seed's priority, which the seeded tests wait for (the seed gets
        # a core while it builds; the workers keep the rest and every core once it is done)
        os.nice(5)
        return
    if not seeded_modules_selected(config):
        return  # nothing needs the seed
    folder = seed_folder(config._tmp_path_factory.getbasetemp())  # type: ignore[attr-defined]
    folder.mkdir(parents=True, exist_ok=True)
    log = open(folder / "build.log", "w")  # noqa: SIM115 (the background build writes it to the end)
    root = str(Path(__file__).resolve().parents[1])  # tools/, which workspaces.py imports
    process = subprocess.Popen(
        [sys.executable, str(Path(__file__).with_name("workspaces.py")), str(folder)],
        env={**os.environ, "PYTHONPATH": os.pathsep.join(filter(None, [root, os.environ.get("PYTHONPATH")]))},
        stdout=log,
        stderr=subprocess.STDOUT,
        start_new_session=True,  # its own process group: stopped with every stage it started
    )
    setattr(config, SEED_PROCESS, process)


def pytest_unconfigure(config: pytest.Config) -> None:
    """A run that ends early (-x, Ctrl-C) stops a seed build still running."""
    process = getattr(config, SEED_PROCESS, None)
    if process is not None and process.poll() is None:
        os.killpg(process.pid, signal.SIGTERM)
        process.wait()


@pytest.fixture(scope="session")
def small_seed_cache(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The DVC cache of the seed's SMALL run: waits for the background build's first phase."""
    return build_seed(seed_folder(tmp_path_factory.getbasetemp()), "small")


@pytest.fixture(scope="session")
def tiny_seed_cache(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The DVC cache of the seed's SMALL and TINY runs: waits for the whole background build."""
    return build_seed(seed_folder(tmp_path_factory.getbasetemp()), "tiny")
