"""Trees: rows of forest parallel to the track (`TREE_LAYERS`) and single trees near it."""

from __future__ import annotations

import math
from dataclasses import dataclass

import cv2
import numpy as np

from ..camera import CAM_HEIGHT, SCALE, SHIFT, View, fill, relative_rows, segment
from ..noise import slots
from ..palette import LEVELS, MAT, MID, shade_code
from ..textures import Textures, texture
from ..zones import Landscape


@dataclass(frozen=True)
class TreeLayer:
    """A row of trees parallel to the track at a fixed lateral distance, on both sides."""

    lateral: float  # m from the track centre
    cell: float  # m of route per tree slot
    reach: int  # neighbouring slots searched on each side for crowns covering a column
    height: tuple[float, float]  # m
    occupancy: tuple[float, ...]  # chance a slot holds a tree, per zone type
    understorey: bool  # dark trunk zone at the bottom (near rows only)
    detail: bool  # branch tiers and leaf texture (visible only on nearer rows)
    salt: int


TREE_LAYERS = (
    TreeLayer(170.0, 10.0, 1, (12.0, 22.0), (0.95, 0.95, 0.9, 0.0, 0.9, 0.9, 0.2), False, False, 11),
    TreeLayer(65.0, 8.0, 2, (10.0, 20.0), (0.9, 0.9, 0.5, 0.0, 0.7, 0.8, 0.12), False, True, 12),
    TreeLayer(22.0, 7.0, 3, (10.0, 20.0), (0.9, 0.85, 0.0, 0.0, 0.3, 0.6, 0.08), True, True, 13),
    TreeLayer(7.0, 5.0, 3, (11.0, 22.0), (0.97, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0), True, True, 14),
)
ZONE_TREE_SCALE = np.array([1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 0.3])  # moorland: low birch scrub


def _tallest_crowns(view: View, p: float, layer: TreeLayer, land: Landscape, textures: Textures) -> tuple | None:
    """Per column of the row, the tallest crown covering it (or the stand's canopy far away).

    Returns (cols, z, s, height, key, spruce, rel, keep) per drawn column, None if none is drawn."""
    z_all = view.focal * layer.lateral / view.col_dist
    s_all = p + z_all
    kind_all, height_all, spruce_all = land.zone_at(view.left, s_all)
    occupancy_all = np.asarray(layer.occupancy)[kind_all]
    cols = np.flatnonzero((occupancy_all > 0) & (z_all <= 4000.0))
    if cols.size == 0:
        return None
    z, s, occupancy = z_all[cols], s_all[cols], occupancy_all[cols]
    height_scale = height_all[cols] * ZONE_TREE_SCALE[kind_all[cols]]
    spruce_share = spruce_all[cols]
    side_key = np.where(view.left[cols], 0, 1 << 26)
    position = s / layer.cell
    cell0 = np.floor(position).astype(np.int64)
    # All candidate slots at once: (2 * reach + 1, columns).
    cell = cell0 + np.arange(-layer.reach, layer.reach + 1)[:, None]
    key = cell + side_key
    rand = textures.table[:, slots(key, layer.salt * 104729)]
    spruce = rand[3] < spruce_share
    centre = cell + 0.5 + 0.5 * (rand[1] - 0.5)
    tree_height = (layer.height[0] + (layer.height[1] - layer.height[0]) * rand[2]) * height_scale
    # Crowns are round, not flat: seen obliquely a crown of radius r covers about r*z/X metres
    # of the row; the searched slots bound that width.
    oblique = np.maximum(z / layer.lateral, 1.0) / layer.cell
    radius = np.where(spruce, 0.2, 0.3) * (0.85 + 0.3 * rand[4]) * tree_height
    half_width = np.clip(radius * oblique, 0.3, layer.reach - 0.3)
    rel = (position - centre) / half_width
    d = np.minimum(np.abs(rel), 1.0)
    # Spruce: a cone. Birch: a dome on top of the stand below it.
    shape = np.where(spruce, 1.0 - d, np.where(d < 1.0, 0.5 + 0.5 * np.sqrt(1.0 - d * d), 0.0))
    h = np.where(rand[0] < occupancy, tree_height * shape, 0.0)
    winner = np.argmax(h, axis=0)[None, :]
    best = np.take_along_axis(h, winner, axis=0)[0]
    best_key = np.take_along_axis(key, winner, axis=0)[0]
    best_spruce = np.take_along_axis(spruce, winner, axis=0)[0]
    best_rel = np.take_along_axis(rel, winner, axis=0)[0]
    # Where crowns would be wider than the searched slots, or many trees share a column, draw
    # the stand's average canopy instead of single crowns (a distant tree line).
    typical = 0.25 * (layer.height[0] + layer.height[1]) / 2 * height_scale
    metres_per_column = z * z / (view.focal * layer.lateral)
    crowding = np.maximum(metres_per_column / layer.cell - 0.5, typical * oblique / (layer.reach - 0.3) - 1.0)
    blend = np.clip(crowding, 0.0, 1.0)
    mean_height = 0.7 * (layer.height[0] + layer.height[1]) / 2 * height_scale * occupancy
    best = best + (mean_height - best) * blend
    keep = best > 0.3
    if not keep.any():
        return None
    return cols, z, s, best, best_key, best_spruce, best_rel, keep


def draw_trees(codes: np.ndarray, view: View, p: float, layer: TreeLayer, land: Landscape, textures: Textures) -> None:
    """A row of trees: per column the tallest crown covering it (spruce cones, birch domes)."""
    crowns = _tallest_crowns(view, p, layer, land, textures)
    if crowns is not None:
        _paint_crowns(codes, view, layer, textures, *crowns)


def _paint_crowns(
    codes: np.ndarray,
    view: View,
    layer: TreeLayer,
    textures: Textures,
    cols: np.ndarray,
    z: np.ndarray,
    s: np.ndarray,
    best: np.ndarray,
    best_key: np.ndarray,
    best_spruce: np.ndarray,
    best_rel: np.ndarray,
    keep: np.ndarray,
) -> None:
    """Fill each column's crown span with spruce or birch codes, lit from the left, textured when near."""
    # Columns without a tree get an empty span above the image.
    top = np.where(keep, view.horizon + view.focal * (CAM_HEIGHT - best) / z, -11.0)
    bottom = np.where(keep, view.horizon + view.focal * CAM_HEIGHT / z, -10.0)
    r0 = max(int(math.floor(top[keep].min())), 0)
    r1 = min(int(math.ceil(bottom[keep].max())), view.height)
    if r1 <= r0:
        return
    y = view.row_centre[r0:r1, None]
    rel_y = relative_rows(y, top, bottom)
    inside = (rel_y >= 0.0) & (rel_y < 1.0)
    rand = textures.table[5:7, slots(best_key, layer.salt * 104729)]
    birch = MAT["birch_a"] + (rand[0] * 3).astype(np.int32)
    dark_code = np.where(best_spruce, MAT["spruce"], birch) * LEVELS
    # Light from the left: the left flank of each crown is lighter.
    column_level = np.where(best_rel < 0.0, MID + 2, MID - 2).astype(np.int32)
    if layer.detail:
        # Height above ground per pixel, so textures stay fixed to the world.
        row_scale = (z / view.focal).astype(np.float32)
        altitude = (CAM_HEIGHT + view.horizon * z / view.focal + 4096.0).astype(np.float32) - y * row_scale
        leaves = texture(textures.grain_int_flat, altitude * np.float32(5.0), s * 4.0)
        # Spruce branch whorls whose upper sides catch light and hold snow, broken up by the
        # leaf texture so they read as patches rather than stripes.
        whorl = (altitude * np.float32(256.0 / 1.8) + (rand[1] * 256.0).astype(np.float32)).astype(np.int32) & 255
        lit = whorl + 24 * leaves < 70
        lit_code = np.where(best_spruce, MAT["spruce_lit"], birch) * LEVELS
        base = np.where(lit, lit_code, dark_code)
        level = column_level + leaves - (4.0 * rel_y).astype(np.int32)
    else:
        base = dark_code
        level = column_level - (4.0 * rel_y).astype(np.int32)
    if layer.understorey:
        base = np.where(rel_y > 0.85, MAT["understorey"] * LEVELS, base)
    block = codes[r0:r1, cols]
    codes[r0:r1, cols] = np.where(inside, base + level, block)


def draw_single_tree(
    codes: np.ndarray, view: View, p: float, s: float, side: int, lateral: float, height: float, spruce: bool
) -> None:
    """A tree standing alone: a spruce of three tiers, or a birch with a round crown."""
    z = s - p
    if z < 2.0:
        return
    x = side * lateral
    if spruce:
        segment(codes, view, (x, 0.0, z), (x, 0.2 * height, z), shade_code("understorey", 14), 0.3)
        for tier in range(3):
            base = (0.12 + 0.25 * tier) * height
            top = min(base + 0.5 * height, height)
            half = 0.2 * height * (1.0 - 0.28 * tier)
            fill(codes, view, [(x - half, base, z), (x + half, base, z), (x, top, z)], shade_code("spruce_lit", 15))
            drop = 0.06 * height
            shadow = [(x - 0.92 * half, base - drop / 2, z), (x + 0.92 * half, base - drop / 2, z), (x, top - drop, z)]
            fill(codes, view, shadow, shade_code("spruce", 14))
    else:
        segment(codes, view, (x, 0.0, z), (x, 0.55 * height, z), shade_code("trunk", 16), 0.25)
        u, v = view.project(x, 0.62 * height, z)
        axes = (view.focal * 0.24 * height / z, view.focal * 0.36 * height / z)
        variant = ("birch_a", "birch_b", "birch_c")[int(s * 7.0) % 3]
        centre, size = (int(u * SCALE), int(v * SCALE)), (int(axes[0] * SCALE) + 1, int(axes[1] * SCALE) + 1)
        cv2.ellipse(codes, centre, size, 0, 0, 360, shade_code(variant, 15), -1, cv2.LINE_8, SHIFT)
