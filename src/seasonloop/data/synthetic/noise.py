"""Hashing and noise: random access along the route from seeded tables, no stored textures."""

from __future__ import annotations

import numpy as np


def mix(*values: int) -> int:
    """Deterministic 64-bit integer hash of a few integers (for per-frame choices)."""
    x = 0x243F6A8885A308D3
    for v in values:
        x = (x ^ (v & 0xFFFFFFFFFFFFFFFF)) * 0x9E3779B97F4A7C15 & 0xFFFFFFFFFFFFFFFF
        x ^= x >> 29
    x = (x * 0xBF58476D1CE4E5B9) & 0xFFFFFFFFFFFFFFFF
    return x ^ (x >> 32)


def slots(keys: np.ndarray, salt: int | np.ndarray) -> np.ndarray:
    """Cheap multiplicative hash of integer keys (|key| < 2**30) to a slot of a 65536-entry table.

    The tables hold the seeded random numbers, so any place along the route can be generated
    on demand without storing anything per metre.
    """
    return (((keys + np.bitwise_and(salt, 0xFFFFF)) * 0x9E3779B1) >> 12) & 0xFFFF


def value_noise(x: np.ndarray, salt: int | np.ndarray, table: np.ndarray) -> np.ndarray:
    """Smooth 1-D value noise in [0, 1) from a random table."""
    cell = np.floor(x)
    frac = x - cell
    cell = cell.astype(np.int64)
    a = table[slots(cell, salt)]
    b = table[slots(cell + 1, salt)]
    return a + (b - a) * (frac * frac * (3.0 - 2.0 * frac))


def fbm(x: np.ndarray, salt: int | np.ndarray, table: np.ndarray, octaves: int = 3) -> np.ndarray:
    """Fractal value noise in [0, 1): rugged enough for skylines."""
    total = np.zeros_like(x, dtype=np.float64)
    amplitude, norm = 1.0, 0.0
    for octave in range(octaves):
        total += amplitude * value_noise(x * (2.0**octave), salt + 977 * octave, table)
        norm += amplitude
        amplitude *= 0.5
    return total / norm


def smoothstep(x: np.ndarray) -> np.ndarray:
    x = np.clip(x, 0.0, 1.0)
    return x * x * (3.0 - 2.0 * x)
