"""The on-disk layout of the split and of the augmented training set, read back for the learners.

A split folder holds split.json (the place ids of every part, seasonloop.data.split.Split.to_json) and
<season>_train.npy / <season>_test.npy, the (N, H, W) images of those places in split.json's
order. An augmented folder holds <season>.npy: the rows seasonloop.data.augment.augmented_places
describes. The callers pass the folders; which folders the pipeline uses is theirs to say.

With split.folds K > 1 every folder a fold has its own of (split, augmented set, models, features,
ground truth) holds the last fold, the study's split, where a run of one fold holds it, and fold
k < K - 1 in <folder>/folds/<k>/ (fold_dir): whatever reads the study's split alone reads the
folder as before.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from seasonloop.data.augment import augment_training_set, augmented_places
from seasonloop.io import load_array, read_json, save_array
from seasonloop.params.settings import AugmentConfig

SPLIT_FILE = "split.json"
FOLDS = "folds"  # the subfolder of the folds other than the study's


def fold_dir(root: Path, fold: int, folds: int) -> Path:
    """The folder of fold `fold` of `folds` under `root` (a negative fold counts from the last): the
    last fold (the study's split) is root itself, fold k < folds - 1 is root/folds/<k>."""
    if not -folds <= fold < folds:
        raise ValueError(f"fold {fold} of {folds}: no such fold")
    fold %= folds
    return root if fold == folds - 1 else root / FOLDS / str(fold)


def fold_dirs(root: Path, folds: int) -> list[Path]:
    """Every fold's folder under `root`, fold 0 first (fold_dir)."""
    return [fold_dir(root, fold, folds) for fold in range(folds)]


def count_folds(root: Path) -> int:
    """How many folds a folder written by fold_dir holds: 1 + its folds/0 .. folds/<K-2>."""
    others = root / FOLDS
    if not others.is_dir():
        return 1
    names = sorted(path.name for path in others.iterdir())
    if sorted(names, key=lambda name: int(name) if name.isdigit() else -1) != [str(k) for k in range(len(names))]:
        raise ValueError(f"{others}: expected the folders 0 to {len(names) - 1}, found {', '.join(names)}")
    return len(names) + 1


def read_split(split_dir: Path) -> dict:
    """split.json of `split_dir`, as written (n_places and the place ids of every part)."""
    return read_json(split_dir / SPLIT_FILE)


def split_images_file(split_dir: Path, season: str, part: str) -> Path:
    """<season>_<part>.npy for part "train" or "test"."""
    return split_dir / f"{season}_{part}.npy"


def augmented_file(augmented_dir: Path, season: str) -> Path:
    return augmented_dir / f"{season}.npy"


def every_kth(places: np.ndarray, k: int, season: str) -> np.ndarray:
    """The places whose id is a multiple of k (VPR-Bench's Nordland queries: every 10th frame)."""
    kept = np.asarray(places)[np.asarray(places) % int(k) == 0]
    if not len(kept):
        raise ValueError(f"split.test_every.{season}: no test place of {season} is a multiple of {k}")
    return kept


def season_split(split: Mapping[str, Any], season: str) -> Mapping[str, Any]:
    """One season's split (n_places and the place ids of every part): its own when the seasons are
    not aligned (split.json's "seasons"), else the shared one, its test places cut to every k-th for
    a season of "test_every" (seasonloop.data.split.Split.season)."""
    if "seasons" not in split:
        every = split.get("test_every", {})
        if season in every:
            return {
                **split,
                "test": every_kth(np.asarray(split["test"], dtype=np.int64), every[season], season).tolist(),
            }
        return split
    if season not in split["seasons"]:
        raise ValueError(f"{season}: not in the split (rerun the split stage)")
    return split["seasons"][season]


def season_part(split: Mapping[str, Any], season: str, part: str) -> np.ndarray:
    """The place ids of `part` ("train", "test", ...) of one season (season_split)."""
    return np.asarray(season_split(split, season)[part], dtype=np.int64)


def test_places(split_dir: Path, season: str | None = None) -> np.ndarray:
    """Place ids of the test images of `season` (rows of <season>_test.npy); aligned seasons share
    them, and then `season` may be None."""
    split = read_split(split_dir)
    if season is None:
        if "seasons" in split:
            raise ValueError("the seasons are not aligned: ask for one season's test places")
        return np.asarray(split["test"])
    return season_part(split, season, "test")


def test_images(split_dir: Path, seasons: Sequence[str]) -> dict[str, np.ndarray]:
    """season -> its (N_test, H, W) test images."""
    return {season: load_array(split_images_file(split_dir, season, "test")) for season in seasons}


def trained_on(learns: bool, seasons: Sequence[str], whole_route: bool) -> str:
    """What a learner was fitted on, in words, for the runtime table and the report: nothing (a
    training-free descriptor), every place of the training traverses (a whole-route protocol, which
    allows database traverses only: seasonloop.params.across), or their training places."""
    if not learns:
        return "nothing (training-free)"
    if whole_route:
        return f"every place of {', '.join(seasons)} (the map; no query traverse)"
    return f"the training places of {', '.join(seasons)}"


def training_images(split_dir: Path, augmented_dir: Path | None, seasons: Sequence[str]) -> np.ndarray:
    """The concatenated training images of `seasons`: the augmented sets of `augmented_dir`, or the
    split's originals when it is None."""
    if augmented_dir is not None:
        paths = [augmented_file(augmented_dir, season) for season in seasons]
    else:
        paths = [split_images_file(split_dir, season, "train") for season in seasons]
    return np.concatenate([load_array(path) for path in paths])


def training_places(split_dir: Path, seasons: Sequence[str], copies: int) -> np.ndarray:
    """The place id of every image that training_images returns, with `copies` augmented copies per
    original (0 for the originals only)."""
    split = read_split(split_dir)
    if not seasons:
        return np.asarray(split["train"])[:0]
    return np.concatenate([augmented_places(_training_place_ids(split, season), copies) for season in seasons])


def training_traverses(split_dir: Path, seasons: Sequence[str], copies: int) -> np.ndarray:
    """The traverse of every image that training_images returns: its season's position in
    `seasons` (which images show one place in other conditions)."""
    split = read_split(split_dir)
    counts = [len(augmented_places(_training_place_ids(split, season), copies)) for season in seasons]
    return np.repeat(np.arange(len(seasons)), counts)


def _training_place_ids(split: Mapping[str, Any], season: str) -> np.ndarray:
    """The place id of each training image of `season`: when the seasons are not aligned, its
    frames' reference places, so that held-out validation blocks are the same stretch of track in
    every season."""
    train = season_part(split, season, "train")
    if "seasons" in split:
        return np.asarray(split["seasons"][season]["reference_place"], dtype=np.int64)[train]
    return train


def write_augmented_sets(
    split_dir: Path, out_dir: Path, seasons: Sequence[str], config: AugmentConfig
) -> dict[str, dict]:
    """Augment every season's training images into out_dir/<season>.npy; season -> its image counts
    (the rows of the study's Table 3)."""
    split = read_split(split_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    per_season = {}
    for index, season in enumerate(seasons):
        train = load_array(split_images_file(split_dir, season, "train"))
        # a distinct, reproducible stream per season
        augmented = augment_training_set(
            train,
            int(config.copies),
            int(config.seed) + index,
            bool(config.horizontal_flip),
            float(config.width_shift),
            float(config.height_shift),
        )
        save_array(augmented_file(out_dir, season), augmented)
        own = season_split(split, season)
        per_season[season] = {
            "frames": own["n_places"],
            "train": len(own["train"]),
            "train_augmented": len(augmented),
            "test": len(own["test"]),
        }
    return per_season


def fold_counts(per_fold: Sequence[Mapping[str, Mapping[str, int]]]) -> dict[str, Any]:
    """The dataset table's entry of a run of several folds, from each fold's write_augmented_sets
    counts: how many folds, each season's test places over all of them (every place tested once)
    and each fold's training images."""
    seasons = list(per_fold[-1])
    return {
        "count": len(per_fold),
        "test": {season: sum(int(fold[season]["test"]) for fold in per_fold) for season in seasons},
        "train": {season: [int(fold[season]["train"]) for fold in per_fold] for season in seasons},
    }


def dataset_record(
    split: Mapping[str, Any], per_season: Mapping[str, dict], frames: Mapping[str, Any], detection: Mapping[str, Any]
) -> dict[str, Any]:
    """The dataset table (study Table 3): image counts per season and in all, what the split left
    out, what a place is (frames.json of the frames step), which ground truth says what is correct
    and the detection scores when there are any. The key order is the JSON file's."""
    # aligned seasons share the split's counts; traverses that are not give each season its own
    own = [season_split(split, season) for season in per_season]
    return {
        "seasons": dict(per_season),
        "total_images": sum(part["n_places"] for part in own),
        "total_train": sum(len(part["train"]) for part in own),
        "total_test": sum(len(part["test"]) for part in own),
        "dropped_tunnel": len(split["dropped_tunnel"]),
        "dropped_stop": len(split["dropped_stop"]),
        "gap": len(split["gap"]),
        # what a place (and so a tolerance of one place) is, and what makes a match correct
        "ground_truth": frames.get("ground_truth", "aligned"),
        "place": frames["place"],
        "frame_step": frames["frame_step"],
        "pairing": frames["pairing"],
        # the measured offset of each season against the first (seasonloop.data.alignment)
        "alignment": frames["alignment"],
        "offsets": frames["offsets"],
        **({"detection": detection} if detection else {}),
    }
