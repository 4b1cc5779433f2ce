"""A season's own ride along the route (`SeasonRide`) and its clock (`RideTimeline`).

The reference ride is the route's `Motion`: at video time t the train is at `motion.position(t)`.
A season may ride the same track at its own pace: its video time tau maps to the reference's time
g(tau), and the season's position at tau is exactly `motion.position(g(tau))`.

    g(0) = start_s
    dg/dtau = speed * (1 + swing * sin(2 pi tau / P + phase))   outside the reference's stops
    dg/dtau = 1 / stop_scale                                     inside a stop span [start, end)

P and phase are drawn per (route seed, season). Between stop boundaries g has a closed form, so
the mapping is exact, not integrated step by step. `SeasonRide()` is the reference: g(tau) = tau.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass, fields

import numpy as np

from ...params.choices import RIDE_SCHEMA
from ...params.seasons import SEASONS
from ..layout import RouteLayout

MIN_ROUTE_LEFT_S = 10.0  # a season starting later than this before the end would have no ride


@dataclass(frozen=True)
class SeasonRide:
    """How one season rides the route: pace (`speed`, with a slow `swing`), time spent standing at
    stops (`stop_scale`) and where on the route it starts (`start_s`, reference seconds)."""

    # each field's range is declared once, in synthetic.rides' check (RIDE_SCHEMA), and used here
    speed: float = 1.0  # times the reference's speed
    stop_scale: float = 1.0  # times the reference's time standing at a stop
    start_s: float = 0.0  # starts this many reference seconds along the route (at most seconds - 10)
    swing: float = 0.0  # relative swing of the speed over a few minutes; below 1 the speed stays
    # positive: the season never stands outside a stop nor runs backwards

    def __post_init__(self) -> None:
        for field in fields(self):
            value = getattr(self, field.name)
            if isinstance(value, bool) or not isinstance(value, (int, float, np.integer, np.floating)):
                raise ValueError(f"{field.name}: expected a number, got {value!r}")
            if not math.isfinite(float(value)):
                raise ValueError(f"{field.name}: expected a finite number, got {value!r}")
            RIDE_SCHEMA[field.name](field.name, value)
            object.__setattr__(self, field.name, float(value))

    @property
    def is_reference(self) -> bool:
        """True for the reference ride (all defaults): g(tau) = tau."""
        return self == SeasonRide()

    def to_json(self) -> dict:
        """Plain-JSON form: the four fields."""
        return asdict(self)


class RideTimeline:
    """The map from a season's video time tau to the reference's time g(tau) along a route.

    Built from piecewise segments between stop boundaries: a stop segment runs at 1/stop_scale,
    a moving one at the swinging speed, integrated in closed form.
    """

    def __init__(self, ride: SeasonRide, layout: RouteLayout, seed: int, season: str):
        if season not in SEASONS:
            raise ValueError(f"unknown season {season!r}; expected one of {SEASONS}")
        if ride.start_s > layout.seconds - MIN_ROUTE_LEFT_S:
            raise ValueError(
                f"start_s: {ride.start_s:g} leaves less than {MIN_ROUTE_LEFT_S:g} s of the {layout.seconds} s route"
            )
        self.ride, self.layout = ride, layout
        self.identity = ride.is_reference  # g(tau) = tau exactly, not through the segments' arithmetic
        rng = np.random.default_rng([int(seed), SEASONS.index(season), 0x41DE])
        self.period = float(rng.uniform(120.0, 300.0))  # s of the season's video
        self.phase = float(rng.uniform(0.0, 2 * np.pi))
        self._build_segments()

    def _antiderivative(self, tau: float | np.ndarray) -> float | np.ndarray:
        """G(tau) with dG/dtau = speed * (1 + swing sin(2 pi tau / P + phase)): moving segments."""
        ride, omega = self.ride, 2 * np.pi / self.period
        return ride.speed * (tau - ride.swing / omega * np.cos(omega * tau + self.phase))

    def _moving_end(self, tau0: float, dg: float) -> float:
        """The tau at which a moving segment starting at tau0 has covered dg reference seconds."""
        ride = self.ride
        if ride.swing == 0.0:
            return tau0 + dg / ride.speed
        # G is strictly increasing (swing < 1): bisect between the fastest and slowest bounds
        target = float(self._antiderivative(tau0)) + dg
        low, high = tau0 + dg / (ride.speed * (1 + ride.swing)), tau0 + dg / (ride.speed * (1 - ride.swing))
        for _ in range(200):
            mid = 0.5 * (low + high)
            if mid in (low, high):
                break
            if self._antiderivative(mid) < target:
                low = mid
            else:
                high = mid
        return 0.5 * (low + high)

    def _build_segments(self) -> None:
        """Cut [start_s, seconds] of reference time at the stop boundaries and time each piece."""
        g, end = self.ride.start_s, float(self.layout.seconds)
        pieces: list[tuple[float, float, bool]] = []  # (g0, g1, stopped)
        for stop_start, stop_end in self.layout.stops:
            a, b = min(float(stop_start), end), min(float(stop_end), end)
            if b <= g:
                continue
            if a > g:
                pieces.append((g, a, False))
            if b > max(a, g):
                pieces.append((max(a, g), b, True))
            g = b
        if g < end:
            pieces.append((g, end, False))
        tau = 0.0
        tau0, g0, stopped = [], [], []
        for piece_start, piece_end, standing in pieces:
            tau0.append(tau)
            g0.append(piece_start)
            stopped.append(standing)
            span = piece_end - piece_start
            tau = tau + span * self.ride.stop_scale if standing else self._moving_end(tau, span)
        self.seg_tau0, self.seg_g0 = np.array(tau0), np.array(g0)
        self.seg_stopped = np.array(stopped, dtype=bool)
        # the season's video ends where its ride reaches the end of the route
        self.duration = float(self.layout.seconds) if self.identity else float(tau)

    def _segment(self, tau: np.ndarray) -> np.ndarray:
        """Index of the segment holding each tau, after checking tau is within the ride."""
        if np.any(tau < 0.0) or np.any(tau > self.duration):
            raise ValueError(f"time tau={tau!r} is outside the season's ride [0, {self.duration:g}] s")
        return np.maximum(np.searchsorted(self.seg_tau0, tau, side="right") - 1, 0)

    def reference_time(self, tau: float | np.ndarray) -> float | np.ndarray:
        """g(tau): the reference ride's time (s) at which it is where this season is at its time tau."""
        scalar = np.ndim(tau) == 0
        tau = np.asarray(tau, dtype=np.float64)
        i = self._segment(tau)
        if self.identity:
            g = tau
        else:
            t0, g0 = self.seg_tau0[i], self.seg_g0[i]
            moving = g0 + self._antiderivative(tau) - self._antiderivative(t0)
            g = np.where(self.seg_stopped[i], g0 + (tau - t0) / self.ride.stop_scale, moving)
            g = np.minimum(g, float(self.layout.seconds))  # the last bisection's rounding
        return float(g) if scalar else g

    def rate(self, tau: float) -> float:
        """dg/dtau at the season's time tau: reference seconds per season second."""
        i = int(self._segment(np.asarray(float(tau))))
        if self.seg_stopped[i]:
            return 1.0 / self.ride.stop_scale
        ride = self.ride
        return ride.speed * (1.0 + ride.swing * math.sin(2 * math.pi * tau / self.period + self.phase))

    def n_frames(self, fps: int) -> int:
        """Frames of the season's video at `fps`: times k/fps before the end of its ride."""
        return math.ceil(self.duration * fps - 1e-9)

    def season_time(self, g: float) -> float:
        """Inverse of `reference_time`: the season's first time at which the reference time is g
        (g before start_s: 0, after the end of the route: the ride's duration)."""
        if g <= self.ride.start_s:
            return 0.0
        if g >= self.layout.seconds:
            return self.duration
        if self.identity:
            return float(g)
        i = int(np.searchsorted(self.seg_g0, g, side="right")) - 1
        t0, g0 = float(self.seg_tau0[i]), float(self.seg_g0[i])
        if self.seg_stopped[i]:
            return t0 + (g - g0) * self.ride.stop_scale
        return self._moving_end(t0, g - g0)

    def spans(self, spans: tuple[tuple[int, int], ...]) -> list[list[float]]:
        """Half-open spans of reference seconds as [start, end) in the season's video seconds,
        rounded to 1 ms; spans the ride never reaches are left out."""
        out = []
        for a, b in spans:
            start, end = self.season_time(float(a)), self.season_time(float(b))
            if end > start:
                out.append([round(start, 3), round(end, 3)])
        return out

    def to_json(self, fps: int) -> dict:
        """This season's ride for rides.json: the ride, its length and its stops and tunnels in its
        own video seconds."""
        return {
            "ride": self.ride.to_json(),
            "seconds": round(self.duration, 3),
            "frames": self.n_frames(fps),
            "stops": self.spans(self.layout.stops),
            "tunnels": self.spans(self.layout.tunnels),
        }
