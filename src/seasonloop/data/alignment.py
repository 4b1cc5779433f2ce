"""Is place i of one season place i of another? Measured, not assumed.

Every stage pairs place i of one season with place i of another. For a sample of places, the
patch-normalised (condition-robust) small grayscale frames of a season are compared with those of
the reference season shifted by -max_offset..max_offset places; the offset whose frames match best
is the measured offset. A season that is off by a whole number of places shows the same best
offset at most sampled places; a hard pair (winter against summer) scatters its per-place best
offsets, so it does not trip the check.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from seasonloop.data.patchnorm import patch_normalise
from seasonloop.data.preprocess import to_gray

PATCH_SIZE = 4
# an offset counts as clear when at least this share of sampled places has its best match within
# one place of it, and it is at least MIN_OFFSET places (one place either way is sampling jitter)
MIN_AGREEMENT = 0.5
MIN_OFFSET = 2
ALIGN_HEIGHT, ALIGN_WIDTH = 16, 32  # small gray frames suffice to see which places match


@dataclass(frozen=True)
class Alignment:
    offset: int  # places: season's place i + offset matches the reference's place i
    agreement: float  # share of sampled places whose own best offset is within 1 of it
    n_sampled: int

    @property
    def clear(self) -> bool:
        return abs(self.offset) >= MIN_OFFSET and self.agreement >= MIN_AGREEMENT

    def to_json(self) -> dict:
        return {
            "offset": self.offset,
            "agreement": round(self.agreement, 4),
            "n_sampled": self.n_sampled,
            "clear": self.clear,
        }


def measure_offset(reference: np.ndarray, season: np.ndarray, max_offset: int, n_samples: int = 200) -> Alignment:
    """The offset (see Alignment) of `season` against `reference`, both (N, H, W) gray images."""
    if reference.shape[1:] != season.shape[1:] or reference.ndim != 3:
        raise ValueError(
            f"alignment: expected two (N, H, W) arrays of one image size, got {reference.shape} and {season.shape}"
        )
    n = min(len(reference), len(season))
    if max_offset < 1 or n <= 2 * max_offset + 1:
        return Alignment(0, 1.0, 0)
    places = np.unique(
        np.linspace(max_offset, n - 1 - max_offset, min(n_samples, n - 2 * max_offset)).round().astype(int)
    )
    offsets = np.arange(-max_offset, max_offset + 1)

    def describe(images: np.ndarray) -> np.ndarray:
        flat = patch_normalise(images.astype(np.float32), PATCH_SIZE).reshape(len(images), -1)
        return flat / np.maximum(np.linalg.norm(flat, axis=1, keepdims=True), 1e-12)

    ref = describe(reference[places])
    # distance[place, offset]: 1 - cosine similarity of reference place p and season place p + offset
    distance = np.stack([1 - np.sum(ref * describe(season[places + d]), axis=1) for d in offsets], axis=1)
    best = offsets[int(np.argmin(np.median(distance, axis=0)))]
    per_place = offsets[np.argmin(distance, axis=1)]
    return Alignment(int(best), float(np.mean(np.abs(per_place - best) <= 1)), len(places))


def apply_offsets(counts: dict[str, int], offsets: dict[str, int]) -> dict[str, slice]:
    """season -> the slice of its places kept when `offsets[season]` leading places are dropped,
    every season cut to the same length."""
    for season, offset in offsets.items():
        if season in counts and not 0 <= offset < counts[season]:
            raise ValueError(f"data.offsets.{season}: {offset} is not in [0, {counts[season]})")
    length = min(counts[season] - offsets.get(season, 0) for season in counts)
    return {season: slice(offsets.get(season, 0), offsets.get(season, 0) + length) for season in counts}


def check_alignment(stored: dict[str, np.ndarray], max_offset: int) -> dict[str, dict]:
    """Each season's measured offset against the first season, from (N, h, w, 3) BGR frames:
    {"<first>-<season>": Alignment.to_json()}. A clear non-zero offset is a ValueError, one line
    naming the seasons, the offset and the data.offsets setting that would shift by it."""
    if max_offset == 0:
        return {}
    seasons = list(stored)
    reference = to_gray(stored[seasons[0]], ALIGN_HEIGHT, ALIGN_WIDTH)
    result = {}
    for season in seasons[1:]:
        alignment = measure_offset(reference, to_gray(stored[season], ALIGN_HEIGHT, ALIGN_WIDTH), max_offset)
        if alignment.clear:
            late, by = (season, alignment.offset) if alignment.offset > 0 else (seasons[0], -alignment.offset)
            raise ValueError(
                f"{season} vs {seasons[0]}: the frames match best at an offset of {alignment.offset} places "
                f"({alignment.agreement:.0%} of {alignment.n_sampled} sampled places agree); if that is real, set "
                f"data.offsets.{late}: {by} (drops {late}'s first {by} places), else check the frame folders"
            )
        result[f"{seasons[0]}-{season}"] = alignment.to_json()
    return result
