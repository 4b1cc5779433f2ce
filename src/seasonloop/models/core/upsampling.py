"""The CAE decoder's up-pooling layer: nearest 2x up-sampling fused with the convolution after it."""

from __future__ import annotations

import torch
import torch.nn.functional as F
from torch import nn


def phase_taps(kernel: int) -> tuple[torch.Tensor, int]:
    """Which low-resolution pixel each tap of a "same" convolution reads after nearest 2x
    up-sampling: a (2, span, kernel) 0/1 tensor, row a for output pixels of parity a (tap u of
    output 2m + a reads input m + (a + u - left) // 2, left = (kernel - 1) // 2, as padding="same"
    pads), and how many pixels the lowest offset lies before m."""
    left = (kernel - 1) // 2
    offsets = [[(a + u - left) // 2 for u in range(kernel)] for a in (0, 1)]
    lowest = min(min(row) for row in offsets)
    span = max(max(row) for row in offsets) - lowest + 1
    taps = torch.zeros(2, span, kernel)
    for a, row in enumerate(offsets):
        for u, offset in enumerate(row):
            taps[a, offset - lowest, u] = 1.0
    return taps, -lowest


class UpsampledConv2d(nn.Conv2d):
    """Nearest 2x up-sampling, then a "same" convolution: the function of nn.Upsample(scale_factor=2)
    followed by nn.Conv2d(padding="same") with the same weights, up to float rounding.

    Where the kernel is wider than the span of low-resolution pixels it reads (kernel >= 4), it runs
    as a sub-pixel convolution (Shi et al. 2016): the taps that read the same low-resolution pixel
    are summed into one kernel per output parity (2 x 2 kernels, stacked as output channels),
    convolved at the input's resolution and interleaved by pixel_shuffle. The 11x11 layer then costs
    7 x 7 multiply-adds an output pixel instead of 11 x 11 (the CAE's fit 1.7x faster at the same
    plateau: benchmarks/speed/bench_training_schedule.py, upsampling=separate).
    """

    def __init__(self, in_channels: int, out_channels: int, kernel: int):
        super().__init__(in_channels, out_channels, kernel, padding="same")
        taps, before = phase_taps(kernel)
        self.span = span = taps.shape[1]
        self.sub_pixel = span < kernel
        self.phase_taps: torch.Tensor
        self.register_buffer("phase_taps", taps, persistent=False)
        # F.pad's (left, right, top, bottom) of the low-resolution input
        self.low_resolution_padding = (before, span - 1 - before) * 2

    def forward(self, inputs: torch.Tensor) -> torch.Tensor:
        if not self.sub_pixel:
            return super().forward(F.interpolate(inputs, scale_factor=2, mode="nearest"))
        taps, span = self.phase_taps.to(self.weight.dtype), self.span
        # kernels[o, a, b, c] for output channel o at parity (a, b): pixel_shuffle's channel o * 4 + 2a + b
        kernels = torch.einsum("aiu,bjv,ocuv->oabcij", taps, taps, self.weight)
        kernels = kernels.reshape(self.out_channels * 4, self.in_channels, span, span)
        bias = None if self.bias is None else self.bias.repeat_interleave(4)
        low_resolution = F.conv2d(F.pad(inputs, self.low_resolution_padding), kernels, bias)
        return F.pixel_shuffle(low_resolution, 2)
