"""The cab camera: per-size geometry (`View`), projection, near clipping and cv2 drawing of codes.

World coordinates: x lateral (right positive), y height above the rail, z distance ahead (m).
Drawing uses cv2 fixed-point coordinates with `SHIFT` sub-pixel bits.
"""

from __future__ import annotations

import math

import cv2
import numpy as np

from .palette import shade_code
from .zones import GROUND_BANDS, N_BANDS

CAM_HEIGHT = 3.2  # m above rail
FOCAL = 0.6  # focal length as a fraction of image width (about 80 degrees horizontal view)
HORIZON = 0.42  # horizon row as a fraction of image height
Z_NEAR = 1.0  # m, near clipping plane


class View:
    """Per-image-size camera geometry that does not change from frame to frame."""

    def __init__(self, width: int, height: int):
        self.width, self.height = width, height
        self.focal = FOCAL * width
        self.cx = width / 2.0
        self.horizon = HORIZON * height
        offset = np.arange(width) + 0.5 - self.cx
        self.col_offset = offset
        self.col_dist = np.maximum(np.abs(offset), 0.5)
        self.col_index = np.arange(width)
        # The mountain range ahead between two morph keys, cached here by scenery.skyline:
        # (key, heights at key, at key+1).
        self.ranges: tuple[int | None, np.ndarray | None, np.ndarray | None] = (None, None, None)
        self.left = offset < 0
        self.first_ground_row = int(math.floor(self.horizon)) + 1
        self.row_centre = (np.arange(height) + 0.5).astype(np.float32)
        ground_y = self.row_centre[self.first_ground_row :].astype(np.float64)
        self.ground_z = self.focal * CAM_HEIGHT / (ground_y - self.horizon)
        self.ground_x = offset[None, :] * self.ground_z[:, None] / self.focal
        self.ground_absx = np.abs(self.ground_x)
        # Texture detail fades out with distance (it would only alias further away).
        self.grain_amp = np.clip(1.0 - self.ground_z / 60.0, 0.0, 1.0).astype(np.float32)[:, None]
        self.ground_xi_fine = (self.ground_x * 3.0 + 3000).astype(np.int32) & 255
        self.ground_xi_coarse = (self.ground_x / 6.0 + 1000).astype(np.int32) & 255
        band = np.searchsorted(GROUND_BANDS, self.ground_absx, side="right")
        stripe = (self.ground_absx / 2.5).astype(np.int64) & 1
        band = np.where((band == N_BANDS - 2) & (stripe == 1), N_BANDS - 1, band)
        rows = np.arange(len(self.ground_z))[:, None]
        self.ground_band_index = ((rows * 2 + (~self.left)[None, :]) * N_BANDS + band).astype(np.int64)
        sky_rows = self.first_ground_row
        rel = (self.row_centre[:sky_rows] / max(self.horizon, 1.0))[:, None]
        sky_level = np.rint(11 + 9 * rel).astype(np.int64)
        haze = shade_code("sky_haze", np.rint(14 + 4 * rel).astype(np.int64))
        sky = np.where(rel > 0.85, haze, shade_code("sky", sky_level))
        self.sky = np.broadcast_to(sky, (sky_rows, width)).astype(np.uint16)

    def project(self, x: float, y: float, z: float) -> tuple[float, float]:
        """World (lateral x, height y above rail, distance z ahead) to pixel (u, v)."""
        return self.cx + self.focal * x / z, self.horizon + self.focal * (CAM_HEIGHT - y) / z


def clip_near(points: list[tuple[float, float, float]]) -> list[tuple[float, float, float]]:
    """Clip a convex polygon to z >= Z_NEAR (Sutherland-Hodgman, one plane)."""
    out = []
    n = len(points)
    for i in range(n):
        a, b = points[i], points[(i + 1) % n]
        a_in, b_in = a[2] >= Z_NEAR, b[2] >= Z_NEAR
        if a_in:
            out.append(a)
        if a_in != b_in:
            w = (Z_NEAR - a[2]) / (b[2] - a[2])
            out.append((a[0] + w * (b[0] - a[0]), a[1] + w * (b[1] - a[1]), Z_NEAR))
    return out


SHIFT = 4  # sub-pixel bits for cv2 drawing
SCALE = float(1 << SHIFT)
LIMIT = 1.0e5  # keep projected coordinates inside int32 after the shift


def pixel(view: View, x: float, y: float, z: float) -> tuple[int, int]:
    """Project to fixed-point pixel coordinates for cv2 drawing with `SHIFT` fractional bits."""
    u, v = view.project(x, y, z)
    return (int(min(max(u * SCALE, -LIMIT), LIMIT)), int(min(max(v * SCALE, -LIMIT), LIMIT)))


def to_pixels(view: View, points: list[tuple[float, float, float]]) -> np.ndarray:
    return np.array([pixel(view, *point) for point in points], dtype=np.int32)


def fill(codes: np.ndarray, view: View, points: list[tuple[float, float, float]], code: int) -> None:
    """Fill a convex world polygon (clipped at the near plane) with one code."""
    clipped = clip_near(points)
    if len(clipped) >= 3:
        cv2.fillConvexPoly(codes, to_pixels(view, clipped), int(code), cv2.LINE_8, SHIFT)


def polyline(codes: np.ndarray, view: View, points: list[tuple[float, float, float]], code: int) -> None:
    """One-pixel line through world points ordered by distance (nearest first), clipped at the near plane."""
    visible = [point for point in points if point[2] >= Z_NEAR]
    if not visible:
        return
    first = points.index(visible[0])
    if first > 0:
        a, b = visible[0], points[first - 1]
        w = (Z_NEAR - a[2]) / (b[2] - a[2])
        visible.insert(0, (a[0] + w * (b[0] - a[0]), a[1] + w * (b[1] - a[1]), Z_NEAR))
    if len(visible) >= 2:
        cv2.polylines(codes, [to_pixels(view, visible)], False, int(code), 1, cv2.LINE_8, SHIFT)


def segment(codes: np.ndarray, view: View, a: tuple, b: tuple, code: int, thickness_m: float) -> None:
    """Draw a world line segment whose pixel width follows its distance."""
    if a[2] < Z_NEAR and b[2] < Z_NEAR:
        return
    if a[2] < Z_NEAR or b[2] < Z_NEAR:
        if a[2] < Z_NEAR:
            a, b = b, a
        w = (Z_NEAR - a[2]) / (b[2] - a[2])
        b = (a[0] + w * (b[0] - a[0]), a[1] + w * (b[1] - a[1]), Z_NEAR)
    thickness = int(min(max(round(view.focal * thickness_m / min(a[2], b[2])), 1), 64))
    cv2.line(codes, pixel(view, *a), pixel(view, *b), int(code), thickness, cv2.LINE_8, SHIFT)


def flat(x0: float, x1: float, y: float, z0: float, z1: float) -> list[tuple[float, float, float]]:
    """Horizontal quad along the track at height y (rails, platform tops)."""
    return [(x0, y, z0), (x1, y, z0), (x1, y, z1), (x0, y, z1)]


def along(x: float, y0: float, y1: float, z0: float, z1: float) -> list[tuple[float, float, float]]:
    """Vertical quad parallel to the track at lateral x (facades, platform edges, chords)."""
    return [(x, y0, z0), (x, y0, z1), (x, y1, z1), (x, y1, z0)]


def facing(x0: float, x1: float, y0: float, y1: float, z: float) -> list[tuple[float, float, float]]:
    """Vertical quad facing the camera at distance z (signs, beams, gable windows)."""
    return [(x0, y0, z), (x1, y0, z), (x1, y1, z), (x0, y1, z)]


def relative_rows(y: np.ndarray, top: np.ndarray, bottom: np.ndarray) -> np.ndarray:
    """(y - top) / (bottom - top) per pixel as float32: in [0, 1) inside a column's span."""
    scale = 1.0 / np.maximum(bottom - top, 0.05)
    return y * scale.astype(np.float32) - (top * scale).astype(np.float32)
