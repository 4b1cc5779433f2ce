"""Geographic train/test split with gaps, and removal of tunnels and station stops from the test set.

Places are frame indices along the route. The route is cut into contiguous sections; the last
`test_fraction` of each section is a test block, and `gap` places on either side of every test
block are used for nothing, so no training image shows a test place or its immediate neighbours.
With `folds` K > 1 (blocked cross-validation along the route, Roberts et al. 2017) each section is
tiled by K test blocks: fold k tests the k-th block of every section and trains on the rest, but
for `gap` places on either side of its blocks; the last fold is the study's split, and the K folds
together test every place but tunnels and stops exactly once.
A test_fraction of 1 is the field's protocols (VPR-Bench, Patch-NetVLAD): every place is tested,
and the learners train on the same places in other seasons (params.schema refuses a training season
that is also evaluated). `test_every` keeps every k-th place of a season's test set (place id
divisible by k): the queries of a protocol that samples them.
Tunnels and stops are detected from per-frame statistics (seasonloop.data.preprocess.frame_statistics);
where the true ones are known (the synthetic route), detection_record scores the detection.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

import numpy as np

from seasonloop.data.datasets import SPLIT_FILE, every_kth, split_images_file
from seasonloop.io import load_array, save_array, write_json
from seasonloop.params.settings import SplitConfig


@dataclass(frozen=True)
class Split:
    n_places: int
    train: np.ndarray  # place ids used for training
    test: np.ndarray  # place ids evaluated (tunnels and stops removed)
    gap: np.ndarray  # place ids in the gaps around test blocks
    dropped_tunnel: np.ndarray  # test-block places left out as tunnel (dark) frames
    dropped_stop: np.ndarray  # test-block places left out as station stops (not already tunnels)
    test_every: Mapping[str, int] = field(default_factory=dict)  # season -> keep every k-th test place

    def season(self, season: str) -> Split:
        """The split of `season`: aligned seasons share one, but for test_every."""
        if season in self.test_every:
            return replace(self, test=every_kth(self.test, self.test_every[season], season), test_every={})
        return self

    def to_json(self) -> dict:
        return {
            "n_places": self.n_places,
            **{
                name: getattr(self, name).tolist()
                for name in ("train", "test", "gap", "dropped_tunnel", "dropped_stop")
            },
            **({"test_every": dict(self.test_every)} if self.test_every else {}),
        }


def section_bounds(n_places: int, section_length: int) -> list[tuple[int, int]]:
    """[start, end) of each section: as many as section_length fits best, of near-equal length."""
    if section_length < 2:
        raise ValueError(f"split.section_length: must be at least 2, got {section_length}")
    n_sections = max(1, round(n_places / section_length))
    bounds = np.linspace(0, n_places, n_sections + 1).round().astype(int)
    return [(int(start), int(end)) for start, end in zip(bounds[:-1], bounds[1:])]


def section_blocks(n_places: int, section_length: int, test_fraction: float) -> list[tuple[int, int]]:
    """[start, end) of the test block at the end of each section."""
    sections = section_bounds(n_places, section_length)
    if not 0 < test_fraction < 1:
        raise ValueError(f"split.test_fraction: must be in (0, 1), got {test_fraction}")
    blocks = []
    for start, end in sections:
        size = max(1, round((end - start) * test_fraction))
        blocks.append((end - size, end))
    return blocks


def fold_blocks(n_places: int, section_length: int, test_fraction: float, folds: int) -> list[list[tuple[int, int]]]:
    """[start, end) of each fold's test block in each section: the last fold's are section_blocks'
    (the study's), the other K - 1 share the rest of every section equally, in route order (all K
    about equal where K is near 1 / test_fraction, as params.section_checks asks)."""
    study = section_blocks(n_places, section_length, test_fraction)
    if folds < 1:
        raise ValueError(f"split.folds: must be at least 1, got {folds}")
    if folds == 1:
        return [study]
    per_fold: list[list[tuple[int, int]]] = [[] for _ in range(folds)]
    for (start, _), (block_start, block_end) in zip(section_bounds(n_places, section_length), study):
        if block_start - start < folds - 1:
            raise ValueError(
                f"split.folds: a section of {block_end - start} places cannot hold {folds} test blocks "
                "(split.section_length, test_fraction)"
            )
        bounds = np.linspace(start, block_start, folds).round().astype(int)
        for fold, (low, high) in enumerate(zip(bounds[:-1], bounds[1:])):
            per_fold[fold].append((int(low), int(high)))
        per_fold[-1].append((block_start, block_end))
    return per_fold


def detect_tunnels(brightness: Mapping[str, np.ndarray], dark_threshold: float) -> np.ndarray:
    """A place is a tunnel when its raw frame is dark in any season."""
    return np.any([values < dark_threshold for values in brightness.values()], axis=0)


def detect_stops(change: Mapping[str, np.ndarray], stop_threshold: float) -> np.ndarray:
    """A place is a stop when its frame barely differs from the previous one in any season.

    Consecutive near-identical frames make the 'same place' ambiguous within the stop, which is
    why the study leaves them out of the test sets.
    """
    return np.any([values < stop_threshold for values in change.values()], axis=0)


def split_masks(
    n_places: int, section_length: int, test_fraction: float, gap: int, folds: int = 1, fold: int = -1
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(in a test block, in a gap, training) masks over n_places places of fold `fold` of `folds`
    (fold_blocks; -1: the last, the study's split); a test_fraction of 1 tests and trains on every
    place (a protocol's whole route: the learners see other seasons only)."""
    if gap < 0:
        raise ValueError(f"split.gap: must be >= 0, got {gap}")
    if test_fraction == 1:
        if folds != 1:
            raise ValueError("split.folds: split.test_fraction 1 already tests every place; set folds to 1")
        return np.ones(n_places, bool), np.zeros(n_places, bool), np.ones(n_places, bool)
    in_test_block = np.zeros(n_places, bool)
    near_test = np.zeros(n_places, bool)
    for start, end in fold_blocks(n_places, section_length, test_fraction, folds)[fold]:
        in_test_block[start:end] = True
        near_test[max(0, start - gap) : min(n_places, end + gap)] = True
    train_mask = ~near_test
    if not train_mask.any():
        raise ValueError(
            f"split: no training places left ({n_places} places, section_length {section_length}, gap {gap})"
        )
    return in_test_block, near_test & ~in_test_block, train_mask


def masks_to_split(
    in_test_block: np.ndarray, gap_mask: np.ndarray, train_mask: np.ndarray, tunnel: np.ndarray, stop: np.ndarray
) -> Split:
    """The Split of one season's places from its part masks and its tunnel and stop masks."""
    places = np.arange(len(in_test_block))
    test_mask = in_test_block & ~tunnel & ~stop
    if not test_mask.any():
        raise ValueError(
            "split: every test place is a tunnel or a stop; check split.dark_threshold / split.stop_threshold"
        )
    return Split(
        n_places=len(in_test_block),
        train=places[train_mask],
        test=places[test_mask],
        gap=places[gap_mask],
        dropped_tunnel=places[in_test_block & tunnel],
        dropped_stop=places[in_test_block & stop & ~tunnel],
    )


def make_split(
    n_places: int,
    section_length: int,
    test_fraction: float,
    gap: int,
    tunnel: np.ndarray,
    stop: np.ndarray,
    test_every: Mapping[str, int] | None = None,
    folds: int = 1,
    fold: int = -1,
) -> Split:
    """Sections of `section_length` places, each ending in a test block, with `gap` places unused
    on either side; tunnels and stops left out of the test blocks; test_every: season -> k, that
    season tested on every k-th place only; fold `fold` of `folds` (split_masks)."""
    if tunnel.shape != (n_places,) or stop.shape != (n_places,):
        raise ValueError(f"tunnel/stop masks must have shape ({n_places},)")
    masks = split_masks(n_places, section_length, test_fraction, gap, folds, fold)
    split = masks_to_split(*masks, tunnel, stop)
    return replace(split, test_every=dict(test_every or {}))


def split_route(
    stats: Mapping[str, np.ndarray], seasons: Sequence[str], config: SplitConfig, fold: int = -1
) -> tuple[Split, np.ndarray, np.ndarray]:
    """(split of fold `fold` of split.folds, tunnel mask, stop mask) from the frame statistics
    `stats` ("<season>_brightness" and "<season>_change" per place, as preprocess writes them)."""
    tunnel = detect_tunnels({s: stats[f"{s}_brightness"] for s in seasons}, float(config.dark_threshold))
    stop = detect_stops({s: stats[f"{s}_change"] for s in seasons}, float(config.stop_threshold))
    split = make_split(
        len(tunnel),
        int(config.section_length),
        float(config.test_fraction),
        int(config.gap),
        tunnel,
        stop,
        dict(config.test_every),
        int(config.folds),
        fold,
    )
    return split, tunnel, stop


def write_split_sets(images_dir: Path, out_dir: Path, seasons: Sequence[str], split: Any) -> None:
    """The split folder: each season's <season>.npy of `images_dir` cut into its train and test
    images (its own parts when the seasons are not aligned), and split.json."""
    for season in seasons:
        own = split.season(season)  # a Split, or seasonloop.data.season_split.SeasonSplits
        images = load_array(images_dir / f"{season}.npy")
        save_array(split_images_file(out_dir, season, "train"), images[own.train])
        save_array(split_images_file(out_dir, season, "test"), images[own.test])
    write_json(out_dir / SPLIT_FILE, split.to_json())


def place_seconds(n_places: int, frame_step: int, fps: float) -> np.ndarray:
    """The whole second of the route that each place shows: place p is the (p * frame_step)-th
    sample at `fps` samples per second."""
    return (np.arange(n_places) * int(frame_step) / float(fps)).astype(int)


def detection_scores(found: np.ndarray, truth: np.ndarray) -> dict[str, float | int]:
    """How many places are truly positive and detected, and the detection's recall and precision."""
    hits = int(np.sum(found & truth))
    return {
        "true": int(truth.sum()),
        "found": int(found.sum()),
        "recall": hits / max(1, int(truth.sum())),
        "precision": hits / max(1, int(found.sum())),
    }


def detection_record(
    tunnel: np.ndarray, stop: np.ndarray, true_tunnel: np.ndarray, true_stop: np.ndarray, seconds: np.ndarray
) -> dict[str, dict[str, float | int]]:
    """Tunnel and stop detection scored against the truth per second of the route (true_tunnel,
    true_stop), place p showing second seconds[p] (place_seconds)."""
    return {
        "tunnel": detection_scores(tunnel, true_tunnel[seconds]),
        # a still, dark tunnel frame looks like a stop too; the split counts it as a tunnel
        "stop": detection_scores(stop & ~tunnel, true_stop[seconds]),
    }
