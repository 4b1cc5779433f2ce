"""The geographic split of traverses that are not frame-aligned (different lengths, speeds, starts).

Each frame of every season is mapped onto the first season's places (the reference): the reference
place nearest it in position if the reference's track passes within the evaluation's tolerance
(else none), or, with a ground-truth matrix, the middle of the reference places
that the matrix says show it (-1: none, and the frame is used for nothing). The sections, test
blocks and gaps are cut along the reference's places (seasonloop.data.split.split_masks), so they
are the same stretches of track in every season, and a frame takes the part of its reference place:
no season trains on a test stretch of any other. A reference place is a tunnel (a stop) when a frame
of any season mapped to it is dark (stands still); a frame is left out of the test set when it or
its reference place is.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, replace

import numpy as np

from seasonloop.data.datasets import every_kth
from seasonloop.data.split import Split, detect_stops, detect_tunnels, masks_to_split, split_masks
from seasonloop.params.settings import SplitConfig

# reference columns handled at once when mapping through a ground-truth matrix (bounds memory)
_MATRIX_COLUMNS_PER_BLOCK = 2048


@dataclass(frozen=True)
class SeasonSplits:
    """Every season's own Split, and the reference place of each of its frames."""

    reference: str
    splits: dict[str, Split]
    reference_place: dict[str, np.ndarray]

    def season(self, season: str) -> Split:
        """The split of one season."""
        return self.splits[season]

    def to_json(self) -> dict:
        """split.json: the reference season's parts at the top level (the aligned layout), and every
        season's own under "seasons"."""
        return {
            **self.splits[self.reference].to_json(),
            "reference": self.reference,
            "seasons": {
                season: {**split.to_json(), "reference_place": self.reference_place[season].tolist()}
                for season, split in self.splits.items()
            },
        }


def by_position(positions: Mapping[str, np.ndarray], reference: str, max_distance_m: float) -> dict[str, np.ndarray]:
    """season -> the reference place nearest each of its places ((n, k) metres each), -1 where the
    reference's track (the straight segments between its consecutive places) passes no closer than
    max_distance_m (the evaluation's tolerance: a frame that far lies on track the reference never
    drove, e.g. past its end). The track, not its places: a season sampled between the reference's
    places lies up to half their spacing from every place, and is still on the track."""
    from sklearn.neighbors import NearestNeighbors  # here: only traverses that are not aligned need it

    if not np.isfinite(max_distance_m) or max_distance_m < 0:
        raise ValueError(f"max_distance_m must be a non-negative number of metres, got {max_distance_m!r}")
    track = np.asarray(positions[reference], dtype=np.float64)
    index = NearestNeighbors(n_neighbors=1).fit(track)
    mapped = {}
    for season, own in positions.items():
        _, nearest = index.kneighbors(own)
        on_track = distance_to_track(track, np.asarray(own, dtype=np.float64), max_distance_m, index) <= max_distance_m
        mapped[season] = np.where(on_track, nearest[:, 0], -1).astype(np.int64)
    return mapped


def distance_to_track(track: np.ndarray, points: np.ndarray, within: float, index=None) -> np.ndarray:
    """Each point's distance to the polyline through `track`'s places in order ((n, k) metres),
    exact where it is at most `within` (beyond, a value above `within`, possibly not the least).
    `index`: a NearestNeighbors fitted on track, when the caller has one."""
    from sklearn.neighbors import NearestNeighbors

    if len(track) < 2:
        return np.linalg.norm(points - track[0], axis=1) if len(track) else np.full(len(points), np.inf)
    index = index if index is not None else NearestNeighbors().fit(track)
    # the closest point of a segment within `within` lies within half the segment's length of one
    # of its ends, so the segments ending at places within within + half the longest hold it
    half_longest = float(np.linalg.norm(np.diff(track, axis=0), axis=1).max()) / 2
    candidates = index.radius_neighbors(points, radius=within + half_longest, return_distance=False)
    owner = np.repeat(np.arange(len(points)), [len(places) for places in candidates])
    places = np.concatenate([*candidates, np.empty(0, dtype=np.int64)]).astype(np.int64)
    start = np.concatenate([places, places - 1])  # the segments leaving and reaching each place
    owner = np.concatenate([owner, owner])
    valid = (start >= 0) & (start < len(track) - 1)
    start, owner = start[valid], owner[valid]
    a, step, point = track[start], track[start + 1] - track[start], points[owner]
    squared = (step * step).sum(axis=1)
    along = np.divide(((point - a) * step).sum(axis=1), squared, out=np.zeros_like(squared), where=squared > 0)
    metres = np.linalg.norm(point - (a + np.clip(along, 0.0, 1.0)[:, None] * step), axis=1)
    distances = np.full(len(points), np.inf)
    np.minimum.at(distances, owner, metres)
    return distances


def by_matrix(truth: np.ndarray, name: str) -> np.ndarray:
    """The reference place of each frame of a season from a (reference places, season places)
    boolean matrix: the middle of its true rows, -1 where it has none."""
    if truth.ndim != 2:
        raise ValueError(f"{name}: the ground-truth matrix must be 2-D, got shape {truth.shape}")
    mapped = np.full(truth.shape[1], -1, dtype=np.int64)
    for start in range(0, truth.shape[1], _MATRIX_COLUMNS_PER_BLOCK):
        block = np.asarray(truth[:, start : start + _MATRIX_COLUMNS_PER_BLOCK], dtype=bool)
        counts = block.sum(axis=0)
        middle = np.argmax(np.cumsum(block, axis=0, dtype=np.int64) >= ((counts + 1) // 2)[None, :], axis=0)
        mapped[start : start + block.shape[1]] = np.where(counts > 0, middle, -1)
    return mapped


def _scatter(n_reference: int, reference_place: np.ndarray, flags: np.ndarray) -> np.ndarray:
    marked = np.zeros(n_reference, dtype=bool)
    marked[reference_place[flags & (reference_place >= 0)]] = True
    return marked


def split_seasons(
    stats: Mapping[str, np.ndarray],
    seasons: Sequence[str],
    config: SplitConfig,
    reference_place: Mapping[str, np.ndarray],
    fold: int = -1,
) -> SeasonSplits:
    """Every season's split of fold `fold` of split.folds (seasonloop.data.split.split_masks) from
    its frame statistics ("<season>_brightness", "<season>_change") and the reference place of each
    of its frames (by_position / by_matrix)."""
    reference = seasons[0]
    n_reference = len(stats[f"{reference}_brightness"])
    own_tunnel = {s: detect_tunnels({s: stats[f"{s}_brightness"]}, float(config.dark_threshold)) for s in seasons}
    own_stop = {s: detect_stops({s: stats[f"{s}_change"]}, float(config.stop_threshold)) for s in seasons}
    for season in seasons:
        if reference_place[season].shape != own_tunnel[season].shape:
            raise ValueError(
                f"{season}: {len(reference_place[season])} reference places for {len(own_tunnel[season])} frames"
            )
    tunnel = np.any([_scatter(n_reference, reference_place[s], own_tunnel[s]) for s in seasons], axis=0)
    stop = np.any([_scatter(n_reference, reference_place[s], own_stop[s]) for s in seasons], axis=0)
    test_block, gap, train = split_masks(
        n_reference, int(config.section_length), float(config.test_fraction), int(config.gap), int(config.folds), fold
    )
    # a whole route (test_fraction 1, the field's protocols) tests every frame, those without a
    # correct reference place too (as VPR-Bench's queries without a row: never a correct match);
    # otherwise such a frame has no place on the reference route's split and is left out
    whole_route = float(config.test_fraction) == 1
    splits = {}
    for season in seasons:
        place = reference_place[season]
        mapped = place >= 0
        unplaced = ~mapped if whole_route else np.zeros_like(mapped)
        at = np.where(mapped, place, 0)
        splits[season] = masks_to_split(
            (test_block[at] & mapped) | unplaced,
            gap[at] & mapped,
            (train[at] & mapped) | unplaced,
            own_tunnel[season] | (tunnel[at] & mapped),
            own_stop[season] | (stop[at] & mapped),
        )
        if season in config.test_every:
            splits[season] = replace(
                splits[season], test=every_kth(splits[season].test, config.test_every[season], season)
            )
    return SeasonSplits(reference, splits, {s: np.asarray(reference_place[s], np.int64) for s in seasons})
