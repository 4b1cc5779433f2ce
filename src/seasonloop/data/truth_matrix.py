"""Ground-truth matrices given with a dataset: <folder>/<database>-<query>.npz holding 'hard' (and
optionally 'soft'), boolean (database places, query places) over the places extract_frames keeps
(rows of data/frames/<season>.npy), as VPR_Tutorial's GThard / GTsoft."""

from __future__ import annotations

from pathlib import Path

import numpy as np


def matrix_file(folder: Path, database: str, query: str) -> Path:
    return Path(folder) / f"{database}-{query}.npz"


def read_matrix(path: Path, n_database: int, n_query: int) -> tuple[np.ndarray, np.ndarray | None]:
    """(hard, soft or None) of one file, checked: its shape must be (n_database, n_query) and its
    values 0/1 or boolean; anything else is one line naming the file."""
    if not Path(path).is_file():
        raise FileNotFoundError(f"{path}: ground-truth matrix not found (data.ground_truth_dir)")
    try:
        with np.load(path) as data:
            arrays = {key: data[key] for key in ("hard", "soft") if key in data.files}
    except (OSError, ValueError) as error:
        raise ValueError(f"{path}: cannot read the ground-truth matrix ({error})") from None
    if "hard" not in arrays:
        raise ValueError(f"{path}: no array 'hard' (the boolean database x query ground truth)")
    for key, array in arrays.items():
        if array.shape != (n_database, n_query):
            raise ValueError(
                f"{path}: '{key}' has shape {array.shape}, expected (database places, query places) = "
                f"({n_database}, {n_query})"
            )
        if array.dtype != np.bool_ and not np.isin(array, (0, 1)).all():
            raise ValueError(f"{path}: '{key}' must be boolean (or 0/1)")
    return arrays["hard"].astype(bool), (arrays["soft"].astype(bool) if "soft" in arrays else None)


def matrix_between(folder: Path, first: str, second: str, n_first: int, n_second: int) -> np.ndarray:
    """The hard (first places, second places) matrix, from <first>-<second>.npz or, transposed,
    <second>-<first>.npz."""
    forward, backward = matrix_file(folder, first, second), matrix_file(folder, second, first)
    if forward.is_file():
        return read_matrix(forward, n_first, n_second)[0]
    if backward.is_file():
        return read_matrix(backward, n_second, n_first)[0].T
    raise FileNotFoundError(
        f"{forward}: ground-truth matrix not found (nor {backward.name}); the split maps every season "
        f"onto {first}'s places through it"
    )
