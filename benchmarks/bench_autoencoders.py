"""FAE and CAE throughput at 32x64 with the registry's default params: training images/s (one
epoch through the learner's fit, after a one-batch warm-up) and inference images/s (describe, the
default descriptor), on the CPU and, when present, on CUDA side by side.

    python benchmarks/bench_autoencoders.py [--fae-images 4096] [--cae-images 64]

Writes benchmarks/results/bench_autoencoders.json; the headline line is printed last.
"""

from __future__ import annotations

import argparse

import torch

from _common import HEIGHT, WIDTH, load_note, machine, timed, training_images, write_result
from seasonloop.models.registry import get_learner


def parse_args() -> argparse.Namespace:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--fae-images", type=int, default=4096, help="training/inference images for the FAE on the CPU")
    parser.add_argument("--cae-images", type=int, default=64,
                        help="training/inference images for the CAE on the CPU (~9 GMAC per image forward)")
    parser.add_argument("--cuda-scale", type=int, default=16, help="CUDA runs use this many times more images")
    parser.add_argument("--seed", type=int, default=0)
    return parser.parse_args()


def synchronised(function, device: str):
    """function(), then wait for queued CUDA work so the wall time covers it."""
    result = function()
    if device == "cuda":
        torch.cuda.synchronize()
    return result


def throughput(name: str, device: str, n_images: int, seed: int) -> dict[str, float]:
    """Training and inference images/s of learner `name` with its defaults on `device`."""
    images, _ = training_images(n_images, seed)
    learner_class = get_learner(name)
    # One epoch over exactly these images; everything else as the registry's defaults.
    params = {**learner_class.defaults, "epochs": 1, "max_train_images": 0, "device": device}
    # Warm-up on one batch (CUDA context, kernel / oneDNN primitive creation) before timing.
    learner_class(params, seed=seed).fit(images[: params["batch_size"]], progress=False)
    learner = learner_class(params, seed=seed)
    _, train_seconds = timed(lambda: synchronised(lambda: learner.fit(images, progress=False), device))
    learner.describe(images[:8], batch_size=8)
    _, describe_seconds = timed(lambda: synchronised(lambda: learner.describe(images, batch_size=256), device))
    return {
        "n_images": n_images,
        "batch_size": params["batch_size"],
        "train_images_per_s": n_images / train_seconds,
        "describe_images_per_s": n_images / describe_seconds,
        "train_seconds": train_seconds,
        "describe_seconds": describe_seconds,
    }


def main() -> None:
    args = parse_args()
    measured_on = machine()
    devices = ["cpu"] + (["cuda"] if torch.cuda.is_available() else [])
    if "cuda" not in devices:
        print("CUDA not available: CPU only (CUDA figures skipped)")
    print(f"{HEIGHT}x{WIDTH} images; torch threads {torch.get_num_threads()}")
    results: dict[str, dict[str, dict[str, float]]] = {}
    for name, n_images in (("fae", args.fae_images), ("cae", args.cae_images)):
        results[name] = {}
        for device in devices:
            count = n_images * (args.cuda_scale if device == "cuda" else 1)
            figures = throughput(name, device, count, args.seed)
            results[name][device] = figures
            print(f"  {name} on {device:4s}: train {figures['train_images_per_s']:9.1f} images/s, "
                  f"describe {figures['describe_images_per_s']:9.1f} images/s "
                  f"({count} images, batch {figures['batch_size']}, default params)")
        if "cuda" in results[name]:
            print(f"  {name} CUDA / CPU: train {results[name]['cuda']['train_images_per_s'] / results[name]['cpu']['train_images_per_s']:.1f}x, "
                  f"describe {results[name]['cuda']['describe_images_per_s'] / results[name]['cpu']['describe_images_per_s']:.1f}x")

    note = load_note(measured_on)
    path = write_result("bench_autoencoders", {"args": vars(args), "results": results, "load_note": note}, measured_on)
    print(f"wrote {path}")
    if note:
        print(note)
    best = "cuda" if "cuda" in devices else "cpu"
    print("HEADLINE: " + "; ".join(
        f"{name} on {best}: train {results[name][best]['train_images_per_s']:.1f} images/s, "
        f"describe {results[name][best]['describe_images_per_s']:.1f} images/s"
        for name in results
    ))


if __name__ == "__main__":
    main()
