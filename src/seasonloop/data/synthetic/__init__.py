"""Deterministic, procedurally rendered train ride: the default stand-in for the Nordland videos.

A route is generated from ``(seconds, seed)``: a speed profile with station stops and tunnels
(`RouteLayout`), and a world along the track made of scenery zones (forest, meadow, farmland,
lakes, villages, rock cuts, moorland), bridges, houses, single trees, telegraph poles, stations,
hills and a mountain skyline. A frame is a forward-facing cab view at route position ``pos(t)``,
which is the same for every season, so frame ``k`` of every season shows the same place; unless
a season rides at its own pace (`SeasonRide`: speed, time at stops, start), when its frame at its
own time tau shows the reference's place at g(tau). Every video's frame positions are written.

Rendering happens in two steps. The geometry of a frame is drawn once into a buffer of
*codes* (material x shade level); each season then only looks the codes up in its own palette
(season colours, light and contrast baked in), adds its own clouds, camera offset and jitter,
slow light changes and sensor noise. This keeps four seasons of a place geometrically identical
while their appearance differs the way Nordland's seasons do, and it is fast.

Where things are (one concern per module):

    difficulty   RouteDifficulty: the knobs (speed, tunnels, stops, winter's light)
    layout       make_layout: when the tunnels and stops happen (RouteLayout: seasonloop.data.layout)
    motion       speed profile and position along the route
    ride         SeasonRide, RideTimeline: a season's own pace, its time -> the reference's
    noise        hashes and value noise
    textures     the seeded texture tables and their lookup
    zones        scenery zones per side, stations, tunnels, bridges (Landscape)
    objects      houses and single trees
    camera       View, projection, near clipping, cv2 drawing of codes
    palette      materials, shade codes, season palettes
    scenery/     ground, skyline, trees, rock cuts, tunnels, structures (one drawing concern each)
    compose      one frame's codes in painter's order
    look         SeasonLook: a season's colours, clouds, shake, light and noise
    world        SyntheticRoute: a route's state and its frames
    video        render_route, render_preview
"""

from ...params.seasons import SEASONS
from ..layout import RouteLayout
from .difficulty import RouteDifficulty
from .layout import make_layout
from .ride import RideTimeline, SeasonRide
from .video import render_preview, render_route
from .world import SyntheticRoute, render_frame

__all__ = [
    "SEASONS",
    "RouteDifficulty",
    "RideTimeline",
    "RouteLayout",
    "SeasonRide",
    "SyntheticRoute",
    "make_layout",
    "render_frame",
    "render_preview",
    "render_route",
]
