"""A `dvc repro` timed stage by stage, for the benchmarks that run the whole pipeline (the default
run, the full preset, the scaling runs).

Each stage's wall time runs from DVC's "Running stage" line to the next one (or to the end), so it
includes DVC's own work on it; its peak memory is the largest resident set of the processes under
`dvc repro` while it ran (sampled every SAMPLE_SECONDS: a peak shorter than that can be missed;
a stage's worker processes count together). Every finished stage is appended to a log in the run's
folder as it ends, so a run stopped part way (a closed session) and started again in the same folder
(DVC restarts at the first unfinished stage) keeps the stages it timed before.
"""

from __future__ import annotations

import contextlib
import json
import sys
import threading
import time
from pathlib import Path

import psutil

RUNNING = "Running stage '"
SAMPLE_SECONDS = 0.2
STAGE_LOG = "stage_log.jsonl"  # one JSON object per finished stage, in the run's folder


def _tree_rss(process: psutil.Popen) -> int:
    """Resident bytes of every process under `process` (not itself: DVC's own)."""
    total = 0
    for child in process.children(recursive=True):
        with contextlib.suppress(psutil.Error):  # ended between listing and reading
            total += child.memory_info().rss
    return total


def read_stage_log(root: Path) -> dict[str, dict[str, float]]:
    """stage -> {"seconds", "peak_rss_mb"} of the stages finished so far in root (earlier runs included)."""
    path = root / STAGE_LOG
    if not path.is_file():
        return {}
    records = [json.loads(line) for line in path.read_text().splitlines() if line.strip()]
    return {record["stage"]: {"seconds": record["seconds"], "peak_rss_mb": record["peak_rss_mb"]} for record in records}


def timed_repro(root: Path, env: dict[str, str]) -> tuple[float, dict[str, dict[str, float]]]:
    """Run `dvc repro` in root; (this run's wall seconds, stage -> {"seconds", "peak_rss_mb"} of
    every stage finished in root, those of earlier runs included). Raises SystemExit with the end
    of DVC's output when it fails (the stages finished before it stay in the log)."""
    dvc = str(Path(sys.executable).parent / "dvc")
    log = root / STAGE_LOG
    output: list[str] = []
    current: list = [None, 0.0, 0]  # stage, its start, its peak bytes
    lock = threading.Lock()

    def finish(now: float) -> None:
        stage, since, peak = current
        if stage is not None:
            with log.open("a") as file:
                file.write(json.dumps({"stage": stage, "seconds": now - since, "peak_rss_mb": peak / 2**20}) + "\n")

    start = time.perf_counter()
    process = psutil.Popen([dvc, "repro"], cwd=root, env=env, stdout=-1, stderr=-2, text=True, bufsize=1)

    def sample() -> None:
        while process.poll() is None:
            rss = _tree_rss(process)
            with lock:
                current[2] = max(current[2], rss)
            time.sleep(SAMPLE_SECONDS)

    sampler = threading.Thread(target=sample, daemon=True)
    sampler.start()
    assert process.stdout is not None
    for line in process.stdout:
        output.append(line)
        print(line, end="", flush=True)
        if line.startswith(RUNNING):
            now = time.perf_counter()
            with lock:
                finish(now)
                current[:] = [line[len(RUNNING) :].split("'")[0], now, 0]
    process.wait()
    sampler.join()
    end = time.perf_counter()
    if process.returncode != 0:
        raise SystemExit(f"dvc repro failed in {root}:\n{''.join(output[-40:])}")
    finish(end)
    return end - start, read_stage_log(root)
