"""Ground truth of one season pair: which database places are correct for each query.

Three kinds (params data.ground_truth):
- aligned: place ids are frame indices shared by every season (Nordland's synchronised videos);
  database place j is correct for query i when |place_j - place_i| <= tolerance (frames);
- positions: every place has a position in metres; correct = within tolerance metres;
- matrix: a boolean (database, query) matrix given with the data (VPR_Tutorial's GThard), and
  optionally a soft one whose extra cells are neither right nor wrong (never picked as the match).

The exact match of a query is the database place nearest it (aligned: by place id; positions: by
position; matrix: the first correct place), -1 when it has none; the report shows it as "true match".
A query with no correct database place at all (its stretch of route is not in the database's test
set) stays a query: whatever it matches is wrong, and it is not a positive of the PR curve
(VPR_Tutorial's convention); PairTruth.n_without_match counts them.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from seasonloop.params.seasons import pair_name

# query rows whose (rows, M) distances to the database are held at once while a truth is built
TRUTH_ROWS_PER_BLOCK = 1024


@dataclass(frozen=True)
class PairTruth:
    """The ground truth of (database season, query season) on their test places."""

    kind: str
    database_places: np.ndarray  # (M,) the database season's place ids (its rows of frames)
    query_places: np.ndarray  # (N,)
    correct: np.ndarray  # (N, M) bool
    exact: np.ndarray  # (N,) column of the exact match, -1 for none
    ignored: np.ndarray | None = None  # (N, M) bool: soft-only cells, neither right nor wrong

    def __post_init__(self) -> None:
        shape = (len(self.query_places), len(self.database_places))
        if self.correct.shape != shape or self.correct.dtype != np.bool_:
            raise ValueError(f"ground truth: correct must be a {shape} boolean matrix, got {self.correct.shape}")
        if self.exact.shape != shape[:1]:
            raise ValueError(f"ground truth: exact must hold {shape[0]} columns, got {self.exact.shape}")
        if self.ignored is not None and self.ignored.shape != shape:
            raise ValueError(f"ground truth: ignored must be a {shape} matrix, got {self.ignored.shape}")

    def query_rows(self, rows: slice) -> PairTruth:
        """The truth of the queries `rows` only (a block of a pair evaluated in blocks)."""
        return PairTruth(
            self.kind,
            self.database_places,
            self.query_places[rows],
            self.correct[rows],
            self.exact[rows],
            None if self.ignored is None else self.ignored[rows],
        )

    @property
    def has_match(self) -> np.ndarray:
        """Bool (N,): the query has at least one correct database place."""
        return np.asarray(self.correct.any(axis=1))

    @property
    def n_without_match(self) -> int:
        return int((~self.has_match).sum())

    def save(self, path: Path) -> None:
        """One compressed .npz (bool matrices compress ~50x)."""
        arrays = {
            "kind": np.array(self.kind),
            "database_places": self.database_places,
            "query_places": self.query_places,
            "correct": self.correct,
            "exact": self.exact,
        }
        if self.ignored is not None:
            arrays["ignored"] = self.ignored
        with open(path, "wb") as stream:
            np.savez_compressed(stream, allow_pickle=False, **arrays)

    @classmethod
    def load(cls, path: Path) -> PairTruth:
        """Read what `save` wrote."""
        if not Path(path).is_file():
            raise FileNotFoundError(f"{path}: ground truth not found (rerun the ground_truth stage)")
        with np.load(path) as data:
            return cls(
                kind=str(data["kind"]),
                database_places=data["database_places"],
                query_places=data["query_places"],
                correct=data["correct"],
                exact=data["exact"],
                ignored=data["ignored"] if "ignored" in data.files else None,
            )


def _places(places: np.ndarray, name: str) -> np.ndarray:
    places = np.asarray(places)
    if places.ndim != 1 or not np.issubdtype(places.dtype, np.integer):
        raise ValueError(f"{name} must be a 1-D array of integer place ids, got {places.shape} {places.dtype}")
    return places.astype(np.int64)


def aligned_truth(database_places: np.ndarray, query_places: np.ndarray, tolerance: int) -> PairTruth:
    """Places are shared frame indices: correct within `tolerance` places of the query's own."""
    if isinstance(tolerance, bool) or not isinstance(tolerance, (int, np.integer)) or tolerance < 0:
        raise ValueError(f"tolerance must be a non-negative integer number of frames, got {tolerance!r}")
    database_places = _places(database_places, "database_places")
    query_places = _places(query_places, "query_places")

    def offsets(rows: slice) -> np.ndarray:
        return np.abs(database_places[None, :] - query_places[rows, None])

    correct, exact = _by_row_blocks(offsets, len(query_places), len(database_places), tolerance)
    return PairTruth("aligned", database_places, query_places, correct, exact)


def _by_row_blocks(
    distance: Callable[[slice], np.ndarray], n_queries: int, n_database: int, tolerance: float
) -> tuple[np.ndarray, np.ndarray]:
    """(correct = distance <= tolerance, exact) built TRUTH_ROWS_PER_BLOCK query rows at a time:
    only the (N, M) booleans are ever whole (27,592 x 27,592 int64 offsets would be 6 GB)."""
    correct = np.empty((n_queries, n_database), dtype=bool)
    exact = np.empty(n_queries, dtype=np.int64)
    for start in range(0, n_queries, TRUTH_ROWS_PER_BLOCK):
        rows = slice(start, min(start + TRUTH_ROWS_PER_BLOCK, n_queries))
        block = distance(rows)
        correct[rows] = block <= tolerance
        exact[rows] = _exact(block, correct[rows])
    return correct, exact


def _exact(distance: np.ndarray, correct: np.ndarray) -> np.ndarray:
    """The nearest database column per query, -1 where no column is correct."""
    if distance.shape[1] == 0:
        return np.full(distance.shape[0], -1, dtype=np.int64)
    nearest = np.argmin(distance, axis=1)
    return np.where(correct.any(axis=1), nearest, -1).astype(np.int64)


def position_truth(
    database_positions: np.ndarray,
    query_positions: np.ndarray,
    database_places: np.ndarray,
    query_places: np.ndarray,
    tolerance_m: float,
) -> PairTruth:
    """Correct = database places within tolerance_m metres of the query's position ((n, k) metres)."""
    if not np.isfinite(tolerance_m) or tolerance_m < 0:
        raise ValueError(f"evaluate.tolerance_m: must be a non-negative number of metres, got {tolerance_m!r}")
    database_positions = np.asarray(database_positions, dtype=np.float64)
    query_positions = np.asarray(query_positions, dtype=np.float64)
    if database_positions.ndim != 2 or query_positions.ndim != 2:
        raise ValueError("positions must be (n, k) arrays of metres")
    if database_positions.shape[1] != query_positions.shape[1]:
        raise ValueError(
            f"positions of the two seasons have {database_positions.shape[1]} and {query_positions.shape[1]} coordinates"
        )
    database_places = _places(database_places, "database_places")
    query_places = _places(query_places, "query_places")
    if len(database_positions) != len(database_places) or len(query_positions) != len(query_places):
        raise ValueError("positions: one position per place is needed")

    def metres(rows: slice) -> np.ndarray:
        return np.linalg.norm(query_positions[rows, None, :] - database_positions[None, :, :], axis=2)

    correct, exact = _by_row_blocks(metres, len(query_places), len(database_places), tolerance_m)
    return PairTruth("positions", database_places, query_places, correct, exact)


def matrix_truth(
    hard: np.ndarray, soft: np.ndarray | None, database_places: np.ndarray, query_places: np.ndarray, source: str
) -> PairTruth:
    """The test places' block of a (database places, query places) ground-truth matrix over all
    places of both seasons (VPR_Tutorial's layout); `source` names the file in errors."""
    database_places = _places(database_places, "database_places")
    query_places = _places(query_places, "query_places")
    correct = np.asarray(hard)[np.ix_(database_places, query_places)].T.astype(bool)
    ignored = None
    if soft is not None:
        if np.shape(soft) != np.shape(hard):
            raise ValueError(f"{source}: 'soft' has shape {np.shape(soft)}, 'hard' {np.shape(hard)}")
        ignored = np.asarray(soft)[np.ix_(database_places, query_places)].T.astype(bool) & ~correct
    first = np.where(correct.any(axis=1), correct.argmax(axis=1), -1).astype(np.int64)
    return PairTruth("matrix", database_places, query_places, correct, first, ignored)


def truth_file(folder: Path, database: str, query: str) -> Path:
    """Where the ground_truth stage writes the truth of (database, query) (PairTruth.save)."""
    return Path(folder) / f"{pair_name(database, query)}.npz"
