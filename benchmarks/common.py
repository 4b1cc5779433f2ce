"""Shared helpers of the benchmarks (run from the repository root as modules:
`python -m benchmarks.speed.bench_pca`).

Data: the pipeline's preprocessed images when `dvc repro` has written data/split/, otherwise
images rendered by seasonloop.data.synthetic and preprocessed by seasonloop.data.preprocess.
"""

from __future__ import annotations

import json
import os
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np

from seasonloop.data.augment import augment_training_set
from seasonloop.data.preprocess import enhance_image_contrast, to_gray
from seasonloop.data.synthetic import SyntheticRoute
from seasonloop.io import read_json
from seasonloop.params.seasons import SEASONS
from tools.records import cpu_busy_fraction, write_result
from tools.repository import commit_all, copy_sources

SPLIT_DIR = Path("data/split")
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


def capped_environment(cap: dict[str, str], capped: bool) -> dict[str, str]:
    """This process's environment for a child process: with `cap`'s variables set if `capped`,
    without any of them otherwise (whatever this shell had set)."""
    env = {key: value for key, value in os.environ.items() if key not in cap}
    return {**env, **cap} if capped else env


def load_note(before: dict[str, Any]) -> str:
    """A warning line when other work kept the CPU busy before or after the run, else ''."""
    busy = {"before": before["other_cpu_busy_fraction"], "after": cpu_busy_fraction()}
    if any(value is not None and value > 0.25 for value in busy.values()):
        shown = ", ".join(f"{key} {value:.0%}" for key, value in busy.items() if value is not None)
        return f"NOTE: other work kept the CPU busy ({shown} of all cores): these timings may be slowed"
    return ""


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
    git repository at root, for a run that starts from nothing (as the tests' workspaces)."""
    copy_sources(root)
    commit_all(root)


def cell_text(value: object) -> str:
    """A value in a table: booleans lower case, floats to 3 significant digits."""
    if isinstance(value, bool):
        return str(value).lower()
    return f"{value:.3g}" if isinstance(value, float) else str(value)


def machine_line(record: dict) -> str:
    """The CPU a benchmark ran on, its threads, and whether its instruction set was capped."""
    machine = record["machine"]
    capped = any((machine.get("isa_cap") or {}).values())
    return f"{machine['cpu']}, {machine['torch_threads']} threads, instruction set " + (
        "capped to AVX2 (an estimate for an AVX2-only CPU)" if capped else "not capped"
    )


def headline_table(path: Path) -> str:
    """A CPU benchmark's own headline (ratio, convergence and quality, as the script states them) and
    where it ran (docs/write_tables.py's table of a benchmark whose headline says it all)."""
    record = json.loads(path.read_text())
    load = record.get("load_note") or "nothing else running"
    return (
        f"| result | measured on | load |\n|---|---|---|\n| {record['headline']} | {machine_line(record)} | {load} |\n"
    )


def where_measured(record: dict) -> str:
    """The sentence under a benchmark's table: the CPU, threads, instruction set and load."""
    load = record.get("load_note") or "nothing else running"
    return f"Measured on {machine_line(record)}; {load}."
