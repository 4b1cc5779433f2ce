"""Do the learners that are not auto-encoders give the same metrics on every CPU? Run the pipeline
up to their evaluation twice, with this CPU's own kernels and with those of an AVX2-only CPU, and
compare every metrics/eval file.

Numerical libraries pick their kernels by the CPU they find: OpenBLAS (numpy, scipy, scikit-learn)
per CPU model, numpy's and OpenCV's own SIMD loops per instruction set, torch (ATen, oneDNN, MKL)
likewise; kernels of another vector width sum in another order and round differently. This script
emulates an AVX2-only CPU on this one with the variables of AVX2_ONLY (read once, at start-up, so
each run is its own `dvc repro` in its own copy of the repository) and compares the two runs file
by file: every metrics/eval file of the learners below, and the data and models on the way.
Measurements only: never set these variables in tests or CI.

    python -m benchmarks.machines.check_cross_blas [--keep DIR]

Takes a few minutes (two runs of the data stages and five learners on the default params).
Writes benchmarks/results/check_cross_blas.json; the headline line is printed last; exit status 1
when a metrics file differs.
"""

from __future__ import annotations

import argparse
import hashlib
import json
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from benchmarks.common import capped_environment, copy_repository
from tools.records import ISA_CAP, machine, write_result

# the learners whose metrics must not depend on the CPU (the auto-encoders may: documented)
LEARNERS = ("raw_patchnorm", "pca", "pca_whiten", "ica", "ica_bovw")
# every library's kernels capped at AVX2: the timing cap (OpenBLAS's Haswell kernels, torch's ATen,
# oneDNN), and MKL, numpy's dispatched loops (x86-64-v4 = AVX-512) and OpenCV's
AVX2_ONLY = {
    **ISA_CAP,
    "MKL_ENABLE_INSTRUCTIONS": "AVX2",
    "NPY_DISABLE_CPU_FEATURES": "X86_V4 AVX512_ICL AVX512_SPR",
    "OPENCV_CPU_DISABLE": "AVX512-SKX",
}
# outputs compared on the way, to say where a difference starts
STAGE_OUTPUTS = ("data/frames", "data/preprocessed", "data/split", "data/augmented", "data/ground_truth")


def run_pipeline(root: Path, capped: bool) -> float:
    """`dvc repro` of the learners' evaluations in root, with or without the AVX2 cap; seconds."""
    env = capped_environment(AVX2_ONLY, capped)
    dvc = str(Path(sys.executable).parent / "dvc")
    start = time.perf_counter()
    result = subprocess.run(
        [dvc, "repro", "--no-run-cache", *(f"evaluate@{learner}" for learner in LEARNERS)],
        cwd=root,
        env=env,
        capture_output=True,
        text=True,
    )
    if result.returncode != 0:
        raise SystemExit(f"dvc repro failed in {root} ({'capped' if capped else 'native'}):\n{result.stderr[-3000:]}")
    return time.perf_counter() - start


def digests(folder: Path) -> dict[str, str]:
    """relative path -> sha256 of every file under folder."""
    return {
        str(path.relative_to(folder)): hashlib.sha256(path.read_bytes()).hexdigest()
        for path in sorted(folder.rglob("*"))
        if path.is_file()
    }


def largest_descriptor_difference(native: Path, capped: Path) -> float:
    """The largest |difference| of two runs' descriptors, relative to the largest |descriptor|."""
    import numpy as np

    largest = 0.0
    for path in sorted(native.glob("*.npy")):
        first, second = np.load(path).astype(np.float64), np.load(capped / path.name).astype(np.float64)
        largest = max(largest, float(np.abs(first - second).max() / max(np.abs(first).max(), 1e-300)))
    return largest


def largest_metric_difference(native: Path, capped: Path) -> tuple[float, str]:
    """The largest |difference| of any number of two metrics files, and its key."""
    first, second = json.loads(native.read_text()), json.loads(capped.read_text())
    keys = [key for key, value in first.items() if isinstance(value, (int, float))]
    key = max(keys, key=lambda name: abs(first[name] - second[name]))
    return abs(first[key] - second[key]), key


def compare(native: Path, capped: Path) -> dict:
    """Per stage output and per learner: how many files are identical, and the largest metric change."""
    stages = {}
    for output in STAGE_OUTPUTS:
        a, b = digests(native / output), digests(capped / output)
        stages[output] = {"files": len(a), "differ": sorted(name for name in a if a[name] != b.get(name))}
    learners = {}
    for learner in LEARNERS:
        models = digests(native / "models" / learner), digests(capped / "models" / learner)
        features = digests(native / "data/features" / learner), digests(capped / "data/features" / learner)
        metrics = digests(native / "metrics/eval" / learner), digests(capped / "metrics/eval" / learner)
        differ = sorted(name for name in metrics[0] if metrics[0][name] != metrics[1].get(name))
        largest = [
            largest_metric_difference(
                native / "metrics/eval" / learner / name, capped / "metrics/eval" / learner / name
            )
            for name in differ
        ]
        learners[learner] = {
            "model_identical": models[0] == models[1],
            "features_identical": features[0] == features[1],
            "largest_relative_descriptor_difference": largest_descriptor_difference(
                native / "data/features" / learner, capped / "data/features" / learner
            ),
            "metrics_files": len(metrics[0]),
            "metrics_files_differ": differ,
            "largest_difference": max(largest, default=(0.0, None)),
        }
    return {"stage_outputs": stages, "learners": learners}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--keep", type=Path, help="run in DIR/native and DIR/capped and keep them")
    args = parser.parse_args()
    measured_on = machine()
    print(f"CPU: {measured_on['cpu']}; capped run: {' '.join(f'{k}={v}' for k, v in AVX2_ONLY.items())}")
    folder = Path(args.keep) if args.keep else Path(tempfile.mkdtemp(prefix="cross-blas-"))
    seconds = {}
    try:
        for name, capped in (("native", False), ("capped", True)):
            root = folder / name
            shutil.rmtree(root, ignore_errors=True)
            root.mkdir(parents=True)
            copy_repository(root)
            seconds[name] = run_pipeline(root, capped)
            print(f"  {name}: dvc repro of {', '.join(LEARNERS)} in {seconds[name]:.0f} s", flush=True)
        record = compare(folder / "native", folder / "capped")
    finally:
        if not args.keep:
            shutil.rmtree(folder, ignore_errors=True)
    for output, row in record["stage_outputs"].items():
        print(f"  {output}: {row['files'] - len(row['differ'])} of {row['files']} files identical")
    for learner, row in record["learners"].items():
        difference, key = row["largest_difference"]
        print(
            f"  {learner}: model {'identical' if row['model_identical'] else 'differs'}, descriptors "
            f"{'identical' if row['features_identical'] else 'differ'} (largest relative difference "
            f"{row['largest_relative_descriptor_difference']:.2g}), "
            f"{row['metrics_files'] - len(row['metrics_files_differ'])} of {row['metrics_files']} metrics files "
            "identical" + (f" (largest change: {key} by {difference:.4g})" if key else "")
        )
    same = [learner for learner, row in record["learners"].items() if not row["metrics_files_differ"]]
    headline = (
        f"metrics identical under this CPU's kernels and AVX2-only kernels for {len(same)} of "
        f"{len(LEARNERS)} learners ({', '.join(same) or 'none'})"
    )
    path = write_result(
        "check_cross_blas", {"avx2_only": AVX2_ONLY, "seconds": seconds, "headline": headline, **record}, measured_on
    )
    print(f"wrote {path}")
    print(f"HEADLINE: {headline}")
    sys.exit(0 if len(same) == len(LEARNERS) else 1)


def _check_cross_blas(path: Path) -> str:
    """benchmarks/machines/check_cross_blas.py's record: per learner, whether model, descriptors and every
    metrics file are the same under this CPU's kernels and an AVX2-only CPU's."""
    record = json.loads(path.read_text())
    lines = [
        f"`python -m benchmarks.machines.check_cross_blas` on {record['machine']['cpu']}, capped run with "
        + " ".join(f"`{key}={value}`" for key, value in record["avx2_only"].items())
        + ":",
        "",
        "| learner | model bytes | descriptors (largest relative difference) | metrics files identical |",
        "|---|---|---|---|",
    ]
    for learner, row in record["learners"].items():
        identical = row["metrics_files"] - len(row["metrics_files_differ"])
        lines.append(
            f"| {learner} | {'identical' if row['model_identical'] else 'differ'} | "
            f"{'identical' if row['features_identical'] else 'differ'} "
            f"({row['largest_relative_descriptor_difference']:.2g}) | {identical} of {row['metrics_files']} |"
        )
    stages = record["stage_outputs"]
    same = sum(row["files"] - len(row["differ"]) for row in stages.values())
    lines += [
        "",
        f"Data stages on the way ({', '.join(stages)}): {same} of {sum(r['files'] for r in stages.values())} files identical.",
    ]
    return "\n".join(lines) + "\n"


# docs/write_tables.py's table of this check's record: name -> (record, snapshot, how it is written)
TABLES = {"check_cross_blas": ("benchmarks/results/check_cross_blas.json", "check_cross_blas.json", _check_cross_blas)}


if __name__ == "__main__":
    main()
