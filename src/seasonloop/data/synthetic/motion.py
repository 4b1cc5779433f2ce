"""How the train moves: a smooth speed profile, exactly zero at stops, integrated to position."""

from __future__ import annotations

import numpy as np

from ..layout import RouteLayout
from .difficulty import RouteDifficulty
from .noise import smoothstep


class Motion:
    """Speed and position on a fine time grid; `position(t)` is the same for every season."""

    TIME_STEP = 0.25  # s, resolution of the integrated position

    def __init__(self, layout: RouteLayout, seed: int, difficulty: RouteDifficulty):
        self.seconds = layout.seconds
        rng = np.random.default_rng([seed, 0x5EED])
        self.t_grid = np.arange(0.0, self.seconds + self.TIME_STEP / 2, self.TIME_STEP)
        t = self.t_grid
        speed = np.full_like(t, difficulty.cruise_speed)  # m/s, 21 by default (about 75 km/h)
        for amplitude, period in ((5.0, 700.0), (3.0, 260.0), (1.5, 90.0)):
            speed += amplitude * np.sin(2 * np.pi * t / (period * rng.uniform(0.8, 1.25)) + rng.uniform(0, 2 * np.pi))
        ramp = difficulty.brake_time  # s to brake or accelerate
        for start, end in layout.stops:
            # Standing on [start-1, end-1] makes pos(t) == pos(t-1) exactly for t in [start, end).
            arrive, leave = start - 1.0, end - 1.0
            factor = np.ones_like(t)
            factor = np.where(t < arrive, smoothstep((arrive - t) / ramp), factor)
            factor = np.where(t > leave, smoothstep((t - leave) / ramp), factor)
            factor[(t >= arrive) & (t <= leave)] = 0.0
            speed *= factor
        steps = (speed[1:] + speed[:-1]) * (self.TIME_STEP / 2)
        self.pos_grid = np.concatenate([[0.0], np.cumsum(steps)])
        self.speed_grid = speed
        self.length = float(self.pos_grid[-1])

    def position(self, t: float | np.ndarray) -> float | np.ndarray:
        """Train position along the route (m) at video time t (s); the same for every season."""
        return np.interp(t, self.t_grid, self.pos_grid)

    def speed(self, t: float) -> float:
        """Train speed (m/s) at video time t (s)."""
        return float(np.interp(t, self.t_grid, self.speed_grid))
