"""`SyntheticRoute`: one route's state (layout, motion, textures, zones, objects) and its frames.

Everything is generated from (seconds, seed, difficulty) when the route is built; a frame is
drawn on demand as codes (`compose`) and coloured per season (`look`).
"""

from __future__ import annotations

from collections import OrderedDict

import numpy as np

from ...params.seasons import SEASONS
from .camera import View
from .compose import render_codes
from .difficulty import DEFAULT_DIFFICULTY, RouteDifficulty
from .layout import make_layout
from .look import SeasonLook
from .motion import Motion
from .objects import RouteObjects
from .ride import RideTimeline, SeasonRide
from .textures import Textures
from .zones import Landscape


class SyntheticRoute:
    """A synthetic Nordland-style route: layout, speed profile and world, all from (seconds, seed).

    `frame(season, t, width, height)` renders the cab view at video time t (seconds);
    `ride_frame(season, ride, tau, width, height)` at a season's own time tau along its `SeasonRide`.
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
        # Geometry by (position, width, height): seasons at the same place share one drawing.
        self._codes: OrderedDict[tuple[float, int, int], np.ndarray] = OrderedDict()
        self._timelines: dict[tuple[str, SeasonRide], RideTimeline] = {}

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

    def _check(self, season: str, width: int, height: int) -> tuple[int, int]:
        """The frame size as ints, after checking the season and the size."""
        if season not in SEASONS:
            raise ValueError(f"unknown season {season!r}; expected one of {SEASONS}")
        if int(width) != width or int(height) != height or width < 16 or height < 16:
            raise ValueError(f"frame size must be integers >= 16, got width={width!r} height={height!r}")
        return int(width), int(height)

    _CODES_KEPT = 8  # places kept: one per season riding its own pace, and then some

    def _geometry(self, p: float, width: int, height: int) -> np.ndarray:
        """Codes of the view from route position p (m), drawn once per place and size."""
        key = (p, width, height)
        if key in self._codes:
            self._codes.move_to_end(key)
        else:
            self._codes[key] = render_codes(self._view(width, height), p, self.land, self.objects, self.textures)
            if len(self._codes) > self._CODES_KEPT:
                self._codes.popitem(last=False)
        return self._codes[key]

    def _colour(self, season: str, codes: np.ndarray, t: float, speed: float, width: int, height: int) -> np.ndarray:
        """`season`'s look of `codes` at its own video time t, riding at `speed` (m/s)."""
        # The cab shakes with the track: hardly at all while the train stands still.
        shake = 0.1 + 0.9 * min(speed / 25.0, 1.0)
        return self._look(season, width, height).colourise(codes, t, shake)

    def frame(self, season: str, t: float, width: int, height: int) -> np.ndarray:
        """Cab view of `season` at video time t of the reference ride: (height, width, 3) uint8 BGR."""
        width, height = self._check(season, width, height)
        if not 0.0 <= t <= self.seconds:
            raise ValueError(f"time t={t!r} is outside the route [0, {self.seconds}] s")
        codes = self._geometry(float(self.position(float(t))), width, height)
        return self._colour(season, codes, float(t), self.motion.speed(t), width, height)

    def timeline(self, season: str, ride: SeasonRide) -> RideTimeline:
        """`season`'s clock when it rides `ride` (tau -> reference time), built once."""
        key = (season, ride)
        if key not in self._timelines:
            self._timelines[key] = RideTimeline(ride, self.layout, self.seed, season)
        return self._timelines[key]

    def ride_position(self, season: str, ride: SeasonRide, tau: float | np.ndarray) -> float | np.ndarray:
        """Position along the route (m) of `season` riding `ride` at its own video time tau (s)."""
        return self.motion.position(self.timeline(season, ride).reference_time(tau))

    def ride_frame(self, season: str, ride: SeasonRide, tau: float, width: int, height: int) -> np.ndarray:
        """Cab view of `season` riding `ride` at its own video time tau: (height, width, 3) uint8 BGR.

        The place is the reference's at g(tau); the shake follows the season's own speed and the
        slow light changes its own time. `SeasonRide()` gives `frame(season, tau, ...)`."""
        width, height = self._check(season, width, height)
        clock = self.timeline(season, ride)
        g = float(clock.reference_time(float(tau)))
        codes = self._geometry(float(self.motion.position(g)), width, height)
        speed = self.motion.speed(g) * clock.rate(float(tau))
        return self._colour(season, codes, float(tau), speed, width, height)


def render_frame(world: SyntheticRoute, season: str, t: float, width: int, height: int) -> np.ndarray:
    """Cab view of `world` in `season` at video time t: (height, width, 3) uint8 BGR."""
    if not isinstance(world, SyntheticRoute):
        raise ValueError(f"world must be a SyntheticRoute, got {type(world).__name__}")
    return world.frame(season, t, width, height)
