"""Is place i of one season place i of another? Measured, not assumed.

Every stage pairs place i of one season with place i of another. For a sample of places, the
patch-normalised (condition-robust) small grayscale frames of a season are compared with those of
the reference season shifted by -max_offset..max_offset places; the offset whose frames match best
is the measured offset. A season that is off by a whole number of places shows the same best
offset at most sampled places; a hard pair (winter against summer) scatters its per-place best
offsets, so it does not trip the check. Places where either season stands (a station stop: its
frame barely changes from the previous one, the split's stop test) match every offset inside the
stop about equally well; they are left out of the sample, and with fewer than MIN_SAMPLED moving
places there is no verdict (real Nordland: a 400-second stop that ends 50 seconds apart in summer
and winter otherwise reads as a clear offset of 10 places).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from seasonloop.data.patchnorm import patch_normalise
from seasonloop.data.preprocess import frame_statistics, to_gray

PATCH_SIZE = 4
# an offset counts as clear when at least this share of sampled places has its best match within
# one place of it, and it is at least MIN_OFFSET places (one place either way is sampling jitter)
MIN_AGREEMENT = 0.5
MIN_OFFSET = 2
# fewer moving places than this sampled: the share that agrees is too noisy to call an offset clear
MIN_SAMPLED = 20
ALIGN_HEIGHT, ALIGN_WIDTH = 16, 32  # small gray frames suffice to see which places match


@dataclass(frozen=True)
class Alignment:
    offset: int  # places: season's place i + offset matches the reference's place i
    agreement: float  # share of sampled places whose own best offset is within 1 of it
    n_sampled: int

    @property
    def clear(self) -> bool:
        return abs(self.offset) >= MIN_OFFSET and self.agreement >= MIN_AGREEMENT and self.n_sampled >= MIN_SAMPLED

    def to_json(self) -> dict:
        return {
            "offset": self.offset,
            "agreement": round(self.agreement, 4),
            "n_sampled": self.n_sampled,
            "clear": self.clear,
        }


def measure_offset(
    reference: np.ndarray, season: np.ndarray, max_offset: int, n_samples: int = 200, standing: np.ndarray | None = None
) -> Alignment:
    """The offset (see Alignment) of `season` against `reference`, both (N, H, W) gray images;
    `standing`: a bool per place, True where either season stands (left out of the sample)."""
    if reference.shape[1:] != season.shape[1:] or reference.ndim != 3:
        raise ValueError(
            f"alignment: expected two (N, H, W) arrays of one image size, got {reference.shape} and {season.shape}"
        )
    n = min(len(reference), len(season))
    if max_offset < 1 or n <= 2 * max_offset + 1:
        return Alignment(0, 1.0, 0)
    candidates = np.arange(max_offset, n - max_offset)
    if standing is not None:
        candidates = candidates[~np.asarray(standing, bool)[candidates]]
    if len(candidates) == 0:
        return Alignment(0, 0.0, 0)
    places = np.unique(
        candidates[np.linspace(0, len(candidates) - 1, min(n_samples, len(candidates))).round().astype(int)]
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


def check_alignment(stored: dict[str, np.ndarray], max_offset: int, stop_threshold: float) -> dict[str, dict]:
    """Each season's measured offset against the first season, from (N, h, w, 3) BGR frames:
    {"<first>-<season>": Alignment.to_json()}, places where either stands left out (a mean absolute
    change from the previous small gray frame below stop_threshold, split.stop_threshold). A clear
    non-zero offset is a ValueError, one line naming the seasons, the offset and the data.offsets
    setting that would shift by it."""
    if max_offset == 0:
        return {}
    seasons = list(stored)
    reference = to_gray(stored[seasons[0]], ALIGN_HEIGHT, ALIGN_WIDTH)
    reference_stands = frame_statistics(reference)[1] < stop_threshold
    result = {}
    for season in seasons[1:]:
        gray = to_gray(stored[season], ALIGN_HEIGHT, ALIGN_WIDTH)
        standing = reference_stands | (frame_statistics(gray)[1] < stop_threshold)
        alignment = measure_offset(reference, gray, max_offset, standing=standing)
        if alignment.clear:
            late, by = (season, alignment.offset) if alignment.offset > 0 else (seasons[0], -alignment.offset)
            raise ValueError(
                f"{season} vs {seasons[0]}: the frames match best at an offset of {alignment.offset} places "
                f"({alignment.agreement:.0%} of {alignment.n_sampled} sampled places agree); if that is real, set "
                f"data.offsets.{late}: {by} (drops {late}'s first {by} places), else check the frame folders"
            )
        result[f"{seasons[0]}-{season}"] = alignment.to_json()
    return result
