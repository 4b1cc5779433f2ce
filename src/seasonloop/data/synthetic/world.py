"""`SyntheticRoute`: one route's state (layout, motion, textures, zones, objects) and its frames.

Everything is generated from (seconds, seed, difficulty) when the route is built; a frame is
drawn on demand as codes (`compose`) and coloured per season (`look`).
"""

from __future__ import annotations

import numpy as np

from ...params.seasons import SEASONS
from .camera import View
from .compose import render_codes
from .difficulty import DEFAULT_DIFFICULTY, RouteDifficulty
from .layout import make_layout
from .look import SeasonLook
from .motion import Motion
from .objects import RouteObjects
from .textures import Textures
from .zones import Landscape


class SyntheticRoute:
    """A synthetic Nordland-style route: layout, speed profile and world, all from (seconds, seed).

    `frame(season, t, width, height)` renders the cab view at video time t (seconds).
    Memory is independent of image count: only small per-second/per-segment arrays are kept.
    `difficulty` sets speed, tunnels, stops and winter's light (default: the built-in route).
    """

    def __init__(self, seconds: int, seed: int, difficulty: RouteDifficulty = DEFAULT_DIFFICULTY):
        self.difficulty = difficulty
        self.layout = make_layout(seconds, seed, difficulty)
        self.seconds = self.layout.seconds
        self.seed = int(seed)
        self.motion = Motion(self.layout, self.seed, difficulty)
        self.length = self.motion.length
        # One generator for the world, drawn in a fixed order: textures, zones, then objects.
        rng = np.random.default_rng([self.seed, 0x3D])
        self.textures = Textures(rng)
        self.land = Landscape(rng, self.layout, self.motion)
        self.objects = RouteObjects(rng, self.land, self.length)
        self._views: dict[tuple[int, int], View] = {}
        self._looks: dict[tuple[int, int, int], SeasonLook] = {}
        self._cached_codes: tuple[tuple[float, int, int], np.ndarray] | None = None

    def position(self, t: float | np.ndarray) -> float | np.ndarray:
        """Train position along the route (m) at video time t (s); the same for every season."""
        return self.motion.position(t)

    def _view(self, width: int, height: int) -> View:
        key = (width, height)
        if key not in self._views:
            self._views[key] = View(width, height)
        return self._views[key]

    def _look(self, season: str, width: int, height: int) -> SeasonLook:
        key = (SEASONS.index(season), width, height)
        if key not in self._looks:
            self._looks[key] = SeasonLook(self.seed, season, self._view(width, height), self.difficulty)
        return self._looks[key]

    def frame(self, season: str, t: float, width: int, height: int) -> np.ndarray:
        """Cab view of `season` at video time t: (height, width, 3) uint8 BGR."""
        if season not in SEASONS:
            raise ValueError(f"unknown season {season!r}; expected one of {SEASONS}")
        if not 0.0 <= t <= self.seconds:
            raise ValueError(f"time t={t!r} is outside the route [0, {self.seconds}] s")
        if int(width) != width or int(height) != height or width < 16 or height < 16:
            raise ValueError(f"frame size must be integers >= 16, got width={width!r} height={height!r}")
        width, height = int(width), int(height)
        key = (float(t), width, height)
        if self._cached_codes is None or self._cached_codes[0] != key:
            # Geometry is shared by all seasons at the same time: render it once.
            p = float(self.position(float(t)))
            codes = render_codes(self._view(width, height), p, self.land, self.objects, self.textures)
            self._cached_codes = (key, codes)
        # The cab shakes with the track: hardly at all while the train stands still.
        shake = 0.1 + 0.9 * min(self.motion.speed(t) / 25.0, 1.0)
        return self._look(season, width, height).colourise(self._cached_codes[1], float(t), shake)


def render_frame(world: SyntheticRoute, season: str, t: float, width: int, height: int) -> np.ndarray:
    """Cab view of `world` in `season` at video time t: (height, width, 3) uint8 BGR."""
    if not isinstance(world, SyntheticRoute):
        raise ValueError(f"world must be a SyntheticRoute, got {type(world).__name__}")
    return world.frame(season, t, width, height)
