"""One frame's geometry as codes: sky, ground, skyline, rails, then trees, rock and objects
in painter's order; or the inside of a tunnel."""

from __future__ import annotations

from collections.abc import Callable
from functools import partial

import numpy as np

from .camera import View
from .objects import RouteObjects
from .scenery.ground import draw_ground, draw_rails
from .scenery.rock import ROCK_LATERAL, draw_rock
from .scenery.skyline import draw_skyline
from .scenery.structures import draw_house, draw_platform, draw_poles, draw_truss
from .scenery.trees import TREE_LAYERS, draw_single_tree, draw_trees
from .scenery.tunnels import draw_portal, tunnel_codes
from .textures import Textures
from .zones import PORTAL_APPROACH, Landscape

OBJECT_RANGE = 600.0  # m ahead within which discrete objects are drawn


def render_codes(view: View, p: float, land: Landscape, placed: RouteObjects, textures: Textures) -> np.ndarray:
    """Codes (height, width) uint16 of the view from route position p (m)."""
    i = int(np.searchsorted(land.tunnel_a, p, side="right")) - 1
    if i >= 0 and p < land.tunnel_b[i]:
        return tunnel_codes(view, float(land.tunnel_b[i] - p), p)
    portal = float(land.tunnel_a[i + 1] - p) if i + 1 < len(land.tunnel_a) else np.inf
    portal = portal if portal < PORTAL_APPROACH else np.inf
    codes = np.empty((view.height, view.width), dtype=np.uint16)
    codes[: view.first_ground_row] = view.sky
    draw_ground(codes, view, p, land, textures)
    draw_skyline(codes, view, p, land, textures)
    draw_rails(codes, view, min(portal, 3000.0))
    objects = visible_objects(codes, view, p, min(portal, OBJECT_RANGE), land, placed, textures)
    drawn = 0
    layers: list[tuple[float, Callable[[], None]]] = []
    for layer in TREE_LAYERS:
        layers.append((layer.lateral, partial(draw_trees, codes, view, p, layer, land, textures)))
    if np.isfinite(portal):
        shape = land.tunnel_shape[i + 1]  # the portal ahead
        layers.append((ROCK_LATERAL + 0.01, lambda: draw_portal(codes, view, portal, shape, textures)))
    layers.append((ROCK_LATERAL, lambda: draw_rock(codes, view, p, min(portal, 2000.0), land, textures)))
    # Painter's order by lateral distance: a side object is hidden only by rows of trees
    # nearer to the track than itself.
    for lateral, draw_layer in layers:
        while drawn < len(objects) and objects[drawn][0] > lateral:
            objects[drawn][2]()
            drawn += 1
        draw_layer()
    for _, _, draw_object in objects[drawn:]:
        draw_object()
    return codes


def visible_objects(
    codes: np.ndarray, view: View, p: float, z_max: float, land: Landscape, placed: RouteObjects, textures: Textures
) -> list[tuple[float, float, Callable[[], None]]]:
    """Objects ahead as (lateral, distance, draw), sorted far-out first then far-away first."""
    objects: list[tuple[float, float, Callable[[], None]]] = []
    lo, hi = np.searchsorted(placed.house_s, [p - 40.0, p + z_max])
    for house in placed.houses[lo:hi]:
        objects.append((house[2], house[0] - p, partial(draw_house, codes, view, p, *house)))
    lo, hi = np.searchsorted(placed.tree_s, [p - 2.0, p + min(z_max, 400.0)])
    for tree in placed.trees[lo:hi]:
        # Small trees far away would be a pixel or two: skip them.
        if tree[0] - p < 60.0 * tree[3]:
            objects.append((tree[2], tree[0] - p, partial(draw_single_tree, codes, view, p, *tree)))
    for at, side in land.stations:
        if at - 200.0 - p < z_max and at + 60.0 - p > -10.0:
            objects.append((1.75, at - p, partial(draw_platform, codes, view, p, at, side)))
    if len(land.bridge_a):
        lo, hi = np.searchsorted(land.bridge_b, [p, p + z_max])
        for a, b in zip(land.bridge_a[lo : hi + 1], land.bridge_b[lo : hi + 1]):
            if a - p < z_max and b > p:
                objects.append((2.6, a - p, partial(draw_truss, codes, view, p, a, b)))
    objects.append((3.6, 0.0, lambda: draw_poles(codes, view, p, z_max, land, textures)))
    objects.sort(key=lambda o: (-o[0], -o[1]))
    return objects
