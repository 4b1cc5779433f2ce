"""A season's look (`SeasonLook`): codes to colours, clouds, camera offset and shake, light, noise."""

from __future__ import annotations

import cv2
import numpy as np

from ...params.seasons import SEASONS
from .camera import View
from .difficulty import RouteDifficulty
from .noise import mix
from .palette import CLOUDS, LEVELS, season_palette


class SeasonLook:
    """One season's appearance at one image size: palette, clouds, camera, light drift, noise."""

    _NOISE_FRAMES = 8
    _NOISE_PAD = 8

    def __init__(self, seed: int, season: str, view: View, difficulty: RouteDifficulty):
        s_index = SEASONS.index(season)
        self.view = view
        self.s_index, self.seed = s_index, seed
        self.palette = season_palette(season, difficulty)
        width, height = view.width, view.height
        scale = width / 256.0
        rng = np.random.default_rng([seed, s_index, 1])
        # A fixed camera offset per season (the cameras were re-mounted) plus smooth shake.
        self.offset = (rng.uniform(-3.0, 3.0) * scale, rng.uniform(-2.0, 2.0) * scale, rng.uniform(-0.4, 0.4))
        self.jitter_freq = rng.uniform(0.15, 1.2, (2, 3))
        self.jitter_phase = rng.uniform(0.0, 2 * np.pi, (2, 3))
        self.jitter_amp = 0.3 * scale
        self.light_period = rng.uniform(60.0, 300.0, 2)
        self.light_phase = rng.uniform(0.0, 2 * np.pi, 2)
        # Clouds: a wide panorama of soft noise, seamless across its ends, that drifts slowly.
        coverage, colour, opacity = CLOUDS[season]
        rng = np.random.default_rng([seed, s_index, 2])
        rows, pano = view.first_ground_row, 4 * width
        noise = np.zeros((rows, pano), dtype=np.float32)
        for octave, weight in ((6, 1.0), (14, 0.5), (30, 0.25)):
            grid = np.tile(rng.normal(0.0, 1.0, (max(2, octave // 3), octave)).astype(np.float32), (1, 3))
            noise += weight * cv2.resize(grid, (3 * pano, rows), interpolation=cv2.INTER_CUBIC)[:, pano : 2 * pano]
        threshold = np.quantile(noise, 1.0 - coverage)
        alpha = np.clip((noise - threshold) / (noise.std() * 0.6), 0.0, 1.0) * opacity
        fade = np.clip((view.horizon - view.row_centre[:rows]) / (0.35 * view.horizon), 0.3, 1.0)[:, None]
        self.clouds = np.concatenate([alpha * fade, (alpha * fade)[:, :width]], axis=1).astype(np.float32)
        self.cloud_image = np.empty((rows, width, 3), dtype=np.uint8)
        self.cloud_image[:] = colour[::-1]
        self.cloud_drift = rng.uniform(0.2, 0.6) * scale  # px/s
        rng = np.random.default_rng([seed, s_index, 3, width, height])
        pad = self._NOISE_PAD
        grain = rng.normal(0.0, 2.0, (self._NOISE_FRAMES, height + pad, width + pad, 3))
        self.noise = np.clip(np.rint(grain), -8, 8).astype(np.int16)

    def colourise(self, codes: np.ndarray, t: float, shake: float) -> np.ndarray:
        """Season colours, clouds, camera offset and shake (scaled by `shake`), light drift, noise."""
        view = self.view
        image = np.take(self.palette, codes, axis=0)
        rows = view.first_ground_row
        shift = int(t * self.cloud_drift) % (self.clouds.shape[1] - view.width)
        alpha = self.clouds[:, shift : shift + view.width] * (codes[:rows] < 2 * LEVELS)  # sky pixels only
        image[:rows] = cv2.blendLinear(image[:rows], self.cloud_image, 1.0 - alpha, alpha)
        dx, dy, angle = self.offset
        jitter = shake * self.jitter_amp * np.sin(2 * np.pi * self.jitter_freq * t + self.jitter_phase).sum(axis=1)
        matrix = cv2.getRotationMatrix2D((view.cx, view.horizon), angle, 1.0)
        matrix[0, 2] += dx + jitter[0]
        matrix[1, 2] += dy + jitter[1]
        image = cv2.warpAffine(
            image, matrix, (view.width, view.height), flags=cv2.INTER_LINEAR, borderMode=cv2.BORDER_REFLECT_101
        )
        gain = 1.0 + 0.04 * float(np.sin(2 * np.pi * t / self.light_period + self.light_phase).sum())
        image = cv2.convertScaleAbs(image, alpha=gain)
        key = mix(self.seed, self.s_index, int(round(t * 1e6)))
        k, oy, ox = key % self._NOISE_FRAMES, (key >> 8) % self._NOISE_PAD, (key >> 16) % self._NOISE_PAD
        noise = self.noise[k, oy : oy + view.height, ox : ox + view.width]
        return cv2.add(image, noise, dtype=cv2.CV_8U)
