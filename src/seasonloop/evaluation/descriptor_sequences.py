"""The field's training-free sequence descriptors beside SeqSLAM: each frame's descriptor replaced by
one computed over a window of consecutive frames, then matched like a single image.

- delta: Delta descriptors (Garg, Harwood and Milford, "Delta Descriptors: Change-Based Place
  Representation for Robust Visual Localization", RA-L 2020), as oravus/seqNet's `Delta` module
  computes them: the mean of the window's second half minus the mean of its first half (for an
  even L, weights -1/(L/2) on its first L//2 frames and +1/(L/2) on the rest), L2-normalised;
- smoothed: the window's mean descriptor, L2-normalised (seqNet's `smooth` pooling).

The window is seqNet's (datasets.py getSeqInds), L frames centred on the frame (L//2 before it,
L - L//2 - 1 after it, as seqNet's evaluation reaches past the frame; this project's SeqSLAM
trails the query instead). Where it meets a break in the place ids (a test block's end, a tunnel
or stop left out: the end of a run of consecutive ids) `sequence.descriptor_window_at_breaks`
says what happens:
- shift (seqNet's rule, the default): the window is moved back inside the segment, L frames long
  (the whole segment where it is shorter, which seqNet never meets), and Delta takes seqNet's
  weights, -1/(L/2) on the first L//2 frames and +1/(L/2) on the rest (for an odd L they do not
  sum to 0, as in seqNet). The first L//2 + 1 frames of a segment then share one window and so one
  descriptor, of which only one can match the right place: on test blocks of a few dozen places
  about a third of the frames sit that close to a break.
- clip: the window is clipped at the segment's ends, so every frame has its own (the smoothing is
  then Garg et al.'s DeltaDescriptors, a zero-padded moving mean); Delta is the mean of the
  window's later half minus that of its first, which for an odd clipped window keeps the weights
  summing to 0.
"""

from __future__ import annotations

import numpy as np

from seasonloop.evaluation.sequence import segment_offsets
from seasonloop.params.choices import DESCRIPTOR_WINDOW_RULES

# descriptor columns summed at once: bounds the float64 cumulative sums at rows x 4,096 x 8 B
_COLUMNS_PER_BLOCK = 4096


def sequence_windows(places: np.ndarray, length: int, at_breaks: str) -> tuple[np.ndarray, np.ndarray]:
    """(first row, rows) of each row's window: `length` rows centred on it (length // 2 before),
    inside its segment of consecutive place ids as `at_breaks` says (shift or clip, module doc)."""
    if isinstance(length, bool) or not isinstance(length, (int, np.integer)) or length < 1:
        raise ValueError(f"sequence.length must be an integer >= 1, got {length!r}")
    if at_breaks not in DESCRIPTOR_WINDOW_RULES:
        raise ValueError(
            f"sequence.descriptor_window_at_breaks: expected one of {', '.join(DESCRIPTOR_WINDOW_RULES)}, "
            f"got {at_breaks!r}"
        )
    length = int(length)
    rows = np.arange(len(places))
    since_start, to_end = segment_offsets(np.asarray(places), len(places), "places")
    first, end = rows - since_start, rows + to_end + 1  # the segment's rows: [first, end)
    start, stop = np.maximum(rows - length // 2, first), np.minimum(rows + length - length // 2, end)
    if at_breaks == "shift":
        # getSeqInds: a window starting at the segment's first row runs L rows from it; else one
        # cut short at the segment's end is moved back to end there
        start = np.where(start == first, first, np.where(stop - start < length, np.maximum(end - length, first), start))
        stop = np.minimum(start + length, end)
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


def smoothed_descriptors(descriptors: np.ndarray, places: np.ndarray, length: int, at_breaks: str) -> np.ndarray:
    """Each row's window mean (sequence_windows), L2-normalised; float32 (n, d)."""
    start, size = sequence_windows(places, length, at_breaks)
    [total] = _window_sums(np.asarray(descriptors), (start, start + size))
    return _unit_rows(total / size[:, None])


def delta_descriptors(descriptors: np.ndarray, places: np.ndarray, length: int, at_breaks: str) -> np.ndarray:
    """Each row's Delta descriptor over its window of n rows (sequence_windows), L2-normalised;
    float32 (n, d): the mean of the last n - n//2 rows minus the mean of the first n//2, except
    under shift for a window of the full length L, where seqNet's weights (+-1/(L/2)) give the sum
    of the last rows minus the sum of the first (the same for an even L). A window shorter than L
    (clipped, or a segment shorter than L) keeps the halves' means, whose weights sum to 0; one of
    a single row has no change to measure (a zero descriptor, cosine distance 1 to all)."""
    start, size = sequence_windows(places, length, at_breaks)
    first = size // 2
    later, earlier = _window_sums(np.asarray(descriptors), (start + first, start + size), (start, start + first))
    change = np.where(
        (first > 0)[:, None], later / (size - first)[:, None] - earlier / np.maximum(first, 1)[:, None], 0.0
    )
    if at_breaks == "shift":
        # seqNet's weights +-1/(L/2) on a full window: the sums' difference, the factor 1/(L/2) left to the norm
        change = np.where((size == int(length))[:, None], later - earlier, change)
    return _unit_rows(change)
