"""What a measured record says about where and from what it was measured (the benchmarks' and
replicate routes' records in benchmarks/results/): the source (commit, uncommitted changes), the
CPU and how busy it was with other work, the library versions."""

from __future__ import annotations

import os
import platform
import subprocess
import time
from pathlib import Path
from typing import Any

from seasonloop.io import write_json
from seasonloop.machine import cpu_model
from seasonloop.models.core.learner import to_json_value
from tools.repository import REPO

RESULTS_DIR = Path("benchmarks/results")
# the variables, and their values, that make this CPU run an AVX2-only CPU's kernels (torch's,
# oneDNN's, OpenBLAS's): an estimate of the slowest CPU the project meets
ISA_CAP = {"ATEN_CPU_CAPABILITY": "avx2", "ONEDNN_MAX_CPU_ISA": "AVX2", "OPENBLAS_CORETYPE": "Haswell"}


def cpu_busy_fraction(seconds: float = 1.0) -> float | None:
    """Fraction of all cores busy over `seconds` while this process sleeps, i.e. other work
    (from /proc/stat; None where it does not exist)."""

    def snapshot() -> tuple[int, int] | None:
        try:
            fields = [int(value) for value in Path("/proc/stat").read_text().split("\n")[0].split()[1:]]
        except OSError:
            return None
        idle = fields[3] + fields[4]  # idle + iowait
        return sum(fields) - idle, sum(fields)

    first = snapshot()
    time.sleep(seconds)
    second = snapshot()
    if first is None or second is None or second[1] == first[1]:
        return None
    return (second[0] - first[0]) / (second[1] - first[1])


def machine() -> dict[str, Any]:
    """What the timings are measured on, how busy the CPU is with other work just now, and the
    source measured (git_state: taken here, at the start, as a commit made during a long run
    is not what ran)."""
    import torch  # here: a record's provenance, and only a measuring process pays for torch

    return {
        "source": git_state(),
        "cpu": cpu_model(),
        # an ISA cap (benchmarks/common.py ISA_CAP) estimates an AVX2-only CPU
        "isa_cap": {key: os.environ.get(key) for key in ISA_CAP},
        "cpu_count": os.cpu_count(),
        "torch_threads": torch.get_num_threads(),
        "cuda": torch.cuda.get_device_name(0) if torch.cuda.is_available() else None,
        "other_cpu_busy_fraction": cpu_busy_fraction(),
        "python": platform.python_version(),
        "torch": torch.__version__,
    }


def git_state() -> dict[str, Any]:
    """The commit this checkout is at, and whether it has uncommitted changes (what was measured)."""

    def git(*args: str) -> str:
        return subprocess.run(["git", *args], cwd=REPO, capture_output=True, text=True).stdout.strip()

    return {"commit": git("rev-parse", "--short", "HEAD") or None, "dirty": bool(git("status", "--porcelain", "-uno"))}


def write_result(name: str, record: dict[str, Any], measured_on: dict[str, Any]) -> Path:
    """Write benchmarks/results/<name>.json with `measured_on` (machine(), taken at the start) and
    the commit measured (at the start), and return its path."""
    path = RESULTS_DIR / f"{name}.json"
    write_json(path, to_json_value({**record, "machine": measured_on, **measured_on.get("source", git_state())}))
    return path
