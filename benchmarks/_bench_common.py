"""Shared helpers of the benchmark scripts (run from the repository root; not a pytest module).
Not named _common: stages/_common.py is imported under that name, and a test process that imports
both would get whichever came first.

Data: the pipeline's preprocessed images when `dvc repro` has written data/split/, otherwise
images rendered by seasonloop.data.synthetic and preprocessed by seasonloop.data.preprocess.
"""

from __future__ import annotations

import os
import platform
import subprocess
import sys
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
import torch

from seasonloop.data.augment import augment_training_set
from seasonloop.data.preprocess import enhance_image_contrast, to_gray
from seasonloop.data.synthetic import SyntheticRoute
from seasonloop.io import read_json, write_json
from seasonloop.machine import cpu_model
from seasonloop.models.core.learner import to_json_value
from seasonloop.params.seasons import SEASONS

# the variables, and their values, that make this CPU run an AVX2-only CPU's kernels (torch's,
# oneDNN's, OpenBLAS's): an estimate of the slowest CPU the project meets
ISA_CAP = {"ATEN_CPU_CAPABILITY": "avx2", "ONEDNN_MAX_CPU_ISA": "AVX2", "OPENBLAS_CORETYPE": "Haswell"}
SPLIT_DIR = Path("data/split")
REPO = Path(__file__).resolve().parents[1]
RESULTS_DIR = Path("benchmarks/results")
# Fallback synthetic route: frames at the pipeline's storage size, then its preprocessing defaults.
FRAME_HEIGHT, FRAME_WIDTH, HEIGHT, WIDTH = 72, 128, 32, 64
SYNTHETIC_PLACES = 1000
SYNTHETIC_TEST_FROM = 850  # places [0, 800) train, a gap of 50, [850, 1000) test


def has_split() -> bool:
    return all((SPLIT_DIR / f"{season}_train.npy").is_file() for season in SEASONS)


def _render(seasons: tuple[str, ...], places: range, seed: int) -> dict[str, np.ndarray]:
    """Preprocessed (N, 32, 64) uint8 images of `places` (seconds) of the synthetic route per season."""
    route = SyntheticRoute(SYNTHETIC_PLACES, seed)
    images = {}
    for season in seasons:
        frames = np.stack([route.frame(season, float(t), FRAME_WIDTH, FRAME_HEIGHT) for t in places])
        images[season] = enhance_image_contrast(to_gray(frames, HEIGHT, WIDTH), "clahe", 2.0, 4)
    return images


def training_images(n_samples: int, seed: int) -> tuple[np.ndarray, str]:
    """n_samples uint8 (N, 32, 64) training images of all seasons, and a line saying where from.

    Seasons' training images concatenated, topped up with seeded flipped/shifted copies (the
    study's augmentation) when fewer than n_samples exist.
    """
    if has_split():
        originals = np.concatenate([np.load(SPLIT_DIR / f"{season}_train.npy") for season in SEASONS])
        source = f"data/split/*_train.npy ({len(originals)} images)"
    else:
        rendered = _render(SEASONS, range(SYNTHETIC_TEST_FROM - 50), seed)
        originals = np.concatenate([rendered[season] for season in SEASONS])
        source = f"synthetic route rendered and preprocessed ({len(originals)} images)"
    copies = max(0, -(-n_samples // len(originals)) - 1)
    images = augment_training_set(originals, copies, seed)[:n_samples]
    if copies:
        source += f" + {copies} augmented cop{'y' if copies == 1 else 'ies'} each"
    return images, source


def pair_images(database: str, query: str, seed: int) -> tuple[np.ndarray, np.ndarray, np.ndarray, str]:
    """Test images of two seasons, their place ids, and where they came from."""
    if has_split():
        places = np.asarray(read_json(SPLIT_DIR / "split.json")["test"])
        images = [np.load(SPLIT_DIR / f"{season}_test.npy") for season in (database, query)]
        return images[0], images[1], places, "data/split/<season>_test.npy"
    places = np.arange(SYNTHETIC_TEST_FROM, SYNTHETIC_PLACES)
    rendered = _render((database, query), range(SYNTHETIC_TEST_FROM, SYNTHETIC_PLACES), seed)
    return rendered[database], rendered[query], places, "synthetic route, places 850-999"


def timed(function: Callable[[], Any]) -> tuple[Any, float]:
    """(function(), wall seconds)."""
    start = time.perf_counter()
    result = function()
    return result, time.perf_counter() - start


def cpu_busy_fraction(seconds: float = 1.0) -> float | None:
    """Fraction of all cores busy over `seconds` while this process sleeps, i.e. other work
    (from /proc/stat; None where it does not exist)."""

    def snapshot() -> tuple[int, int] | None:
        try:
            fields = [int(value) for value in Path("/proc/stat").read_text().split("\n")[0].split()[1:]]
        except OSError:
            return None
        idle = fields[3] + fields[4]  # idle + iowait
        return sum(fields) - idle, sum(fields)

    first = snapshot()
    time.sleep(seconds)
    second = snapshot()
    if first is None or second is None or second[1] == first[1]:
        return None
    return (second[0] - first[0]) / (second[1] - first[1])


def capped_environment(cap: dict[str, str], capped: bool) -> dict[str, str]:
    """This process's environment for a child process: with `cap`'s variables set if `capped`,
    without any of them otherwise (whatever this shell had set)."""
    env = {key: value for key, value in os.environ.items() if key not in cap}
    return {**env, **cap} if capped else env


def machine() -> dict[str, Any]:
    """What the timings are measured on, how busy the CPU is with other work just now, and the
    source measured (git_state: taken here, at the start, as a commit made during a long run
    is not what ran)."""
    return {
        "source": git_state(),
        "cpu": cpu_model(),
        # an ISA cap (ATEN_CPU_CAPABILITY=avx2 ONEDNN_MAX_CPU_ISA=AVX2 OPENBLAS_CORETYPE=Haswell)
        # estimates an AVX2-only CPU
        "isa_cap": {key: os.environ.get(key) for key in ISA_CAP},
        "cpu_count": os.cpu_count(),
        "torch_threads": torch.get_num_threads(),
        "cuda": torch.cuda.get_device_name(0) if torch.cuda.is_available() else None,
        "other_cpu_busy_fraction": cpu_busy_fraction(),
        "python": platform.python_version(),
        "torch": torch.__version__,
    }


def load_note(before: dict[str, Any]) -> str:
    """A warning line when other work kept the CPU busy before or after the run, else ''."""
    busy = {"before": before["other_cpu_busy_fraction"], "after": cpu_busy_fraction()}
    if any(value is not None and value > 0.25 for value in busy.values()):
        shown = ", ".join(f"{key} {value:.0%}" for key, value in busy.items() if value is not None)
        return f"NOTE: other work kept the CPU busy ({shown} of all cores): these timings may be slowed"
    return ""


def git_state() -> dict[str, Any]:
    """The commit this checkout is at, and whether it has uncommitted changes (what was measured)."""

    def git(*args: str) -> str:
        return subprocess.run(["git", *args], cwd=REPO, capture_output=True, text=True).stdout.strip()

    return {"commit": git("rev-parse", "--short", "HEAD") or None, "dirty": bool(git("status", "--porcelain", "-uno"))}


def write_result(name: str, record: dict[str, Any], measured_on: dict[str, Any]) -> Path:
    """Write benchmarks/results/<name>.json with `measured_on` (machine(), taken at the start) and
    the commit measured (at the start), and return its path."""
    path = RESULTS_DIR / f"{name}.json"
    write_json(path, to_json_value({**record, "machine": measured_on, **measured_on.get("source", git_state())}))
    return path


def save_and_report(name: str, record: dict[str, Any], measured_on: dict[str, Any]) -> Path:
    """write_result, then print where it went, the record's load note if it has one, and its
    headline last (the line a reader and docs/benchmarks.md look for); the path written."""
    path = write_result(name, record, measured_on)
    print(f"wrote {path}")
    if record.get("load_note"):
        print(record["load_note"])
    print(f"HEADLINE: {record['headline']}")
    return path


def copy_repository(root: Path) -> None:
    """The repository's source files (as a fresh clone has them, plus uncommitted changes) in a new
    git repository at root, for a run that starts from nothing: the tests' own copy (tests/workspaces.py)."""
    sys.path.insert(0, str(REPO / "tests"))
    from workspaces import commit_all, copy_sources

    copy_sources(root)
    commit_all(root)
