"""Do the auto-encoders give the same bytes on every CPU? Fit each one in a fresh process per
instruction set and precision, then compare the weights.

Torch picks its CPU kernels by the instruction set it finds (AVX2, AVX512, AMX), and kernels of
another vector width sum in another order. This script emulates an older CPU on this one by
capping the instruction set (ATEN_CPU_CAPABILITY=avx2 ONEDNN_MAX_CPU_ISA=AVX2
MKL_ENABLE_INSTRUCTIONS=AVX2) and fits the FAE
and the CAE (the default run's width, on a few hundred images for a few epochs from the same seed)
in float32 and in bfloat16, capped and uncapped, each in its own process (the variables are read
once, at start-up). It prints, per learner and precision, whether the weights are byte-identical
across the instruction sets, and how far apart they and their validation losses are.

    python -m benchmarks.machines.check_cross_isa [--images 512] [--epochs 3]

Writes benchmarks/results/check_cross_isa.json; the headline line is printed last.
"""

from __future__ import annotations

import argparse
import hashlib
import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

from tools.repository import learner_params

# torch's own kernels, oneDNN's (convolutions) and MKL's (the FAE's matrix products)
CAPPED = {"ATEN_CPU_CAPABILITY": "avx2", "ONEDNN_MAX_CPU_ISA": "AVX2", "MKL_ENABLE_INSTRUCTIONS": "AVX2"}
LEARNERS = {"fae": {}, "cae": {"channels": [6, 16, 24], "batch_size": 32}}
PRECISIONS = ("float32", "bfloat16")


def fit_once(name: str, precision: str, images: int, epochs: int, out: Path) -> None:
    """(child process) fit one learner and save its weights as .npz with its losses."""
    import torch

    from benchmarks.common import training_images
    from seasonloop.models.core.lookup import get_learner

    data, _ = training_images(images, seed=0)
    params = {
        **LEARNERS[name],
        "precision": precision,
        "max_epochs": epochs,
        "patience": epochs + 1,
        "max_validation_images": 0,
        "device": "cpu",
    }
    learner = get_learner(name)(learner_params(name, params), seed=0)
    info = learner.fit(data, progress=False, places=np.arange(len(data)) // 2)
    weights = {key: value.detach().float().numpy() for key, value in learner.model.state_dict().items()}
    np.savez(out, **weights)
    out.with_suffix(".json").write_text(
        json.dumps(
            {
                "validation_loss": info["validation_loss_per_epoch"],
                "precision": info["precision"],
                "cpu_capability": torch.backends.cpu.get_cpu_capability(),
            }
        )
    )


def run_child(name: str, precision: str, capped: bool, args: argparse.Namespace, folder: Path) -> dict:
    out = folder / f"{name}-{precision}-{'capped' if capped else 'native'}.npz"
    env = {key: value for key, value in os.environ.items() if key not in CAPPED}
    if capped:
        env.update(CAPPED)
    subprocess.run(
        [
            sys.executable,
            "-m",
            __spec__.name,
            "--child",
            name,
            precision,
            str(out),
            "--images",
            str(args.images),
            "--epochs",
            str(args.epochs),
        ],
        env=env,
        check=True,
    )
    weights = dict(np.load(out))
    digest = hashlib.sha256(b"".join(weights[key].tobytes() for key in sorted(weights))).hexdigest()
    return {"weights": weights, "sha256": digest, **json.loads(out.with_suffix(".json").read_text())}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--images", type=int, default=512, help="training images (validation: 10%% of the places)")
    parser.add_argument("--epochs", type=int, default=3)
    parser.add_argument("--child", nargs=3, metavar=("LEARNER", "PRECISION", "OUT"), help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.child:
        name, precision, out = args.child
        fit_once(name, precision, args.images, args.epochs, Path(out))
        return
    from tools.records import machine, write_result

    measured_on = machine()
    print(f"CPU: {measured_on['cpu']}; {args.images} images, {args.epochs} epochs from seed 0")
    results, identical = {}, {}
    with tempfile.TemporaryDirectory() as folder:
        for name in LEARNERS:
            for precision in PRECISIONS:
                native = run_child(name, precision, False, args, Path(folder))
                capped = run_child(name, precision, True, args, Path(folder))
                largest = max(
                    float(np.max(np.abs(native["weights"][key] - capped["weights"][key]))) for key in native["weights"]
                )
                same = native["sha256"] == capped["sha256"]
                identical[f"{name} {precision}"] = same
                results[f"{name} {precision}"] = {
                    "identical": same,
                    "largest_weight_difference": largest,
                    "validation_loss": {"native": native["validation_loss"], "capped": capped["validation_loss"]},
                    "cpu_capability": {"native": native["cpu_capability"], "capped": capped["cpu_capability"]},
                    "precision_run": {"native": native["precision"], "capped": capped["precision"]},
                }
                print(
                    f"  {name} {precision:8s}: kernels {native['cpu_capability']} vs {capped['cpu_capability']}: "
                    f"weights {'byte-identical' if same else 'differ'} (largest difference {largest:.3g}); "
                    f"final validation loss {native['validation_loss'][-1]:.6f} vs {capped['validation_loss'][-1]:.6f}",
                    flush=True,
                )
    path = write_result(
        "check_cross_isa", {"args": {"images": args.images, "epochs": args.epochs}, "results": results}, measured_on
    )
    print(f"wrote {path}")
    print(
        "HEADLINE: same bytes across the instruction sets of this CPU: "
        + ", ".join(f"{key} {'yes' if same else 'no'}" for key, same in identical.items())
    )


def _check_cross_isa(path: Path) -> str:
    record = json.loads(path.read_text())
    lines = [
        f"`python -m benchmarks.machines.check_cross_isa --images {record['args']['images']} --epochs "
        f"{record['args']['epochs']}` on {record['machine']['cpu']}:",
        "",
        "| learner and precision | kernels (uncapped / capped) | weights byte-identical | largest weight "
        "difference | final validation loss (uncapped / capped) |",
        "|---|---|---|---|---|",
    ]
    for name, row in record["results"].items():
        loss = row["validation_loss"]
        lines.append(
            f"| {name} | {row['cpu_capability']['native']} / {row['cpu_capability']['capped']} | "
            f"{'yes' if row['identical'] else 'no'} | {row['largest_weight_difference']:.2g} | "
            f"{loss['native'][-1]:.6f} / {loss['capped'][-1]:.6f} |"
        )
    return "\n".join(lines) + "\n"


# docs/write_tables.py's table of this check's record: name -> (record, snapshot, how it is written)
TABLES = {"check_cross_isa": ("benchmarks/results/check_cross_isa.json", "check_cross_isa.json", _check_cross_isa)}


if __name__ == "__main__":
    main()
