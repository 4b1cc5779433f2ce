"""The field's training-free sequence descriptors beside SeqSLAM: each frame's descriptor replaced by
one computed over a window of consecutive frames, then matched like a single image.

- delta: Delta descriptors (Garg, Harwood and Milford, "Delta Descriptors: Change-Based Place
  Representation for Robust Visual Localization", RA-L 2020), as oravus/seqNet's `Delta` module
  computes them: the mean of the window's second half minus the mean of its first half (for an
  even L, weights -1/(L/2) on its first L//2 frames and +1/(L/2) on the rest), L2-normalised;
- smoothed: the window's mean descriptor, L2-normalised (seqNet's `smooth` pooling).

The window is seqNet's (datasets.py getSeqInds), L frames centred on the frame (L//2 before it),
but clipped at a break in the test sections (the end of a run of consecutive place ids), as
SeqSLAM's trajectories are: seqNet shifts a window that meets a sequence's bound back inside it,
which on test sections of a few dozen places gives the first and last frames of every section one
and the same window (and so one descriptor, of which only one frame can be the right match); a
clipped window is shorter there and every frame's is its own. Unlike this project's SeqSLAM,
whose trajectories trail the query (online), the window reaches L - L//2 - 1 frames past the
frame, as seqNet's evaluation does.
"""

from __future__ import annotations

import numpy as np

from seasonloop.evaluation.sequence import segment_offsets

# descriptor columns summed at once: bounds the float64 cumulative sums at rows x 4,096 x 8 B
_COLUMNS_PER_BLOCK = 4096


def sequence_windows(places: np.ndarray, length: int) -> tuple[np.ndarray, np.ndarray]:
    """(first row, rows) of each row's window: `length` rows centred on it (length // 2 before),
    clipped to its segment of consecutive place ids."""
    if isinstance(length, bool) or not isinstance(length, (int, np.integer)) or length < 1:
        raise ValueError(f"sequence.length must be an integer >= 1, got {length!r}")
    rows = np.arange(len(places))
    since_start, to_end = segment_offsets(np.asarray(places), len(places), "places")
    start = np.maximum(rows - int(length) // 2, rows - since_start)
    stop = np.minimum(rows + int(length) - int(length) // 2, rows + to_end + 1)
    return start, stop - start


def _window_sums(descriptors: np.ndarray, *windows: tuple[np.ndarray, np.ndarray]) -> list[np.ndarray]:
    """Each row's sum of descriptors[start:stop] (float64) for each (start, stop) of `windows`, from
    one cumulative sum a block of columns at a time."""
    sums = [np.empty((len(start), descriptors.shape[1])) for start, _ in windows]
    for column in range(0, descriptors.shape[1], _COLUMNS_PER_BLOCK):
        block = descriptors[:, column : column + _COLUMNS_PER_BLOCK].astype(np.float64)
        cumulative = np.zeros((len(block) + 1, block.shape[1]))
        np.cumsum(block, axis=0, out=cumulative[1:])
        for total, (start, stop) in zip(sums, windows):
            total[:, column : column + _COLUMNS_PER_BLOCK] = cumulative[stop] - cumulative[start]
    return sums


def _unit_rows(vectors: np.ndarray) -> np.ndarray:
    norms = np.linalg.norm(vectors, axis=1, keepdims=True)
    return np.divide(vectors, norms, out=np.zeros_like(vectors), where=norms > 0).astype(np.float32)


def smoothed_descriptors(descriptors: np.ndarray, places: np.ndarray, length: int) -> np.ndarray:
    """Each row's window mean (sequence_windows), L2-normalised; float32 (n, d)."""
    start, size = sequence_windows(places, length)
    [total] = _window_sums(np.asarray(descriptors), (start, start + size))
    return _unit_rows(total / size[:, None])


def delta_descriptors(descriptors: np.ndarray, places: np.ndarray, length: int) -> np.ndarray:
    """Each row's Delta descriptor over its window of n rows (sequence_windows): the mean of its
    last n - n//2 rows minus the mean of its first n//2, L2-normalised; float32 (n, d). For an even
    n these are seqNet's weights (+-1/(n/2)); for an odd n (a window clipped at a break) seqNet's
    would not sum to 0 and would add a share of the window's mean, so the halves' means are taken.
    A window of one row has no change to measure: a zero descriptor (cosine distance 1 to all)."""
    start, size = sequence_windows(places, length)
    first = size // 2
    later, earlier = _window_sums(np.asarray(descriptors), (start + first, start + size), (start, start + first))
    change = later / (size - first)[:, None] - earlier / np.maximum(first, 1)[:, None]
    return _unit_rows(np.where((first > 0)[:, None], change, 0.0))
