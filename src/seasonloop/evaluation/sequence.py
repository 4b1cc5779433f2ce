"""SeqSLAM sequence matching (Milford & Wyeth 2012) on a query x database distance matrix.

Local contrast enhancement of the distance matrix (enhance_distance_contrast), then for every
(query, database) cell the mean enhanced difference along straight trailing trajectories of several
velocities; the best velocity gives the score.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator

import numpy as np

from seasonloop.params.choices import MIN_SEQUENCE_WINDOW, WINDOW_RULES
from seasonloop.params.settings import SequenceConfig

# Rows processed at once by enhance_distance_contrast: bounds its float64 temporaries (~6 x rows x M x 8 B).
_ENHANCE_ROWS_PER_BLOCK = 256


def _as_distance_matrix(distances: np.ndarray) -> np.ndarray:
    distances = np.asarray(distances)
    if distances.ndim != 2 or distances.shape[0] == 0 or distances.shape[1] == 0:
        raise ValueError(f"distances must be a non-empty 2-D (N, M) array, got shape {distances.shape}")
    if not np.all(np.isfinite(distances)):
        raise ValueError("distances contains NaN or infinite values")
    return distances


def enhancement_windows(
    n_database: int, window: int, database_places: np.ndarray | None, rule: str
) -> tuple[np.ndarray, np.ndarray]:
    """(first column, one past the last) of each database column's contrast-enhancement window
    under `rule` (WINDOW_RULES)."""
    if rule not in WINDOW_RULES:
        raise ValueError(f"sequence.window_at_breaks: expected one of {', '.join(WINDOW_RULES)}, got {rule!r}")
    half = int(window) // 2
    columns = np.arange(n_database)
    since_start, to_end = segment_offsets(None if rule == "ignore" else database_places, n_database, "database_places")
    first, last = columns - since_start, columns + to_end
    if rule == "shift":
        size = np.minimum(2 * half + 1, last - first + 1)
        start = np.clip(columns - half, first, last + 1 - size)
        return start, start + size
    return np.maximum(columns - half, first), np.minimum(columns + half, last) + 1


def enhance_distance_contrast(
    distances: np.ndarray, window: int = 10, database_places: np.ndarray | None = None, window_at_breaks: str = "clip"
) -> np.ndarray:
    """SeqSLAM local contrast enhancement of an (N queries, M database) distance matrix.

    Each entry (i, j) becomes (d[i, j] - mean) / std, with mean and (population) std of row i over
    the database columns of j's window: j - window//2 .. j + window//2, clipped at the matrix
    edges (as OpenSeqSLAM does) and meeting breaks in database_places (segment_offsets; None: no
    break) as `window_at_breaks` says (WINDOW_RULES). The window holds only database columns of
    the same query row: whichever the rule, nothing of the ground truth or of another query enters.
    Windows with zero spread give 0. As in OpenSeqSLAM the result is then shifted so its
    minimum is 0, which keeps it a non-negative distance (a uniform shift changes no ranking).
    Window sums come from cumulative sums; returns float32.
    """
    distances = _as_distance_matrix(distances)
    window_start, window_stop = _windows(distances.shape[1], window, database_places, window_at_breaks)
    enhanced = enhance_rows(distances, window_start, window_stop)
    enhanced -= enhanced.min()
    return enhanced


def _windows(
    n_database: int, window: int, database_places: np.ndarray | None, rule: str
) -> tuple[np.ndarray, np.ndarray]:
    if isinstance(window, bool) or not isinstance(window, (int, np.integer)) or window < MIN_SEQUENCE_WINDOW:
        raise ValueError(f"window must be an integer >= {MIN_SEQUENCE_WINDOW} (database columns), got {window!r}")
    return enhancement_windows(n_database, window, database_places, rule)


def enhance_rows(distances: np.ndarray, window_start: np.ndarray, window_stop: np.ndarray) -> np.ndarray:
    """enhance_distance_contrast's rows before the shift to a minimum of 0 (each row on its own)."""
    n_queries, n_database = distances.shape
    window_size = window_stop - window_start
    enhanced = np.empty((n_queries, n_database), dtype=np.float32)
    for start in range(0, n_queries, _ENHANCE_ROWS_PER_BLOCK):
        block = distances[start : start + _ENHANCE_ROWS_PER_BLOCK].astype(np.float64)
        # Centring each row first keeps the cumulative sums of squares from losing precision.
        block -= block.mean(axis=1, keepdims=True)
        sums = np.zeros((block.shape[0], n_database + 1))
        np.cumsum(block, axis=1, out=sums[:, 1:])
        squares = np.zeros_like(sums)
        np.cumsum(block * block, axis=1, out=squares[:, 1:])
        local_mean = (sums[:, window_stop] - sums[:, window_start]) / window_size
        local_var = (squares[:, window_stop] - squares[:, window_start]) / window_size - local_mean**2
        local_std = np.sqrt(np.maximum(local_var, 0.0))
        # Treat spreads at rounding-noise level as zero (constant windows).
        scale = 1.0 + np.abs(block).max(axis=1, keepdims=True)
        enhanced[start : start + block.shape[0]] = np.divide(
            block - local_mean, local_std, out=np.zeros_like(block), where=local_std > 1e-9 * scale
        )
    return enhanced


def segment_offsets(places: np.ndarray | None, n: int, name: str) -> tuple[np.ndarray, np.ndarray]:
    """(rows since the segment start, rows to the segment end) per row, where a segment is a run of
    consecutive place ids (each one more than the last); None: the n rows are one segment.

    A break (a new test block, or places dropped as tunnel or station stop) ends a segment: a
    sequence must not pretend the route runs straight across it.
    """
    if places is None:
        rows = np.arange(n)
        return rows, n - 1 - rows
    places = np.asarray(places)
    if places.shape != (n,) or not np.issubdtype(places.dtype, np.integer):
        raise ValueError(f"{name} must be {n} integer place ids, got shape {places.shape}, dtype {places.dtype}")
    starts_segment = np.ones(n, dtype=bool)
    starts_segment[1:] = np.diff(places.astype(np.int64)) != 1
    segment = np.cumsum(starts_segment) - 1
    first_row = np.flatnonzero(starts_segment)
    last_row = np.append(first_row[1:] - 1, n - 1)
    rows = np.arange(n)
    return rows - first_row[segment], last_row[segment] - rows


def _check_trajectories(length: int, v_min: float, v_max: float, v_steps: int) -> None:
    if isinstance(length, bool) or not isinstance(length, (int, np.integer)) or length < 1:
        raise ValueError(f"length must be an integer >= 1, got {length!r}")
    if isinstance(v_steps, bool) or not isinstance(v_steps, (int, np.integer)) or v_steps < 1:
        raise ValueError(f"v_steps must be an integer >= 1, got {v_steps!r}")
    if not (np.isfinite(v_min) and np.isfinite(v_max)) or v_min > v_max:
        raise ValueError(f"need finite v_min <= v_max, got v_min={v_min!r}, v_max={v_max!r}")


def _add_trajectory_step(
    total: np.ndarray,
    enhanced: np.ndarray,
    first_target: int,
    step: int,
    shift: int,
    target_since_start: np.ndarray,
    database_since_start: np.ndarray,
    database_to_end: np.ndarray,
) -> None:
    """Add step `step` (database shift `shift`) of every trajectory to `total`, in place.

    Target t (row first_target + t of `enhanced`), column j reads enhanced row first_target + t -
    step, column j - shift, for the targets whose segment reaches back `step` rows; targets whose
    source column lies outside their database segment ran out of data and are disqualified (+inf)
    for this velocity.
    """
    n_database = enhanced.shape[1]
    rows = np.flatnonzero(target_since_start >= step)
    if rows.size == 0:
        return
    if abs(shift) >= n_database:
        total[rows] = np.inf
        return
    block = total[rows]
    sources = rows + first_target - step
    if shift >= 0:
        block[:, shift:] += enhanced[sources, : n_database - shift]
        outside = database_since_start < shift
    else:
        block[:, : n_database + shift] += enhanced[sources, -shift:]
        outside = database_to_end < -shift
    block[:, outside] = np.inf
    total[rows] = block


def trajectory_scores(
    enhanced: np.ndarray,
    first_target: int,
    target_since_start: np.ndarray,
    database_places: np.ndarray | None,
    n_steps: int,
    velocities: np.ndarray,
) -> np.ndarray:
    """Sequence scores (n targets, M) of the rows first_target.. of `enhanced` (the rows before
    them: the trajectories' history); target_since_start: each target's rows since its segment's
    start; n_steps: the trajectories' points, min(length, the pair's queries)."""
    n_targets, n_database = len(target_since_start), enhanced.shape[1]
    database_since_start, database_to_end = segment_offsets(database_places, n_database, "database_places")
    best = np.full((n_targets, n_database), np.inf, dtype=np.float32)
    total = np.empty_like(best)
    steps = np.arange(n_steps)
    # Points before the query's segment start are left out: query i averages min(offset + 1, length).
    points = np.minimum(target_since_start + 1, steps.size).astype(np.float32)[:, None]
    for velocity in velocities:
        shifts = np.floor(velocity * steps + 0.5).astype(np.int64)
        total.fill(0.0)
        for step, shift in zip(steps, shifts):
            _add_trajectory_step(
                total,
                enhanced,
                first_target,
                int(step),
                int(shift),
                target_since_start,
                database_since_start,
                database_to_end,
            )
        total /= points
        np.minimum(best, total, out=best)
    return best


def sequence_distances(
    distances: np.ndarray,
    length: int = 10,
    v_min: float = 0.8,
    v_max: float = 1.2,
    v_steps: int = 5,
    window: int = 10,
    query_places: np.ndarray | None = None,
    database_places: np.ndarray | None = None,
    window_at_breaks: str = "clip",
) -> np.ndarray:
    """SeqSLAM sequence scores as an (N, M) distance (lower = better), float32.

    For query i and database j: the minimum over velocities v in linspace(v_min, v_max, v_steps)
    of the mean contrast-enhanced difference along the trailing, online-causal trajectory
    (i - k, j - round(v * k)), k = 0..length-1 (round half up). A trajectory never crosses a
    break in place ids (query_places, database_places: the rows' and columns' place ids; None
    means no break): points before the start of the query's segment (a run of consecutive place
    ids) are left out of the mean, so the first queries of the test set and of every segment use
    shorter sequences. A trajectory whose database index leaves its database segment (or the
    matrix) is disqualified (infinite score for that velocity), as OpenSeqSLAM does at the matrix
    edge: averaging over only the points left would let the shorter, noisier sequences at the first
    database columns win by chance. window and window_at_breaks: enhance_distance_contrast's. Each (v, k) adds one shifted copy of the enhanced matrix (no
    loop over cells).
    Cells with no complete trajectory at any velocity are +inf (e.g. the first database columns
    of a segment for queries deep into theirs); ValueError when a whole query row has none.
    """
    distances = _as_distance_matrix(distances)
    _check_trajectories(length, v_min, v_max, v_steps)
    enhanced = enhance_distance_contrast(distances, window, database_places, window_at_breaks)
    query_since_start, _ = segment_offsets(query_places, len(distances), "query_places")
    velocities = np.linspace(v_min, v_max, int(v_steps))
    best = trajectory_scores(
        enhanced, 0, query_since_start, database_places, min(int(length), len(distances)), velocities
    )
    _check_complete(best, length, v_min, v_max)
    return best


def _check_complete(best: np.ndarray, length: int, v_min: float, v_max: float) -> None:
    if not np.isfinite(best).any(axis=1).all():
        raise ValueError(
            f"database of {best.shape[1]} columns is too short for sequences of length {length} "
            f"at velocities {v_min}..{v_max}: some queries have no complete trajectory"
        )


def sequence_distance_blocks(
    distance_rows: Callable[[slice], np.ndarray],
    n_queries: int,
    n_database: int,
    rows_per_block: int,
    sequence: SequenceConfig,
    query_places: np.ndarray | None,
    database_places: np.ndarray | None,
) -> Iterator[tuple[slice, np.ndarray]]:
    """sequence_distances' rows a block of `rows_per_block` query rows at a time: (rows, their
    scores), the same numbers in bounded memory. distance_rows(rows) gives the distances of query
    rows `rows`; a block also reads the length - 1 rows before it (its trajectories' history),
    and every row but the first block's twice: the enhanced matrix's minimum (OpenSeqSLAM shifts it
    to 0) is the whole pair's."""
    length, v_min, v_max = int(sequence.length), float(sequence.v_min), float(sequence.v_max)
    _check_trajectories(length, v_min, v_max, int(sequence.v_steps))
    blocks = [slice(start, min(start + rows_per_block, n_queries)) for start in range(0, n_queries, rows_per_block)]
    window_start, window_stop = _windows(n_database, int(sequence.window), database_places, sequence.window_at_breaks)

    def enhanced(rows: slice) -> np.ndarray:
        return enhance_rows(_as_distance_matrix(distance_rows(rows)), window_start, window_stop)

    # the first block has no history before it: the second pass reuses the first's enhanced rows
    first_block = {0: enhanced(blocks[0])}
    lowest = min([float(first_block[0].min()), *(float(enhanced(rows).min()) for rows in blocks[1:])])
    query_since_start, _ = segment_offsets(query_places, n_queries, "query_places")
    velocities = np.linspace(v_min, v_max, int(sequence.v_steps))
    for rows in blocks:
        first = max(0, rows.start - (length - 1))
        history = first_block.pop(rows.start) if rows.start in first_block else enhanced(slice(first, rows.stop))
        history -= np.float32(lowest)
        best = trajectory_scores(
            history, rows.start - first, query_since_start[rows], database_places, min(length, n_queries), velocities
        )
        _check_complete(best, length, v_min, v_max)
        yield rows, best
