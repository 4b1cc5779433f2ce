"""How the auto-encoders (and the torch ICA solvers) compute on this machine: the device, the
precision of the forward pass (bfloat16 where the hardware has it, autocast) and denormal floats
flushed to zero on the CPU. torch is imported where it computes: the learners' params checks read
DEVICES and PRECISIONS, and torch takes a second to import."""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    import torch

DEVICES = ("auto", "cpu", "cuda")
PRECISIONS = ("auto", "float32", "bfloat16")  # of the auto-encoders' forward pass


def resolve_device(requested: str, key: str) -> torch.device:
    """'auto' -> cuda if available else cpu; 'cuda' without CUDA -> ValueError naming `key`."""
    import torch

    if requested == "auto":
        return torch.device("cuda" if torch.cuda.is_available() else "cpu")
    if requested == "cuda" and not torch.cuda.is_available():
        raise ValueError(f"{key} = 'cuda' but CUDA is not available on this machine")
    return torch.device(requested)


def cpu_has_native_bfloat16() -> bool:
    """True where the CPU computes bfloat16 in hardware (AVX512-BF16 or AMX); elsewhere torch
    emulates it, which is slower than float32."""
    import torch

    cpu = torch.cpu
    return any(
        getattr(cpu, check, lambda: False)() for check in ("_is_avx512_bf16_supported", "_is_amx_tile_supported")
    )


def resolve_precision(requested: str, device: torch.device, key: str) -> torch.dtype:
    """The autocast dtype for `requested` ('auto' | 'float32' | 'bfloat16') on `device`.

    auto: bfloat16 on CUDA devices that support it and on CPUs with native bfloat16, float32
    otherwise. An explicit 'bfloat16' is honoured where torch can run it (emulated on CPUs
    without the units, which is slow but not wrong) and raises naming `key` on a CUDA device
    without bfloat16.
    """
    import torch

    if requested not in PRECISIONS:
        raise ValueError(f"{key} must be one of {', '.join(PRECISIONS)}, got {requested!r}")
    cuda = device.type == "cuda"
    native = torch.cuda.is_bf16_supported() if cuda else cpu_has_native_bfloat16()
    if requested == "bfloat16" and cuda and not native:
        raise ValueError(f"{key} = 'bfloat16' but this CUDA device has no bfloat16 support")
    if requested == "bfloat16" or (requested == "auto" and native):
        return torch.bfloat16
    return torch.float32


@contextmanager
def autocast(device: torch.device, dtype: torch.dtype) -> Iterator[None]:
    """Mixed-precision forward pass in `dtype` (no-op for float32)."""
    import torch

    with torch.autocast(device.type, dtype=dtype, enabled=dtype != torch.float32):
        yield


def flush_denormals(device: torch.device) -> None:
    """From here on in this process, compute with denormal floats flushed to zero (FTZ and DAZ) on
    the CPU.

    Why: the FAE's gradients reach the denormal range (below ~1.2e-38) after ~10 epochs, where a
    multiply-add takes many times longer; its epochs then took twice as long
    (benchmarks/speed/bench_training_schedule.py: denormals=kept). Flushed, every FAE run measured ended at
    the same epoch with the same validation loss to the last digit, and its weights after 14 epochs
    were the same to the bit (such values vanish in sums of normal ones). The mode is per thread,
    and torch's OpenMP threads take the calling thread's when they are created: called before a
    process's first parallel torch operation (as in a fit stage) it holds in every thread; called
    later, in the calling thread only (slower, not other arithmetic where no denormal arises).
    """
    import torch

    if device.type == "cpu":
        torch.set_flush_denormal(True)
