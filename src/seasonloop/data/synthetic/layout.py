"""When the train is in a tunnel or at a station: `make_layout` places the events in video time."""

from __future__ import annotations

import numpy as np

from ..layout import RouteLayout
from .difficulty import DEFAULT_DIFFICULTY, RouteDifficulty

_AT_LEAST_ONE_S = 600  # a route this long has at least one tunnel and one stop


def make_layout(seconds: int, seed: int, difficulty: RouteDifficulty = DEFAULT_DIFFICULTY) -> RouteLayout:
    """Place tunnels and stops from the seed (by default ~1 tunnel per 600 s, 10-40 s long, and
    ~1 stop per 900 s, 20-60 s long; see `RouteDifficulty`).

    Events never overlap, keep `event_gap_s` between each other and stay `edge_margin_s` away from
    both ends; a route of 600 s or more has at least one of each.
    """
    if int(seconds) != seconds or seconds < 1:
        raise ValueError(f"seconds must be a positive integer, got {seconds!r}")
    if int(seed) != seed or seed < 0:
        raise ValueError(f"seed must be a non-negative integer, got {seed!r}")
    seconds = int(seconds)
    d = difficulty
    rng = np.random.default_rng([int(seed), 0x1A7])
    n_tunnels = int(rng.poisson(seconds / d.tunnel_every_s))
    n_stops = int(rng.poisson(seconds / d.stop_every_s))
    if seconds >= _AT_LEAST_ONE_S:
        n_tunnels, n_stops = max(n_tunnels, 1), max(n_stops, 1)
    events = [("tunnel", int(n)) for n in rng.integers(d.tunnel_min_s, d.tunnel_max_s + 1, n_tunnels)]
    events += [("stop", int(n)) for n in rng.integers(d.stop_min_s, d.stop_max_s + 1, n_stops)]
    events = [events[i] for i in rng.permutation(len(events))]
    usable = seconds - 2 * d.edge_margin_s

    def needed() -> int:
        return sum(n for _, n in events) + d.event_gap_s * max(len(events) - 1, 0)

    # Short routes cannot hold every drawn event: drop from the more numerous kind.
    while events and needed() > usable:
        kinds = [kind for kind, _ in events]
        drop = "tunnel" if kinds.count("tunnel") >= kinds.count("stop") else "stop"
        del events[len(kinds) - 1 - kinds[::-1].index(drop)]
    slack = usable - needed()
    spare = np.floor(rng.dirichlet(np.ones(len(events) + 1)) * slack).astype(int)
    tunnels: list[tuple[int, int]] = []
    stops: list[tuple[int, int]] = []
    cursor = d.edge_margin_s
    for (kind, length), extra in zip(events, spare):
        start = cursor + int(extra)
        (tunnels if kind == "tunnel" else stops).append((start, start + length))
        cursor = start + length + d.event_gap_s
    return RouteLayout(seconds=seconds, tunnels=tuple(tunnels), stops=tuple(stops))
