"""Ground-truth matrices given with a dataset: <folder>/<database>-<query>.npz holding 'hard' (and
optionally 'soft'), boolean (database places, query places) over the places extract_frames keeps
(rows of data/frames/<season>.npy), as VPR_Tutorial's GThard / GTsoft; or VPR-Bench's
<folder>/ground_truth_new.npy (rows [query index, array of correct reference indices]) for its two
traverses, the reference (database) and the queries."""

from __future__ import annotations

import zipfile
from pathlib import Path

import numpy as np

# what np.load raises on a file that is not a readable .npy/.npz, opening it or reading an array
UNREADABLE = (OSError, ValueError, EOFError, zipfile.BadZipFile)


VPR_BENCH_FILE = "ground_truth_new.npy"


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


def read_vpr_bench(path: Path, n_reference: int, n_query: int) -> np.ndarray:
    """VPR-Bench's ground truth (an object array of rows [query index, array of correct reference
    indices], indices into each folder's images in order) as the hard (reference places, query
    places) matrix; a query without a row, or whose row lists no reference, has no correct place.
    Anything else is one line naming the file and row. The format is a pickled object array: read only files you trust."""
    if not Path(path).is_file():
        raise FileNotFoundError(f"{path}: VPR-Bench ground truth not found (ground_truth_new.npy in data.frames_dir)")
    try:
        rows = np.load(path, allow_pickle=True)
    except (*UNREADABLE, ImportError) as error:  # a pickle naming a missing module: ImportError
        raise ValueError(f"{path}: cannot read the VPR-Bench ground truth ({error})") from None
    if rows.ndim != 2 or rows.shape[1] != 2:
        raise ValueError(f"{path}: expected rows of [query index, reference indices], got shape {rows.shape}")
    hard = np.zeros((n_reference, n_query), dtype=bool)
    seen = np.zeros(n_query, dtype=bool)
    for row, (query, references) in enumerate(rows):
        references = np.atleast_1d(np.asarray(references))
        if not (np.issubdtype(np.asarray(query).dtype, np.integer) and 0 <= query < n_query):
            raise ValueError(f"{path}: row {row}: query index {query!r} is not one of the {n_query} query places")
        if references.size and not np.issubdtype(references.dtype, np.integer):
            raise ValueError(f"{path}: row {row}: reference indices {references.tolist()} are not integers")
        if references.size and (references.min() < 0 or references.max() >= n_reference):
            raise ValueError(
                f"{path}: row {row}: reference indices {references.tolist()} beyond the {n_reference} reference places"
            )
        if seen[query]:
            raise ValueError(f"{path}: query {query} on two rows")
        seen[query] = True
        if references.size:  # an empty list (read as float64): the query has no correct place
            hard[references, query] = True
    return hard


def pair_matrix(
    folder: Path,
    first: str,
    second: str,
    n_first: int,
    n_second: int,
    needed_for: str,
    vpr_bench: tuple[str, str] | None = None,
) -> tuple[np.ndarray, np.ndarray | None, Path]:
    """(hard, soft or None, the file read) as (first places, second places) matrices, from
    <first>-<second>.npz or, transposed, <second>-<first>.npz: one file per pair of seasons, in
    either order; with vpr_bench = (reference, query) traverses, from VPR-Bench's file instead.
    needed_for says in the error what the matrix is for."""
    if vpr_bench is not None:
        path = Path(folder) / VPR_BENCH_FILE
        if (first, second) == vpr_bench:
            return read_vpr_bench(path, n_first, n_second), None, path
        if (second, first) == vpr_bench:
            return read_vpr_bench(path, n_second, n_first).T, None, path
        raise ValueError(f"{path}: holds the pair {'-'.join(vpr_bench)} only, not {first}-{second}")
    forward, backward = matrix_file(folder, first, second), matrix_file(folder, second, first)
    if forward.is_file():
        return (*read_matrix(forward, n_first, n_second), forward)
    if backward.is_file():
        hard, soft = read_matrix(backward, n_second, n_first)
        return hard.T, (None if soft is None else soft.T), backward
    raise FileNotFoundError(f"{forward}: ground-truth matrix not found (nor {backward.name}); {needed_for}")


def matrix_between(
    folder: Path, first: str, second: str, n_first: int, n_second: int, vpr_bench: tuple[str, str] | None = None
) -> np.ndarray:
    """The hard (first places, second places) matrix (pair_matrix)."""
    needed_for = f"the split maps every season onto {first}'s places through it"
    return pair_matrix(folder, first, second, n_first, n_second, needed_for, vpr_bench)[0]
