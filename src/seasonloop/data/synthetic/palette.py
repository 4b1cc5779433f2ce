"""Materials, shade codes and the season palettes that turn codes into colours.

A frame's geometry is drawn as *codes* (material x shade level); each season looks them up in its
own palette, with the season's colours, light and contrast baked in.
"""

from __future__ import annotations

from typing import overload

import numpy as np

from ...params.seasons import SEASONS
from .difficulty import RouteDifficulty

LEVELS = 32  # shade levels per material; code = material * LEVELS + level
MID = 16  # level of unshaded colour

# RGB per season (summer, spring, fall, winter). Winter: snow on ground, trees and roofs, overcast.
COLOURS: dict[str, tuple[tuple[int, int, int], ...]] = {
    "sky": ((95, 150, 220), (120, 172, 235), (138, 148, 162), (178, 182, 190)),
    "sky_haze": ((175, 200, 228), (195, 215, 238), (165, 170, 178), (192, 194, 198)),
    "mtn_low": ((82, 102, 104), (96, 114, 112), (112, 102, 88), (186, 190, 198)),
    "mtn_rock": ((110, 120, 138), (120, 128, 146), (112, 116, 128), (176, 181, 192)),
    "mtn_patch": ((118, 128, 146), (226, 231, 240), (120, 124, 136), (214, 218, 226)),
    "mtn_top": ((160, 168, 184), (232, 236, 244), (196, 200, 210), (222, 226, 232)),
    "hill_forest": ((46, 80, 50), (76, 108, 64), (116, 92, 52), (150, 156, 162)),
    "hill_bare": ((104, 112, 92), (118, 116, 96), (122, 98, 72), (210, 214, 222)),
    "hill_patch": ((104, 112, 92), (226, 230, 236), (122, 98, 72), (222, 226, 232)),
    "spruce": ((24, 54, 30), (36, 68, 36), (28, 50, 28), (66, 78, 72)),
    "spruce_lit": ((40, 80, 42), (58, 98, 50), (42, 70, 38), (222, 226, 232)),
    "birch_a": ((58, 112, 38), (128, 168, 66), (206, 168, 48), (112, 108, 104)),
    "birch_b": ((70, 124, 44), (146, 180, 78), (210, 128, 40), (126, 120, 116)),
    "birch_c": ((52, 100, 36), (116, 156, 60), (160, 70, 40), (100, 96, 94)),
    "understorey": ((20, 30, 20), (30, 38, 26), (32, 28, 22), (150, 154, 160)),
    "grass": ((78, 124, 52), (122, 150, 62), (136, 120, 62), (228, 232, 238)),
    "verge": ((92, 116, 60), (128, 134, 78), (128, 112, 70), (214, 218, 224)),
    "forest_floor": ((48, 78, 34), (90, 98, 54), (102, 80, 44), (218, 222, 228)),
    "field_a": ((96, 150, 50), (126, 104, 74), (192, 162, 82), (234, 236, 240)),
    "field_b": ((80, 134, 44), (140, 160, 70), (160, 126, 70), (222, 226, 232)),
    "moor": ((100, 114, 60), (124, 114, 74), (132, 90, 56), (228, 231, 236)),
    "water": ((58, 88, 128), (78, 116, 158), (72, 82, 94), (204, 209, 217)),
    "ballast": ((112, 106, 98), (120, 114, 104), (100, 95, 88), (196, 198, 203)),
    "sleeper": ((76, 64, 54), (80, 70, 60), (70, 60, 52), (160, 162, 168)),
    "rail": ((172, 172, 176), (176, 176, 180), (150, 150, 155), (96, 96, 102)),
    "rail_dark": ((60, 54, 50), (64, 58, 54), (56, 50, 46), (84, 84, 90)),
    "rock": ((104, 104, 100), (114, 112, 106), (94, 92, 88), (148, 151, 158)),
    "rock_top": ((80, 110, 60), (110, 124, 70), (122, 96, 56), (228, 231, 236)),
    "house_red": ((152, 40, 34), (158, 44, 38), (136, 38, 32), (138, 52, 46)),
    "house_white": ((226, 226, 220), (232, 232, 226), (206, 206, 200), (212, 212, 212)),
    "house_yellow": ((216, 180, 90), (222, 186, 96), (196, 162, 84), (198, 174, 112)),
    "roof_dark": ((52, 52, 58), (56, 56, 62), (48, 48, 54), (228, 230, 236)),
    "roof_red": ((122, 50, 40), (128, 54, 44), (110, 46, 38), (228, 230, 236)),
    "window": ((40, 46, 58), (44, 50, 62), (36, 40, 50), (62, 64, 72)),
    "pole": ((86, 66, 46), (90, 70, 50), (74, 58, 42), (76, 64, 52)),
    "wire": ((44, 44, 44), (48, 48, 48), (42, 42, 42), (92, 92, 96)),
    "steel": ((92, 102, 96), (98, 108, 102), (86, 94, 90), (124, 128, 134)),
    "platform": ((150, 148, 142), (156, 154, 148), (136, 134, 128), (218, 220, 225)),
    "platform_edge": ((230, 210, 60), (236, 216, 66), (210, 190, 56), (196, 196, 186)),
    "tunnel": ((40, 36, 32), (40, 36, 32), (40, 36, 32), (40, 36, 32)),
    "lamp": ((170, 140, 80), (170, 140, 80), (170, 140, 80), (170, 140, 80)),
    "daylight": ((240, 242, 238), (244, 246, 244), (226, 228, 228), (236, 237, 240)),
    "trunk": ((196, 192, 182), (200, 196, 186), (186, 180, 170), (150, 146, 140)),
    "sign": ((232, 232, 232), (236, 236, 236), (214, 214, 214), (226, 226, 226)),
}
MATERIAL_NAMES = tuple(COLOURS)
MAT = {name: index for index, name in enumerate(MATERIAL_NAMES)}

# Global light per season: channel gains (RGB), contrast around a pivot, how much of the
# directional shading survives (flat overcast light in fall and winter). Winter's contrast and
# shading set how hard winter is: they come from `RouteDifficulty` (`season_grade`).
_GRADE = {
    "summer": {"gain": (1.00, 1.00, 1.00), "contrast": 1.00, "pivot": 120.0, "shading": 1.00},
    "spring": {"gain": (1.05, 1.05, 1.07), "contrast": 1.00, "pivot": 120.0, "shading": 0.90},
    "fall": {"gain": (0.95, 0.90, 0.84), "contrast": 0.95, "pivot": 120.0, "shading": 0.70},
    "winter": {"gain": (0.95, 0.97, 1.02), "pivot": 180.0},
}
# Clouds per season: sky fraction covered, colour (RGB), opacity.
CLOUDS = {
    "summer": (0.35, (246, 246, 248), 0.85),
    "spring": (0.18, (250, 250, 252), 0.80),
    "fall": (0.70, (148, 150, 156), 0.75),
    "winter": (0.90, (204, 205, 209), 0.35),
}


@overload
def shade_code(material: str, level: int) -> int: ...
@overload
def shade_code(material: str, level: np.ndarray) -> np.ndarray: ...
def shade_code(material: str, level: int | np.ndarray) -> int | np.ndarray:
    """The code of `material` at shade `level` (0 .. LEVELS - 1, `MID` unshaded)."""
    return MAT[material] * LEVELS + level


def season_grade(season: str, difficulty: RouteDifficulty) -> dict:
    """The season's light: gain, contrast, pivot and shading (winter's from `difficulty`)."""
    grade = _GRADE[season]
    if season == "winter":
        grade = {**grade, "contrast": difficulty.winter_contrast, "shading": difficulty.winter_shading}
    return grade


def season_palette(season: str, difficulty: RouteDifficulty) -> np.ndarray:
    """(materials * levels, 3) uint8 BGR lookup table with season colour and light baked in."""
    s_index = SEASONS.index(season)
    grade = season_grade(season, difficulty)
    base = np.array([COLOURS[name][s_index] for name in MATERIAL_NAMES], dtype=np.float64)
    shade = 1.0 + (np.arange(LEVELS) / (LEVELS - 1) - 0.5) * grade["shading"]
    colours = np.clip(base[:, None, :] * shade[None, :, None], 0, 255)
    colours = colours * np.array(grade["gain"])
    graded = grade["pivot"] + (colours - grade["pivot"]) * grade["contrast"]
    # Tunnels are lit by lamps and headlights, not by the season's sky: no contrast change there.
    lamp_lit = np.isin(np.arange(len(MATERIAL_NAMES)), [MAT[name] for name in ("tunnel", "lamp", "daylight")])
    colours = np.where(lamp_lit[:, None, None], colours, graded)
    rgb = np.clip(np.rint(colours), 0, 255).astype(np.uint8).reshape(-1, 3)
    return np.ascontiguousarray(rgb[:, ::-1])
