"""Geographic train/test split with gaps, and removal of tunnels and station stops from the test set.

Places are frame indices along the route. The route is cut into contiguous sections; the last
`test_fraction` of each section is a test block, and `gap` places on either side of every test
block are used for nothing, so no training image shows a test place or its immediate neighbours.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class Split:
    n_places: int
    train: np.ndarray          # place ids used for training
    test: np.ndarray           # place ids evaluated (tunnels and stops removed)
    gap: np.ndarray            # place ids in the gaps around test blocks
    dropped_tunnel: np.ndarray  # test-block places left out as tunnel (dark) frames
    dropped_stop: np.ndarray   # test-block places left out as station stops (not already tunnels)

    def to_json(self) -> dict:
        return {
            "n_places": self.n_places,
            **{name: getattr(self, name).tolist() for name in ("train", "test", "gap", "dropped_tunnel", "dropped_stop")},
        }


def section_blocks(n_places: int, section_length: int, test_fraction: float) -> list[tuple[int, int]]:
    """[start, end) of the test block at the end of each section."""
    if section_length < 2:
        raise ValueError(f"split.section_length: must be at least 2, got {section_length}")
    if not 0 < test_fraction < 1:
        raise ValueError(f"split.test_fraction: must be in (0, 1), got {test_fraction}")
    n_sections = max(1, round(n_places / section_length))
    bounds = np.linspace(0, n_places, n_sections + 1).round().astype(int)
    blocks = []
    for start, end in zip(bounds[:-1], bounds[1:]):
        size = max(1, round((end - start) * test_fraction))
        blocks.append((end - size, end))
    return blocks


def detect_tunnels(brightness: Mapping[str, np.ndarray], dark_threshold: float) -> np.ndarray:
    """A place is a tunnel when its raw frame is dark in any season."""
    return np.any([values < dark_threshold for values in brightness.values()], axis=0)


def detect_stops(change: Mapping[str, np.ndarray], stop_threshold: float) -> np.ndarray:
    """A place is a stop when its frame barely differs from the previous one in any season.

    Consecutive near-identical frames make the 'same place' ambiguous within the stop, which is
    why the study leaves them out of the test sets.
    """
    return np.any([values < stop_threshold for values in change.values()], axis=0)


def make_split(
    n_places: int,
    section_length: int,
    test_fraction: float,
    gap: int,
    tunnel: np.ndarray,
    stop: np.ndarray,
) -> Split:
    if gap < 0:
        raise ValueError(f"split.gap: must be >= 0, got {gap}")
    if tunnel.shape != (n_places,) or stop.shape != (n_places,):
        raise ValueError(f"tunnel/stop masks must have shape ({n_places},)")
    in_test_block = np.zeros(n_places, bool)
    near_test = np.zeros(n_places, bool)
    for start, end in section_blocks(n_places, section_length, test_fraction):
        in_test_block[start:end] = True
        near_test[max(0, start - gap) : min(n_places, end + gap)] = True
    gap_mask = near_test & ~in_test_block
    train_mask = ~near_test
    if not train_mask.any():
        raise ValueError(
            f"split: no training places left ({n_places} places, section_length {section_length}, gap {gap})"
        )
    places = np.arange(n_places)
    dropped_tunnel = in_test_block & tunnel
    dropped_stop = in_test_block & stop & ~tunnel
    test_mask = in_test_block & ~tunnel & ~stop
    if not test_mask.any():
        raise ValueError("split: every test place is a tunnel or a stop; check split.dark_threshold / split.stop_threshold")
    return Split(
        n_places=n_places,
        train=places[train_mask],
        test=places[test_mask],
        gap=places[gap_mask],
        dropped_tunnel=places[dropped_tunnel],
        dropped_stop=places[dropped_stop],
    )
