"""The route's difficulty knobs (`RouteDifficulty`): train speed, tunnels and stops, winter's light.

The defaults are the built-in route as pinned by tests/test_synthetic_pinned.py; params.yaml's
`synthetic.*` keys of the same names override them (stages/acquire.py).
"""

from __future__ import annotations

from dataclasses import dataclass, fields


@dataclass(frozen=True)
class RouteDifficulty:
    """What makes the route easy or hard to recognise; every field has today's value as default."""

    cruise_speed: float = 21.0  # m/s (about 75 km/h) around which the speed varies
    brake_time: float = 16.0  # s to brake into a stop or accelerate out of it
    tunnel_every_s: float = 600.0  # mean seconds of video per tunnel
    tunnel_min_s: int = 10  # shortest tunnel, s
    tunnel_max_s: int = 40  # longest tunnel, s
    stop_every_s: float = 900.0  # mean seconds of video per station stop
    stop_min_s: int = 20  # shortest stop, s
    stop_max_s: int = 60  # longest stop, s
    event_gap_s: int = 40  # s between events: room to brake, accelerate and change scenery
    edge_margin_s: int = 30  # no tunnel or stop in the first or last seconds
    winter_contrast: float = 0.5  # winter's contrast around its bright pivot (1: as summer)
    winter_shading: float = 0.4  # share of directional shading left in winter's flat light

    def __post_init__(self) -> None:
        for field in fields(self):
            value = getattr(self, field.name)
            # ints stay ints: the layout's seconds are integers
            wanted = int if field.type == "int" else (int, float)
            if isinstance(value, bool) or not isinstance(value, wanted):
                kind = "an integer" if wanted is int else "a number"
                raise ValueError(f"{field.name}: expected {kind}, got {value!r}")
            if field.type == "float":
                object.__setattr__(self, field.name, float(value))
        positive = (
            "cruise_speed",
            "brake_time",
            "tunnel_every_s",
            "stop_every_s",
            "tunnel_min_s",
            "stop_min_s",
            "winter_contrast",
        )
        for name in positive:
            if not getattr(self, name) > 0:
                raise ValueError(f"{name}: expected a positive number, got {getattr(self, name)!r}")
        for name in ("event_gap_s", "edge_margin_s", "winter_shading"):
            if getattr(self, name) < 0:
                raise ValueError(f"{name}: expected a number >= 0, got {getattr(self, name)!r}")
        for kind in ("tunnel", "stop"):
            low, high = getattr(self, f"{kind}_min_s"), getattr(self, f"{kind}_max_s")
            if high < low:
                raise ValueError(f"{kind}_max_s: {high} is below {kind}_min_s {low}")

    @classmethod
    def knobs(cls) -> tuple[str, ...]:
        """The knobs' names: also their keys in params.yaml's `synthetic` section."""
        return tuple(field.name for field in fields(cls))


DEFAULT_DIFFICULTY = RouteDifficulty()
