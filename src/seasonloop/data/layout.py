"""A route's true layout: where in video time the train is in a tunnel or stands at a station.

The built-in renderer writes it (data/acquired/layout.json) and the split stage reads it to score
its image-based detection; it lives outside the renderer so that reading it imports nothing else.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class RouteLayout:
    """Where in video time the train is in a tunnel or stands at a station."""

    seconds: int
    tunnels: tuple[tuple[int, int], ...]  # half-open [start, end) seconds of video time
    stops: tuple[tuple[int, int], ...]  # half-open [start, end) seconds standing still

    def to_json(self) -> dict:
        """Plain-JSON form (lists), inverse of `from_json`."""
        return {
            "seconds": self.seconds,
            "tunnels": [list(span) for span in self.tunnels],
            "stops": [list(span) for span in self.stops],
        }

    @classmethod
    def from_json(cls, data: dict) -> RouteLayout:
        """Rebuild a layout written by `to_json`; missing keys raise ValueError."""
        for key in ("seconds", "tunnels", "stops"):
            if key not in data:
                raise ValueError(f"route layout JSON lacks key {key!r}")
        return cls(
            seconds=int(data["seconds"]),
            tunnels=tuple((int(a), int(b)) for a, b in data["tunnels"]),
            stops=tuple((int(a), int(b)) for a, b in data["stops"]),
        )

    def _flags(self, spans: tuple[tuple[int, int], ...]) -> np.ndarray:
        flags = np.zeros(self.seconds, dtype=bool)
        for start, end in spans:
            flags[start:end] = True
        return flags

    def in_tunnel(self) -> np.ndarray:
        """Bool (seconds,): True for seconds inside a tunnel."""
        return self._flags(self.tunnels)

    def stopped(self) -> np.ndarray:
        """Bool (seconds,): True for seconds at which the train stands where it stood at t-1."""
        return self._flags(self.stops)
