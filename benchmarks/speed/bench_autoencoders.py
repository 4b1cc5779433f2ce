"""FAE and CAE (Table 5) speed and quality in every way of running them, side by side in one run:
training and inference images/s at 32x64 through the learners' own fit and describe: float32 vs
bfloat16 autocast, contiguous vs channels_last activations, batch size, and torch.compile for the
CAE, at Table 5's width and at the default run's (`--cae-widths`), on the CPU and, when present,
on CUDA; then the quality check: validation loss after the same number of epochs from the same
seed in each variant, and the fraction correct on summer-fall.

    python -m benchmarks.speed.bench_autoencoders [--fae-images 4096] [--cae-images 64] [--cae-widths 1,0.0625]
        [--plateau-images 2048]

A speed-up counts only at equal quality (validation loss within 2% relative of the float32
reference after the same epochs from the same seed). Where the CPU has no bfloat16 units torch
emulates bfloat16, several times slower than float32; the bfloat16 throughput is then measured on
fewer images and its quality check is skipped. `--plateau-images N` adds the strict comparison:
the CAE trained in float32 and in bfloat16 (where the CPU has the units) to its validation plateau
on N images with the pipeline's stopping rule, timed, with its best validation loss and fraction
correct. Writes benchmarks/results/bench_autoencoders.json; the headline line is printed last.
"""

from __future__ import annotations

import argparse
import json
import os
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import torch

from benchmarks.common import HEIGHT, WIDTH, load_note, pair_images, timed, training_images
from seasonloop.ablations.cae_widths import width_channels, width_label
from seasonloop.evaluation.distances import distance_matrix
from seasonloop.evaluation.metrics import evaluate_pair
from seasonloop.models.core.arithmetic import cpu_has_native_bfloat16
from seasonloop.models.core.lookup import get_learner
from tools.records import machine, write_result
from tools.repository import learner_params


@dataclass(frozen=True)
class Variant:
    """One way of running a network: autocast precision, activation layout, batch size, torch.compile."""

    precision: str = "float32"
    channels_last: bool = False
    batch_size: int = 0  # 0: the learner's default
    compiled: bool = False

    @property
    def label(self) -> str:
        return " + ".join(
            [self.precision]
            + (["channels_last"] if self.channels_last else [])
            + ([f"batch {self.batch_size}"] if self.batch_size else [])
            + (["compile"] if self.compiled else [])
        )


# variants per network; the first is the float32 reference
VARIANTS = {
    "fae": [Variant(), Variant("bfloat16")],
    "cae": [
        Variant(),
        Variant(channels_last=True),
        Variant(channels_last=True, batch_size=128),
        Variant(channels_last=True, compiled=True),
        Variant("bfloat16"),
        Variant("bfloat16", channels_last=True),
        Variant("bfloat16", channels_last=True, compiled=True),
    ],
}
QUALITY_TOLERANCE = 0.02  # relative validation-loss difference that still counts as equal quality
GOALS = {"train": 8.0, "describe": 10.0}  # the CAE's speed-up goals over float32


def parse_args() -> argparse.Namespace:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--fae-images", type=int, default=4096, help="images timed for the FAE on the CPU")
    parser.add_argument(
        "--cae-images",
        type=int,
        default=64,
        help="images timed for the CAE on the CPU (~9 GMAC each at width 1; scaled by 1/width^2)",
    )
    parser.add_argument(
        "--cae-widths",
        default="1,0.0625",
        help="CAE widths, fractions of Table 5's channels (1: Table 5; 0.0625: the default run's)",
    )
    parser.add_argument(
        "--emulated-images", type=int, default=16, help="CAE images timed in bfloat16 on a CPU that only emulates it"
    )
    parser.add_argument("--quality-images", type=int, default=256, help="training images of the quality check")
    parser.add_argument("--quality-epochs", type=int, default=3, help="epochs of the quality check (no early stop)")
    parser.add_argument(
        "--pair-places", type=int, default=0, help="test places of summer-fall in the quality check (0: all)"
    )
    parser.add_argument("--cuda-scale", type=int, default=16, help="CUDA runs use this many times more images")
    parser.add_argument(
        "--plateau-images",
        type=int,
        default=0,
        help="also train the CAE of each width in float32 and in bfloat16 (channels_last, where "
        "the CPU has bfloat16 units) to its validation plateau on this many images and compare "
        "time, best validation loss and fraction correct (0: skip)",
    )
    parser.add_argument("--seed", type=int, default=0)
    return parser.parse_args()


def native_bfloat16(device: str) -> bool:
    return torch.cuda.is_bf16_supported() if device == "cuda" else cpu_has_native_bfloat16()


def learner_for(name: str, variant: Variant, device: str, seed: int, **params):
    if variant.batch_size:
        params["batch_size"] = variant.batch_size
    learner = get_learner(name)(
        learner_params(name, {"precision": variant.precision, "device": device, "max_train_images": 0, **params}),
        seed=seed,
    )
    learner.channels_last = variant.channels_last  # the class's choice, overridden to measure both
    if variant.compiled:
        build = learner._seeded_model

        def compiled_model():
            # encoder and decoder compiled apart: describe runs them one at a time
            model = build()
            model.encoder, model.decoder = torch.compile(model.encoder), torch.compile(model.decoder)
            return model

        learner._seeded_model = compiled_model
    return learner


def synchronised(function, device: str):
    """function(), then wait for queued CUDA work so the wall time covers it."""
    result = function()
    if device == "cuda":
        torch.cuda.synchronize()
    return result


def throughput(name: str, variant: Variant, device: str, images: np.ndarray, seed: int, **params) -> dict:
    """Training images/s (one epoch of fit, validated on 2 images) and inference images/s (describe)."""
    places = np.arange(len(images))
    one_epoch = {"max_epochs": 1, "max_validation_images": 2, "validation_block": 1, **params}
    batch = variant.batch_size or learner_params(name)["batch_size"]
    # warm-up on one batch: CUDA context, oneDNN primitive creation (torch.compile compiles on
    # its first call, so the timed fit below reuses nothing: its compile time is in the figure
    # unless the warm-up's compiled kernels are cached, which inductor does on disk)
    learner_for(name, variant, device, seed, **one_epoch).fit(
        images[: batch + 2], progress=False, places=places[: batch + 2]
    )
    learner = learner_for(name, variant, device, seed, **one_epoch)
    info = synchronised(lambda: learner.fit(images, progress=False, places=places), device)
    learner.describe(images[:8], batch_size=8)
    _, describe_seconds = timed(lambda: synchronised(lambda: learner.describe(images, batch_size=256), device))
    return {
        "n_images": len(images),
        "batch_size": batch,
        "train_images_per_s": info["n_train_images"] / info["training_seconds"],
        "describe_images_per_s": len(images) / describe_seconds,
    }


def quality(
    name: str,
    variant: Variant,
    device: str,
    images: np.ndarray,
    pair: tuple[np.ndarray, np.ndarray, np.ndarray],
    epochs: int,
    seed: int,
    **params,
) -> dict:
    """Validation loss after `epochs` epochs from `seed` (no early stop) and summer-fall fraction correct."""
    learner = learner_for(
        name, variant, device, seed, max_epochs=epochs, patience=epochs + 1, max_validation_images=0, **params
    )
    info = learner.fit(images, progress=False, places=np.arange(len(images)))
    return {
        "final_validation_loss": info["validation_loss_per_epoch"][-1],
        "fraction_correct": pair_correct(learner, pair),
    }


def pair_correct(learner, pair: tuple[np.ndarray, np.ndarray, np.ndarray]) -> float:
    """Single-image fraction correct of a fitted learner on pair = (database, queries, places), cosine."""
    database, queries, places = pair
    distances = distance_matrix(learner.describe(database), learner.describe(queries), metric="cosine")
    return evaluate_pair(distances, places, places, tolerance=0, confidence="distance")[0]["fraction_correct"]


def networks(args: argparse.Namespace) -> list[tuple[str, str, dict, int]]:
    """(result key, learner name, extra params, images timed on the CPU) of each network measured."""
    rows = [("fae", "fae", {}, args.fae_images)]
    for width in (float(text) for text in args.cae_widths.split(",")):
        key = "cae" if width == 1 else f"cae {width_label(width)}"
        # the same seconds of timing at any width: the cost goes as width^2
        count = max(args.cae_images, min(64 * args.cae_images, round(args.cae_images / width**2)))
        rows.append((key, "cae", {"channels": width_channels(width)}, count))
    return rows


def measure(
    name: str, params: dict, count: int, device: str, args: argparse.Namespace, quality_images: np.ndarray, pair: tuple
) -> dict:
    """Every variant of one network on one device: throughput, quality, speed-up over the first."""
    scale = args.cuda_scale if device == "cuda" else 1
    runs = {}
    for variant in VARIANTS[name]:
        emulated = variant.precision == "bfloat16" and not native_bfloat16(device)
        images, _ = training_images(
            (min(count, args.emulated_images) if emulated and name == "cae" else count) * scale, args.seed
        )
        run = throughput(name, variant, device, images, args.seed, **params)
        # quality is checked where a variant could be chosen: not for emulated bfloat16
        run["quality"] = (
            None
            if emulated
            else quality(name, variant, device, quality_images, pair, args.quality_epochs, args.seed, **params)
        )
        run["emulated_bfloat16"] = emulated
        runs[variant.label] = run
    reference = runs[VARIANTS[name][0].label]
    for run in runs.values():
        run["speedup_vs_float32"] = {
            key: run[f"{key}_images_per_s"] / reference[f"{key}_images_per_s"] for key in GOALS
        }
        if run["quality"] is not None:
            run["quality"]["validation_loss_change"] = (
                run["quality"]["final_validation_loss"] / reference["quality"]["final_validation_loss"] - 1
            )
    return runs


def to_plateau(params: dict, args: argparse.Namespace, pair: tuple) -> dict:
    """float32 vs bfloat16 (channels_last), each trained to its validation plateau with the pipeline's
    stopping rule: the speed-up at equal quality in the strict sense (both converged)."""
    images, _ = training_images(args.plateau_images, args.seed)
    places = np.arange(len(images)) // 2  # pairs of images share a place, as original and augmented copy
    runs = {}
    for precision in ("float32", "bfloat16"):
        if precision == "bfloat16" and not cpu_has_native_bfloat16():
            continue
        learner = learner_for(
            "cae",
            Variant(precision, channels_last=True),
            "cpu",
            args.seed,
            max_validation_images=256,
            max_epochs=300,
            **params,
        )
        info = learner.fit(images, progress=False, places=places)
        runs[precision] = {
            key: info[key]
            for key in ("converged", "stop_reason", "epochs_run", "best_validation_loss", "training_seconds")
        } | {"fraction_correct": pair_correct(learner, pair)}
    return runs


def verdict(run: dict) -> str:
    if run["quality"] is None:
        return "quality not checked (bfloat16 emulated on this CPU)"
    change = run["quality"]["validation_loss_change"]
    return (
        f"validation loss {run['quality']['final_validation_loss']:.5f} ({change:+.2%}, "
        f"{'equal' if abs(change) <= QUALITY_TOLERANCE else 'NOT equal'} quality), summer-fall "
        f"{100 * run['quality']['fraction_correct']:.1f}% correct"
    )


def main() -> None:
    args = parse_args()
    measured_on = machine()
    devices = ["cpu"] + (["cuda"] if torch.cuda.is_available() else [])
    print(
        f"{HEIGHT}x{WIDTH} images; {measured_on['cpu']}; torch threads "
        f"{torch.get_num_threads()}; native bfloat16 on this CPU: {cpu_has_native_bfloat16()}; "
        f"ATEN_CPU_CAPABILITY={os.environ.get('ATEN_CPU_CAPABILITY', '(unset)')}, "
        f"ONEDNN_MAX_CPU_ISA={os.environ.get('ONEDNN_MAX_CPU_ISA', '(unset)')}"
        + ("" if "cuda" in devices else "; CUDA not available (CUDA figures skipped)")
    )
    pair = tuple(array[: args.pair_places or None] for array in pair_images("summer", "fall", args.seed)[:3])
    quality_images, _ = training_images(args.quality_images, args.seed + 1)
    results: dict = {}
    for key, name, params, count in networks(args):
        for device in devices:
            runs = results.setdefault(key, {})[device] = measure(
                name, params, count, device, args, quality_images, pair
            )
            for label, run in runs.items():
                speedup = run["speedup_vs_float32"]
                print(
                    f"  {key:8s} on {device:4s} {label:45s}: train {run['train_images_per_s']:8.1f} images/s "
                    f"({speedup['train']:.2f}x), describe {run['describe_images_per_s']:8.1f} images/s "
                    f"({speedup['describe']:.2f}x) [{run['n_images']} images]; {verdict(run)}",
                    flush=True,
                )

    if args.plateau_images:
        for key, name, params, _ in networks(args):
            if name != "cae":
                continue
            runs = results[key]["cpu_to_plateau"] = to_plateau(params, args, pair)
            for precision, run in runs.items():
                print(
                    f"  {key:8s} to its plateau in {precision:8s} ({args.plateau_images} images): "
                    f"{run['training_seconds']:.0f} s, {run['epochs_run']} epochs, converged {run['converged']}, best "
                    f"validation loss {run['best_validation_loss']:.5f}, summer-fall {100 * run['fraction_correct']:.1f}%",
                    flush=True,
                )
            if len(runs) == 2:
                print(
                    f"  {key:8s} to its plateau: bfloat16 {runs['float32']['training_seconds'] / runs['bfloat16']['training_seconds']:.2f}x "
                    f"float32's speed, best validation loss {runs['bfloat16']['best_validation_loss'] / runs['float32']['best_validation_loss'] - 1:+.1%}"
                )

    note = load_note(measured_on)
    path = write_result("bench_autoencoders", {"args": vars(args), "results": results, "load_note": note}, measured_on)
    print(f"wrote {path}")
    if note:
        print(note)
    device = devices[-1]
    for key in (key for key in results if key.startswith("cae")):
        checked = {
            label: run
            for label, run in results[key][device].items()
            if run["quality"] is not None and abs(run["quality"]["validation_loss_change"]) <= QUALITY_TOLERANCE
        }
        best = max(checked, key=lambda label: checked[label]["speedup_vs_float32"]["train"])
        speedup = checked[best]["speedup_vs_float32"]
        print(
            f"HEADLINE: {key} on {device}, fastest at equal quality ({best}; validation loss within "
            f"{QUALITY_TOLERANCE:.0%} after {args.quality_epochs} epochs from the same seed): train "
            f"{speedup['train']:.2f}x and describe {speedup['describe']:.2f}x float32 contiguous (goals "
            f"{GOALS['train']:.0f}x / {GOALS['describe']:.0f}x: "
            + ", ".join(
                f"{goal_key} {'met' if speedup[goal_key] >= goal else 'not met'}" for goal_key, goal in GOALS.items()
            )
            + ")"
        )


def _bench_autoencoders(path: Path) -> str:
    """benchmarks/speed/bench_autoencoders.py's record: one row per network and variant, then the
    to-the-plateau comparison where the run made it."""
    record = json.loads(path.read_text())
    args = record["args"]
    lines = [
        f"`python -m benchmarks.speed.bench_autoencoders --fae-images {args['fae_images']} --cae-images "
        f"{args['cae_images']} --cae-widths {args['cae_widths']} --quality-images {args['quality_images']} "
        f"--quality-epochs {args['quality_epochs']} --pair-places {args['pair_places']}"
        + (f" --plateau-images {args['plateau_images']}" if args.get("plateau_images") else "")
        + f"` on {record['machine']['cpu']}, {record['machine']['torch_threads']} threads"
        + (f" ({record['load_note']})" if record.get("load_note") else "")
        + ":",
        "",
        "| network | variant | train images/s | describe images/s | train / describe vs float32 | "
        f"validation loss after {args['quality_epochs']} epoch(s) (vs float32) | summer-fall % |",
        "|---|---|---|---|---|---|---|",
    ]
    # the FAE first, and in each network the float32 reference first (the JSON's keys are sorted)
    for network, devices in sorted(record["results"].items(), key=lambda item: (item[0] != "fae", item[0])):
        for device, runs in devices.items():
            if device.endswith("to_plateau"):
                continue
            for variant, run in sorted(runs.items(), key=lambda item: (not item[0].startswith("float32"), item[0])):
                quality = run["quality"]
                checked = (
                    "not checked (emulated)"
                    if quality is None
                    else (f"{quality['final_validation_loss']:.5f} ({quality['validation_loss_change']:+.1%})")
                )
                correct = "" if quality is None else f"{100 * quality['fraction_correct']:.1f}"
                lines.append(
                    f"| {network} ({device}) | {variant} | {run['train_images_per_s']:.1f} | "
                    f"{run['describe_images_per_s']:.1f} | {run['speedup_vs_float32']['train']:.2f}x / "
                    f"{run['speedup_vs_float32']['describe']:.2f}x | {checked} | {correct} |"
                )
    plateau = {
        network: devices["cpu_to_plateau"]
        for network, devices in record["results"].items()
        if "cpu_to_plateau" in devices
    }
    if plateau:
        lines += [
            "",
            f"Each trained to its validation plateau on {args['plateau_images']} images (the pipeline's "
            "stopping rule), channels_last:",
            "",
            "| network | precision | seconds | epochs | converged | best validation loss | summer-fall % |",
            "|---|---|---|---|---|---|---|",
        ]
        for network, runs in plateau.items():
            for precision, run in sorted(runs.items(), key=lambda item: item[0] != "float32"):
                lines.append(
                    f"| {network} | {precision} | {run['training_seconds']:.0f} | {run['epochs_run']} | "
                    f"{str(run['converged']).lower()} | {run['best_validation_loss']:.5f} | "
                    f"{100 * run['fraction_correct']:.1f} |"
                )
    return "\n".join(lines) + "\n"


# docs/write_tables.py's tables of this benchmark's record: name -> (record, its snapshot in
# docs/results/, how it is written); three runs (the record is rewritten by each): Table 5's width,
# the default width, and the default width trained to its plateau in float32 and bfloat16
TABLES = {
    "bench_autoencoders_table5": (
        "benchmarks/results/bench_autoencoders.json",
        "bench_autoencoders_table5.json",
        _bench_autoencoders,
    ),
    "bench_autoencoders_width16": (
        "benchmarks/results/bench_autoencoders.json",
        "bench_autoencoders_width16.json",
        _bench_autoencoders,
    ),
    "bench_autoencoders_plateau": (
        "benchmarks/results/bench_autoencoders.json",
        "bench_autoencoders_plateau.json",
        _bench_autoencoders,
    ),
}


if __name__ == "__main__":
    main()
