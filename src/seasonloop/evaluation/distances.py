"""Descriptor distances between a database (season A) and queries (season B), and best matches.

DISTANCES is the registry of distance metrics (evaluate.metric, evaluate.extra_metrics) and
CONFIDENCES that of match confidences (evaluate.confidence); distance_matrix and best_matches
validate their inputs and dispatch to them. params.yaml's choices are checked against their names
(seasonloop.registries): a new metric is one function plus one line here.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

# Query rows per block when finding the ratio's runner-up: bounds the (rows, M) temporaries.
_RATIO_ROWS_PER_BLOCK = 1024


def _as_descriptors(array: np.ndarray, name: str) -> np.ndarray:
    """Validate an (n, D) finite descriptor array with at least one row and column."""
    array = np.asarray(array)
    if array.ndim != 2:
        raise ValueError(f"{name} must be a 2-D (n, D) array, got shape {array.shape}")
    if array.shape[0] == 0 or array.shape[1] == 0:
        raise ValueError(f"{name} must have at least one row and one column, got shape {array.shape}")
    if not np.issubdtype(array.dtype, np.number) or np.issubdtype(array.dtype, np.complexfloating):
        raise ValueError(f"{name} must be a real numeric array, got dtype {array.dtype}")
    if not np.all(np.isfinite(array)):
        raise ValueError(f"{name} contains NaN or infinite values")
    return array


def _unit_rows(vectors: np.ndarray) -> np.ndarray:
    """Scale rows to unit L2 norm; zero rows stay zero (so their cosine similarity is 0, not NaN)."""
    norms = np.linalg.norm(vectors, axis=1, keepdims=True)
    return np.divide(vectors, norms, out=np.zeros_like(vectors), where=norms > 0)


# A metric prepares the float64 (M, D) database once and returns the function that gives the
# (rows, M) distances of a float64 batch of query rows. A new metric is one function + one line.
BatchDistances = Callable[[np.ndarray], np.ndarray]


def _cosine(database: np.ndarray) -> BatchDistances:
    database = _unit_rows(database)

    def distances(batch: np.ndarray) -> np.ndarray:
        similarity = _unit_rows(batch) @ database.T
        # Rounding can push similarity slightly outside [-1, 1].
        return np.clip(1.0 - similarity, 0.0, 2.0)

    return distances


def _euclidean(database: np.ndarray) -> BatchDistances:
    database_sq_norms = np.einsum("ij,ij->i", database, database)

    def distances(batch: np.ndarray) -> np.ndarray:
        squared = np.einsum("ij,ij->i", batch, batch)[:, None] + database_sq_norms[None, :] - 2.0 * (batch @ database.T)
        # Cancellation in the expanded form can give tiny negatives for identical vectors.
        return np.sqrt(np.maximum(squared, 0.0))

    return distances


def compute_threads() -> int:
    """Threads for the distance loops: OMP_NUM_THREADS where set (the tests set 1: two workers
    share two cores), else every CPU this process may run on."""
    import os

    given = os.environ.get("OMP_NUM_THREADS", "")
    return max(1, int(given)) if given.isdigit() else len(os.sched_getaffinity(0))


def _cityblock(database: np.ndarray) -> BatchDistances:
    # scipy's loop, not torch.cdist: the same sums on every CPU (no kernel picked per instruction
    # set), faster on 2 cores (3.0 s vs 4.4 s for 1,500 x 1,500 x 2,048 in float64, identical values)
    # and a 0.3 s import instead of torch's 1.5 s at every evaluate stage's start. cdist releases the
    # GIL, so threads over blocks of query rows run it on every core, each row's sums unchanged
    # (hog's 35,721-dimensional descriptors: 0.45 -> 0.23 s for 158 x 158 on 2 cores)
    from concurrent.futures import ThreadPoolExecutor

    from scipy.spatial.distance import cdist

    def distances(batch: np.ndarray) -> np.ndarray:
        threads = min(compute_threads(), len(batch))
        if threads == 1:
            return cdist(batch, database, metric="cityblock")
        bounds = np.linspace(0, len(batch), threads + 1).astype(int)
        with ThreadPoolExecutor(threads) as pool:
            parts = pool.map(
                lambda rows: cdist(batch[rows], database, metric="cityblock"),
                [slice(a, b) for a, b in zip(bounds[:-1], bounds[1:])],
            )
            return np.concatenate(list(parts))

    return distances


# In the order params.yaml's errors list them.
DISTANCES: dict[str, Callable[[np.ndarray], BatchDistances]] = {
    "cosine": _cosine,
    "euclidean": _euclidean,
    "cityblock": _cityblock,
}
METRICS = tuple(DISTANCES)


def distance_matrix(
    database: np.ndarray, queries: np.ndarray, metric: str = "cosine", batch_size: int = 4096
) -> np.ndarray:
    """Distances between every query and every database descriptor.

    database is (M, D), queries is (N, D); returns (N, M) float32 with query rows and database
    columns. "cosine" is 1 - cosine similarity, in [0, 2]; a zero vector is treated as orthogonal to
    everything (distance 1, itself included) instead of producing NaN. "euclidean" uses the expanded
    form |q|^2 + |d|^2 - 2 q.d (one BLAS matmul), clipped at 0 before the square root. "cityblock"
    is the L1 distance sum |q - d| (SeqSLAM's sum of absolute differences), by scipy's cdist (a
    direct summation in a plain loop: the same sums on every CPU; torch.cdist gave equal values).
    Cosine and Euclidean distances are unchanged by any rotation of the descriptor space; L1 is not.
    Arithmetic is float64 (the expanded form loses precision in float32); queries are processed in
    batches of batch_size rows so the float64 temporaries stay bounded.
    """
    database = _as_descriptors(database, "database")
    queries = _as_descriptors(queries, "queries")
    if metric not in DISTANCES:
        raise ValueError(f"unknown metric {metric!r}; expected one of {METRICS}")
    if database.shape[1] != queries.shape[1]:
        raise ValueError(
            f"descriptor dimensions differ: database has D={database.shape[1]}, queries have D={queries.shape[1]}"
        )
    if int(batch_size) < 1:
        raise ValueError(f"batch_size must be >= 1, got {batch_size}")
    batch_size = int(batch_size)

    batch_distances = DISTANCES[metric](database.astype(np.float64))
    distances = np.empty((queries.shape[0], database.shape[0]), dtype=np.float32)
    for start in range(0, queries.shape[0], batch_size):
        batch = queries[start : start + batch_size].astype(np.float64)
        distances[start : start + batch.shape[0]] = batch_distances(batch)
    return distances


def best_matches(
    distances: np.ndarray, confidence: str = "distance", database_places: np.ndarray | None = None, exclusion: int = 0
) -> tuple[np.ndarray, np.ndarray]:
    """Best database column per query row and a confidence for it (higher = more confident).

    confidence="distance": -(best distance).
    confidence="ratio": how much closer the best match is than the best database place outside an
    exclusion window around it (Lowry-style distinctiveness; OpenSeqSLAM excludes 10 places),
    as 1 - best / runner-up, in [0, 1]. It ranks queries exactly as runner-up / best does but stays
    finite when the best distance is 0: 1 when the runner-up is > 0 (or +inf, as sequence scores
    can be), 0 when it is 0 too (not distinctive at all). The runner-up is the smallest distance
    over database columns whose place id differs from the best column's by more than `exclusion`
    (database_places: the columns' place ids; default the column indices, so exclusion 0 takes
    the second-smallest distance at any other column). Needs non-negative distances and a database
    place outside the window.
    Ties for the best distance resolve to the lowest column index (np.argmin).
    """
    distances = np.asarray(distances)
    if distances.ndim != 2 or distances.shape[0] == 0 or distances.shape[1] == 0:
        raise ValueError(f"distances must be a non-empty 2-D (N, M) array, got shape {distances.shape}")
    if np.isnan(distances).any():
        raise ValueError("distances contains NaN values")
    if confidence not in CONFIDENCES:
        raise ValueError(f"unknown confidence {confidence!r}; expected one of {tuple(CONFIDENCES)}")
    best_columns = np.argmin(distances, axis=1)
    best_distances = np.take_along_axis(distances, best_columns[:, None], axis=1)[:, 0].astype(np.float64)
    return best_columns, CONFIDENCES[confidence](distances, best_columns, best_distances, database_places, exclusion)


def _distance_confidence(
    distances: np.ndarray,
    best_columns: np.ndarray,
    best_distances: np.ndarray,
    database_places: np.ndarray | None,
    exclusion: int,
) -> np.ndarray:
    return -best_distances


def _ratio_confidence(
    distances: np.ndarray,
    best_columns: np.ndarray,
    best_distances: np.ndarray,
    database_places: np.ndarray | None,
    exclusion: int,
) -> np.ndarray:
    if isinstance(exclusion, bool) or not isinstance(exclusion, (int, np.integer)) or exclusion < 0:
        raise ValueError(f"exclusion must be a non-negative integer number of places, got {exclusion!r}")
    places = np.arange(distances.shape[1]) if database_places is None else np.asarray(database_places)
    if places.shape != (distances.shape[1],) or not np.issubdtype(places.dtype, np.integer):
        raise ValueError(
            f"database_places must be {distances.shape[1]} integer place ids, got {places.shape} {places.dtype}"
        )
    if (distances < 0).any():
        raise ValueError("confidence 'ratio' needs non-negative distances")
    places = places.astype(np.int64)
    runner_up = np.empty(len(distances))
    has_outside = np.empty(len(distances), dtype=bool)
    for start in range(0, len(distances), _RATIO_ROWS_PER_BLOCK):
        rows = slice(start, start + _RATIO_ROWS_PER_BLOCK)
        near_best = np.abs(places[None, :] - places[best_columns[rows], None]) <= exclusion
        runner_up[rows] = np.where(near_best, np.inf, distances[rows]).min(axis=1)
        has_outside[rows] = ~near_best.all(axis=1)
    if not has_outside.all():
        raise ValueError(
            f"confidence 'ratio' needs a database place more than {exclusion} places from every best match"
        )
    ratio = np.zeros(len(distances))
    positive = (runner_up > 0) & np.isfinite(best_distances)
    ratio[positive] = 1.0 - best_distances[positive] / runner_up[positive]
    return ratio


# confidence -> (distances, best columns, best distances, database places, exclusion) -> one
# confidence per query, higher = more confident (see best_matches)
CONFIDENCES: dict[str, Callable[..., np.ndarray]] = {"distance": _distance_confidence, "ratio": _ratio_confidence}
