"""FAE and CAE (Table 5) speed and quality in every precision and memory format, side by side in
one run: training and inference images/s at 32x64 through the learners' own fit and describe
(float32 vs bfloat16 autocast, and contiguous vs channels_last for the CAE), on the CPU and, when
present, on CUDA; then the quality check: validation loss after the same number of steps from the
same seed in each variant, and the fraction correct on summer-fall.

    python benchmarks/bench_autoencoders.py [--fae-images 4096] [--cae-images 64]

A speed-up counts only at equal quality (validation loss within 2% relative of float32, same
fraction correct). Where the CPU has no bfloat16 units torch emulates bfloat16, several times
slower than float32; the bfloat16 throughput is then measured on fewer images and its quality
check is skipped (precision 'auto' uses float32 there). Writes benchmarks/results/bench_autoencoders.json;
the headline line is printed last.
"""

from __future__ import annotations

import argparse

import numpy as np
import torch

from _common import HEIGHT, WIDTH, load_note, machine, pair_images, timed, training_images, write_result
from seasonloop.matching import distance_matrix
from seasonloop.metrics import evaluate_pair
from seasonloop.models._training import cpu_has_native_bfloat16
from seasonloop.models.registry import get_learner

# (precision, channels_last) variants per network; the first is the float32 reference
VARIANTS = {
    "fae": [("float32", False), ("bfloat16", False)],
    "cae": [("float32", False), ("float32", True), ("bfloat16", False), ("bfloat16", True)],
}
QUALITY_TOLERANCE = 0.02  # relative validation-loss difference that still counts as equal quality
GOALS = {"train": 8.0, "describe": 10.0}  # the CAE's speed-up goals over float32


def parse_args() -> argparse.Namespace:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--fae-images", type=int, default=4096, help="images timed for the FAE on the CPU")
    parser.add_argument("--cae-images", type=int, default=64, help="images timed for the CAE on the CPU (~9 GMAC each)")
    parser.add_argument("--emulated-images", type=int, default=16,
                        help="CAE images timed in bfloat16 on a CPU that only emulates it")
    parser.add_argument("--quality-images", type=int, default=256, help="training images of the quality check")
    parser.add_argument("--quality-epochs", type=int, default=3, help="epochs of the quality check (no early stop)")
    parser.add_argument("--pair-places", type=int, default=0,
                        help="test places of summer-fall in the quality check (0: all)")
    parser.add_argument("--cuda-scale", type=int, default=16, help="CUDA runs use this many times more images")
    parser.add_argument("--seed", type=int, default=0)
    return parser.parse_args()


def native_bfloat16(device: str) -> bool:
    return torch.cuda.is_bf16_supported() if device == "cuda" else cpu_has_native_bfloat16()


def learner_for(name: str, precision: str, channels_last: bool, device: str, seed: int, **params):
    learner = get_learner(name)({"precision": precision, "device": device, "max_train_images": 0, **params}, seed=seed)
    learner.channels_last = channels_last  # the class's choice, overridden to measure both
    return learner


def synchronised(function, device: str):
    """function(), then wait for queued CUDA work so the wall time covers it."""
    result = function()
    if device == "cuda":
        torch.cuda.synchronize()
    return result


def throughput(name: str, precision: str, channels_last: bool, device: str, images: np.ndarray, seed: int) -> dict:
    """Training images/s (one epoch of fit, validated on 2 images) and inference images/s (describe)."""
    places = np.arange(len(images))
    one_epoch = {"max_epochs": 1, "max_validation_images": 2, "validation_block": 1}
    batch = get_learner(name).defaults["batch_size"]
    # warm-up on one batch: CUDA context, oneDNN primitive creation
    learner_for(name, precision, channels_last, device, seed, **one_epoch).fit(
        images[: batch + 2], progress=False, places=places[: batch + 2])
    learner = learner_for(name, precision, channels_last, device, seed, **one_epoch)
    info = synchronised(lambda: learner.fit(images, progress=False, places=places), device)
    learner.describe(images[:8], batch_size=8)
    _, describe_seconds = timed(lambda: synchronised(lambda: learner.describe(images, batch_size=256), device))
    return {"n_images": len(images), "batch_size": batch,
            "train_images_per_s": info["n_train_images"] / info["training_seconds"],
            "describe_images_per_s": len(images) / describe_seconds}


def quality(name: str, precision: str, channels_last: bool, device: str, images: np.ndarray,
            pair: tuple[np.ndarray, np.ndarray, np.ndarray], epochs: int, seed: int) -> dict:
    """Validation loss after `epochs` epochs from `seed` (no early stop) and summer-fall fraction correct."""
    learner = learner_for(name, precision, channels_last, device, seed, max_epochs=epochs, patience=epochs + 1,
                          max_validation_images=0)
    info = learner.fit(images, progress=False, places=np.arange(len(images)))
    database, queries, places = pair
    distances = distance_matrix(learner.describe(database), learner.describe(queries), metric="cosine")
    metrics, _ = evaluate_pair(distances, places, places, tolerance=0, confidence="distance")
    return {"final_validation_loss": info["validation_loss_per_epoch"][-1], "fraction_correct": metrics["fraction_correct"]}


def label(precision: str, channels_last: bool) -> str:
    return precision + (" + channels_last" if channels_last else "")


def main() -> None:
    args = parse_args()
    measured_on = machine()
    devices = ["cpu"] + (["cuda"] if torch.cuda.is_available() else [])
    print(f"{HEIGHT}x{WIDTH} images; torch threads {torch.get_num_threads()}; "
          f"native bfloat16 on this CPU: {cpu_has_native_bfloat16()}"
          + ("" if "cuda" in devices else "; CUDA not available (CUDA figures skipped)"))
    pair = tuple(array[: args.pair_places or None] for array in pair_images("summer", "fall", args.seed)[:3])
    quality_images, _ = training_images(args.quality_images, args.seed + 1)
    results: dict = {}
    for name, sizes in (("fae", args.fae_images), ("cae", args.cae_images)):
        for device in devices:
            scale = args.cuda_scale if device == "cuda" else 1
            runs = results.setdefault(name, {}).setdefault(device, {})
            for precision, channels_last in VARIANTS[name]:
                emulated = precision == "bfloat16" and not native_bfloat16(device)
                count = (args.emulated_images if emulated and name == "cae" else sizes) * scale
                images, _ = training_images(count, args.seed)
                run = throughput(name, precision, channels_last, device, images, args.seed)
                # quality is checked where a variant could be chosen: not for emulated bfloat16
                run["quality"] = None if emulated else quality(
                    name, precision, channels_last, device, quality_images, pair, args.quality_epochs, args.seed)
                run["emulated_bfloat16"] = emulated
                runs[label(precision, channels_last)] = run
            reference = runs[label(*VARIANTS[name][0])]
            for variant, run in runs.items():
                speedup = {key: run[f"{key}_images_per_s"] / reference[f"{key}_images_per_s"] for key in GOALS}
                run["speedup_vs_float32"] = speedup
                if run["quality"] is None:
                    verdict = "quality not checked (bfloat16 emulated: auto uses float32 here)"
                else:
                    loss_change = run["quality"]["final_validation_loss"] / reference["quality"]["final_validation_loss"] - 1
                    run["quality"]["validation_loss_change"] = loss_change
                    equal = abs(loss_change) <= QUALITY_TOLERANCE
                    verdict = (f"validation loss {run['quality']['final_validation_loss']:.5f} ({loss_change:+.2%}, "
                               f"{'equal' if equal else 'NOT equal'} quality), summer-fall "
                               f"{100 * run['quality']['fraction_correct']:.1f}% correct")
                print(f"  {name} on {device:4s} {variant:27s}: train {run['train_images_per_s']:8.1f} images/s "
                      f"({speedup['train']:.2f}x), describe {run['describe_images_per_s']:8.1f} images/s "
                      f"({speedup['describe']:.2f}x) [{run['n_images']} images]; {verdict}")

    note = load_note(measured_on)
    path = write_result("bench_autoencoders", {"args": vars(args), "results": results, "load_note": note}, measured_on)
    print(f"wrote {path}")
    if note:
        print(note)
    device = devices[-1]
    checked = {variant: run for variant, run in results["cae"][device].items() if run["quality"] is not None
               and abs(run["quality"].get("validation_loss_change", 0.0)) <= QUALITY_TOLERANCE}
    best = max(checked, key=lambda variant: checked[variant]["speedup_vs_float32"]["train"])
    speedup = checked[best]["speedup_vs_float32"]
    print(f"HEADLINE: cae on {device}, fastest at equal quality ({best}, {args.quality_epochs} epochs from the same "
          f"seed in each): train {speedup['train']:.2f}x and describe {speedup['describe']:.2f}x float32 "
          f"(goals {GOALS['train']:.0f}x / {GOALS['describe']:.0f}x: "
          + ", ".join(f"{key} {'met' if speedup[key] >= goal else 'not met'}" for key, goal in GOALS.items()) + ")")


if __name__ == "__main__":
    main()
