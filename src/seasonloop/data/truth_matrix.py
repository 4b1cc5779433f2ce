"""Ground-truth matrices given with a dataset: <folder>/<database>-<query>.npz holding 'hard' (and
optionally 'soft'), boolean (database places, query places) over the places extract_frames keeps
(rows of data/frames/<season>.npy), as VPR_Tutorial's GThard / GTsoft."""

from __future__ import annotations

import zipfile
from pathlib import Path

import numpy as np

# what np.load raises on a file that is not a readable .npy/.npz, opening it or reading an array
UNREADABLE = (OSError, ValueError, EOFError, zipfile.BadZipFile)


def matrix_file(folder: Path, database: str, query: str) -> Path:
    return Path(folder) / f"{database}-{query}.npz"


def read_matrix(path: Path, n_database: int, n_query: int) -> tuple[np.ndarray, np.ndarray | None]:
    """(hard, soft or None) of one file, checked: its shape must be (n_database, n_query) and its
    values 0/1 or boolean; anything else is one line naming the file."""
    if not Path(path).is_file():
        raise FileNotFoundError(f"{path}: ground-truth matrix not found (data.ground_truth_dir)")
    try:
        loaded = np.load(path, allow_pickle=False)
    except UNREADABLE as error:
        raise ValueError(f"{path}: cannot read the ground-truth matrix ({error})") from None
    if not isinstance(loaded, np.lib.npyio.NpzFile):
        raise ValueError(f"{path}: not an .npz archive (a single array saved with np.save?); save 'hard' with np.savez")
    try:
        with loaded as data:
            arrays = {key: data[key] for key in ("hard", "soft") if key in data.files}
    except UNREADABLE as error:
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


def pair_matrix(
    folder: Path, first: str, second: str, n_first: int, n_second: int, needed_for: str
) -> tuple[np.ndarray, np.ndarray | None, Path]:
    """(hard, soft or None, the file read) as (first places, second places) matrices, from
    <first>-<second>.npz or, transposed, <second>-<first>.npz: one file per pair of seasons, in
    either order. needed_for says in the error what the matrix is for."""
    forward, backward = matrix_file(folder, first, second), matrix_file(folder, second, first)
    if forward.is_file():
        return (*read_matrix(forward, n_first, n_second), forward)
    if backward.is_file():
        hard, soft = read_matrix(backward, n_second, n_first)
        return hard.T, (None if soft is None else soft.T), backward
    raise FileNotFoundError(f"{forward}: ground-truth matrix not found (nor {backward.name}); {needed_for}")


def matrix_between(folder: Path, first: str, second: str, n_first: int, n_second: int) -> np.ndarray:
    """The hard (first places, second places) matrix (pair_matrix)."""
    needed_for = f"the split maps every season onto {first}'s places through it"
    return pair_matrix(folder, first, second, n_first, n_second, needed_for)[0]
