"""What machine a timing or a result came from: the CPU's model and its vector units.

Machines differ between sessions (AVX2 only, AVX512-BF16, AMX), and torch picks its kernels by
them, so a timing or a byte-level comparison means little without this line.
"""

from __future__ import annotations

import platform
from pathlib import Path

VECTOR_UNITS = ("avx2", "avx512f", "avx512_bf16", "amx_bf16")


def cpu_model() -> str:
    """The CPU's model name, family and model numbers (a virtual machine's name is often just 'AMD
    EPYC': family 25 model 1 is Zen 3, model 17 Zen 4) and its vector units (what lscpu shows), e.g.
    'AMD EPYC (family 25 model 17; avx2, avx512f, avx512_bf16)'."""
    try:
        lines = Path("/proc/cpuinfo").read_text().splitlines()
    except OSError:
        return platform.processor() or "unknown CPU"
    fields = {key.strip(): value.strip() for key, value in (line.split(":", 1) for line in lines if ":" in line)}
    flags = set(fields.get("flags", "").split())
    units = [flag for flag in VECTOR_UNITS if flag in flags]
    family = (
        f"family {fields['cpu family']} model {fields['model']}; "
        if "cpu family" in fields and "model" in fields
        else ""
    )
    return f"{fields.get('model name', 'unknown CPU')} ({family}{', '.join(units) or 'no AVX2'})"
