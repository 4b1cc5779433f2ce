"""Descriptor distances between a database (season A) and queries (season B), and best matches."""

from __future__ import annotations

import numpy as np

METRICS = ("cosine", "euclidean")
CONFIDENCES = ("distance", "ratio")


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


def distance_matrix(
    database: np.ndarray, queries: np.ndarray, metric: str = "cosine", batch_size: int = 4096
) -> np.ndarray:
    """Distances between every query and every database descriptor.

    database is (M, D), queries is (N, D); returns (N, M) float32 with query rows and database
    columns. "cosine" is 1 - cosine similarity, in [0, 2]; a zero vector is treated as orthogonal to
    everything (distance 1, itself included) instead of producing NaN. "euclidean" uses the expanded
    form |q|^2 + |d|^2 - 2 q.d (one BLAS matmul), clipped at 0 before the square root. Arithmetic
    is float64 (the expanded form loses precision in float32); queries are processed in batches of
    batch_size rows so the float64 temporaries stay bounded.
    """
    database = _as_descriptors(database, "database")
    queries = _as_descriptors(queries, "queries")
    if metric not in METRICS:
        raise ValueError(f"unknown metric {metric!r}; expected one of {METRICS}")
    if database.shape[1] != queries.shape[1]:
        raise ValueError(
            f"descriptor dimensions differ: database has D={database.shape[1]}, "
            f"queries have D={queries.shape[1]}"
        )
    if int(batch_size) < 1:
        raise ValueError(f"batch_size must be >= 1, got {batch_size}")
    batch_size = int(batch_size)

    database = database.astype(np.float64)
    if metric == "cosine":
        database = _unit_rows(database)
    else:
        database_sq_norms = np.einsum("ij,ij->i", database, database)

    distances = np.empty((queries.shape[0], database.shape[0]), dtype=np.float32)
    for start in range(0, queries.shape[0], batch_size):
        batch = queries[start : start + batch_size].astype(np.float64)
        if metric == "cosine":
            similarity = _unit_rows(batch) @ database.T
            # Rounding can push similarity slightly outside [-1, 1].
            distances[start : start + batch.shape[0]] = np.clip(1.0 - similarity, 0.0, 2.0)
        else:
            squared = (
                np.einsum("ij,ij->i", batch, batch)[:, None]
                + database_sq_norms[None, :]
                - 2.0 * (batch @ database.T)
            )
            # Cancellation in the expanded form can give tiny negatives for identical vectors.
            distances[start : start + batch.shape[0]] = np.sqrt(np.maximum(squared, 0.0))
    return distances


def best_matches(distances: np.ndarray, confidence: str = "distance") -> tuple[np.ndarray, np.ndarray]:
    """Best database column per query row and a confidence for it (higher = more confident).

    confidence="distance": -(best distance).
    confidence="ratio": second-best distance / best distance (Lowry-style distinctiveness: a best
    match much closer than the runner-up is trusted more). Needs non-negative distances and at least
    two database columns. A best distance of 0 gives +inf when the second best is > 0 (perfectly
    distinctive) and 1.0 when both are 0 (not distinctive at all).
    Ties for the best distance resolve to the lowest column index (np.argmin).
    """
    distances = np.asarray(distances)
    if distances.ndim != 2 or distances.shape[0] == 0 or distances.shape[1] == 0:
        raise ValueError(f"distances must be a non-empty 2-D (N, M) array, got shape {distances.shape}")
    if np.isnan(distances).any():
        raise ValueError("distances contains NaN values")
    if confidence not in CONFIDENCES:
        raise ValueError(f"unknown confidence {confidence!r}; expected one of {CONFIDENCES}")

    best_columns = np.argmin(distances, axis=1)
    best_distances = np.take_along_axis(distances, best_columns[:, None], axis=1)[:, 0].astype(np.float64)
    if confidence == "distance":
        return best_columns, -best_distances

    if distances.shape[1] < 2:
        raise ValueError("confidence 'ratio' needs at least two database columns")
    if (distances < 0).any():
        raise ValueError("confidence 'ratio' needs non-negative distances")
    # After partitioning at index 1, column 1 holds the second-smallest distance of each row.
    second_distances = np.partition(distances, 1, axis=1)[:, 1].astype(np.float64)
    ratio = np.full(best_distances.shape, np.inf)
    positive = best_distances > 0
    ratio[positive] = second_distances[positive] / best_distances[positive]
    ratio[~positive & (second_distances == 0)] = 1.0
    return best_columns, ratio
