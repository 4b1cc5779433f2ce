"""What the auto-encoders' training settings cost and give: each learner trained to its validation
plateau (the pipeline's stopping rule) on the pipeline's own training set under several settings
of its section (learning rate, batch size, training subset, ...), side by side in one run: seconds,
epochs, why it stopped, best validation loss, and the single-image fraction correct (cosine) on
every pair of evaluate.pairs. A faster setting counts only at equal quality: converged, best
validation loss no higher than the reference's (+2%), fraction correct within the spread the
reference itself shows between seeds.

    python -m benchmarks.speed.bench_training_schedule [--learners fae,cae] [--seeds 0,1]
        [--settings "cae=learning_rate=0.002,batch_size=64;max_train_images=1024"]
        [--settings "fae=adam=per_tensor" --settings "cae=upsampling=separate"]

Besides keys of the learner's section, a setting can name how the training computes (IMPLEMENTATIONS):
adam=per_tensor runs torch's default Adam (one pass over the weights per operation) instead of the
pipeline's fused one; upsampling=separate runs the CAE's decoder as nn.Upsample then the convolution
instead of its sub-pixel convolution (seasonloop.models.core.upsampling.UpsampledConv2d); denormals=kept trains
without flushing denormal floats to zero (seasonloop.models.core.arithmetic.flush_denormals). Each
computes the same function up to float rounding, so a difference in quality is that rounding's
effect on training. Every fit runs in a fresh process, as a fit stage does (a process's threads
keep the floating-point mode they were created with).

Run from the repository root after `dvc repro` (reads data/split and data/augmented, and
params.yaml's sections of the learners). The first setting of each learner is the reference
(params.yaml's own). Writes benchmarks/results/bench_training_schedule.json.
"""

from __future__ import annotations

import argparse
import contextlib
import json
import multiprocessing
import sys
import time
from collections.abc import Iterator
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path
from unittest import mock

import numpy as np
import torch
import yaml

from benchmarks.common import load_note, where_measured
from seasonloop.data import datasets
from seasonloop.evaluation.distances import distance_matrix
from seasonloop.evaluation.metrics import evaluate_pair
from seasonloop.io import read_json
from seasonloop.models.cae import ConvolutionalAutoEncoder
from seasonloop.models.core import arithmetic, training
from seasonloop.models.core.lookup import get_learner
from seasonloop.models.core.upsampling import UpsampledConv2d
from tools.records import machine, write_result
from tools.repository import REPO, learner_params

sys.path.insert(0, str(REPO / "stages"))
import _datasets as stage_datasets  # noqa: E402  (the stages' binding of params to data/split, data/augmented)

SPLIT, AUGMENTED = stage_datasets.SPLIT, stage_datasets.AUGMENTED

QUALITY_TOLERANCE = 0.02  # best validation loss may exceed the reference's by this fraction
# settings per learner: ';'-separated, each a ','-separated list of key=value of the learner's section
DEFAULT_SETTINGS = {
    "fae": "learning_rate=0.002;batch_size=256,learning_rate=0.002;max_train_images=5440",
    "cae": "learning_rate=0.002;batch_size=64,learning_rate=0.002;max_train_images=1024",
}


def parse_settings(texts: list[str], learners: list[str]) -> dict[str, list[dict]]:
    """learner -> [overrides of its section, ...], params.yaml's own ({}) first."""
    given = dict(DEFAULT_SETTINGS)
    for text in texts:
        name, _, values = text.partition("=")
        given[name] = values
    settings = {
        name: [{}]
        + [
            {key: yaml.safe_load(value) for key, value in (item.split("=") for item in setting.split(","))}
            for setting in given[name].split(";")
        ]
        for name in learners
    }
    # an unknown implementation stops the run here, not after the fits before it
    for overrides in (overrides for listed in settings.values() for overrides in listed):
        for key in overrides.keys() & IMPLEMENTATIONS.keys():
            if overrides[key] not in IMPLEMENTATIONS[key]:
                raise SystemExit(f"--settings: {key}={overrides[key]} (known: {', '.join(IMPLEMENTATIONS[key])})")
    return settings


@contextlib.contextmanager
def per_tensor_adam() -> Iterator[None]:
    """torch's default Adam (not fused): the update the pipeline ran before training.adam fused it."""
    per_tensor = lambda model, learning_rate: torch.optim.Adam(model.parameters(), lr=learning_rate)  # noqa: E731
    with mock.patch.object(training, "adam", per_tensor):
        yield


@contextlib.contextmanager
def separate_upsampling() -> Iterator[None]:
    """The CAE's decoder as nn.Upsample then a "same" convolution at the higher resolution."""
    build = ConvolutionalAutoEncoder._build_model

    def built_separate(learner, height: int, width: int):
        model = build(learner, height, width)
        for module in model.modules():
            if isinstance(module, UpsampledConv2d):
                module.sub_pixel = False
        return model

    with mock.patch.object(ConvolutionalAutoEncoder, "_build_model", built_separate):
        yield


@contextlib.contextmanager
def kept_denormals() -> Iterator[None]:
    """Training without flushing denormal floats to zero (the fit imports flush_denormals from
    arithmetic when it starts, so the module's attribute is what it gets)."""
    with mock.patch.object(arithmetic, "flush_denormals", lambda device: None):
        yield


# setting key -> value -> the context the fit runs in (not a key of the learner's section)
IMPLEMENTATIONS = {
    "adam": {"per_tensor": per_tensor_adam},
    "upsampling": {"separate": separate_upsampling},
    "denormals": {"kept": kept_denormals},
}


def label(overrides: dict) -> str:
    return " ".join(f"{key}={value}" for key, value in overrides.items()) or "params.yaml"


def fraction_correct(learner, params: dict) -> dict[str, float]:
    """pair -> single-image fraction correct (%), cosine, exact place (the default run's setting)."""
    pairs = [pair.split("-") for pair in params["evaluate"]["pairs"]]
    seasons = sorted({season for pair in pairs for season in pair})
    images = datasets.test_images(SPLIT, seasons)
    places = np.asarray(read_json(SPLIT / "split.json")["test"])
    descriptors = {season: learner.describe(images[season]) for season in seasons}
    tolerance = int(params["evaluate"]["tolerance_frames"])
    return {
        f"{database}-{query}": 100
        * evaluate_pair(
            distance_matrix(descriptors[database], descriptors[query], metric="cosine"), places, places, tolerance
        )[0]["fraction_correct"]
        for database, query in pairs
    }


def fit_once(name: str, section: dict, overrides: dict, seed: int, data: tuple) -> dict:
    section_overrides = {key: value for key, value in overrides.items() if key not in IMPLEMENTATIONS}
    learner = get_learner(name)(learner_params(name, {**section, **section_overrides}), seed=seed)
    images, places, params = data
    with contextlib.ExitStack() as implementation:
        for key in overrides.keys() & IMPLEMENTATIONS.keys():  # values checked by parse_settings
            implementation.enter_context(IMPLEMENTATIONS[key][overrides[key]]())
        start = time.perf_counter()
        info = learner.fit(images, progress=False, places=places)
        seconds = time.perf_counter() - start
    correct = fraction_correct(learner, params)
    return {
        "setting": label(overrides),
        "overrides": overrides,
        "seed": seed,
        "seconds": seconds,
        "seconds_per_epoch": seconds / info["epochs_run"],
        "epochs_run": info["epochs_run"],
        "best_epoch": info["best_epoch"],
        "stop_reason": info["stop_reason"],
        "converged": info["converged"],
        "best_validation_loss": info["best_validation_loss"],
        "fraction_correct": correct,
        "mean_fraction_correct": float(np.mean(list(correct.values()))),
        "validation_loss_per_epoch": info["validation_loss_per_epoch"],
        "learning_rate_per_epoch": info["learning_rate_per_epoch"],
    }


def verdicts(runs: list[dict]) -> list[str]:
    """One line per setting: its mean over seeds against the reference's (the first setting)."""
    settings = list(dict.fromkeys(run["setting"] for run in runs))

    def values(setting: str, key: str) -> list:
        return [run[key] for run in runs if run["setting"] == setting]

    def mean(setting: str, key: str) -> float:
        return float(np.mean(values(setting, key)))

    reference = settings[0]
    reference_spread = max(values(reference, "mean_fraction_correct")) - min(values(reference, "mean_fraction_correct"))
    lines = []
    for setting in settings:
        converged = all(values(setting, "converged"))
        loss_change = mean(setting, "best_validation_loss") / mean(reference, "best_validation_loss") - 1
        correct_change = mean(setting, "mean_fraction_correct") - mean(reference, "mean_fraction_correct")
        equal = converged and loss_change <= QUALITY_TOLERANCE and abs(correct_change) <= max(reference_spread, 1.0)
        lines.append(
            f"{setting}: {mean(setting, 'seconds'):.0f} s ({mean(reference, 'seconds') / mean(setting, 'seconds'):.2f}x), "
            f"{mean(setting, 'epochs_run'):.0f} epochs of {mean(setting, 'seconds_per_epoch'):.2f} s, "
            f"converged {converged}, best validation loss {mean(setting, 'best_validation_loss'):.5f} "
            f"({loss_change:+.1%}), fraction correct {mean(setting, 'mean_fraction_correct'):.1f}% "
            f"({correct_change:+.1f}; seeds {', '.join(f'{value:.1f}' for value in values(setting, 'mean_fraction_correct'))}): "
            f"{'equal quality' if equal else 'NOT equal quality'}" + (" [reference]" if setting == reference else "")
        )
    return lines


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--learners", default="fae,cae")
    parser.add_argument("--seeds", default="0,1", help="seeds of each setting (the spread is the noise)")
    parser.add_argument(
        "--settings", action="append", default=[], help="learner=key=value,key=value;key=value (';' between settings)"
    )
    args = parser.parse_args()
    params = yaml.safe_load(Path("params.yaml").read_text())
    if not AUGMENTED.is_dir():
        raise SystemExit(f"{AUGMENTED}: missing; run `dvc repro` first")
    # the training set of fit@<learner>, chosen by the stages' own code
    seasons = list(params["train"]["seasons"])
    data = (stage_datasets.training_images(params, seasons), stage_datasets.training_places(params, seasons), params)
    learners = args.learners.split(",")
    seeds = [int(seed) for seed in args.seeds.split(",")]
    measured_on = machine()
    results: dict = {"args": vars(args), "learners": {}}
    headline = []
    for name, settings in parse_settings(args.settings, learners).items():
        runs = []
        for overrides in settings:
            for seed in seeds:
                # a fresh process per fit: no thread pool, floating-point mode or cache of another fit
                with ProcessPoolExecutor(1, mp_context=multiprocessing.get_context("spawn")) as fresh:
                    runs.append(fresh.submit(fit_once, name, params[name], overrides, seed, data).result())
                shown = {key: value for key, value in runs[-1].items() if not isinstance(value, (dict, list))}
                print(name, shown, flush=True)
        results["learners"][name] = {"runs": runs, "verdicts": verdicts(runs)}
        headline += [f"{name} {line}" for line in results["learners"][name]["verdicts"]]
    results["headline"] = headline
    results["load_note"] = load_note(measured_on)
    write_result("bench_training_schedule", results, measured_on)
    print("\n".join(headline))
    print(f"Measured on {measured_on['cpu']}, ISA cap {measured_on['isa_cap']}. {results['load_note']}")


def _bench_training_schedule(path: Path) -> str:
    """Every run of the auto-encoders' training settings, then the script's verdicts."""
    record = json.loads(path.read_text())
    lines = [
        f"`python -m benchmarks.speed.bench_training_schedule --learners {record['args']['learners']} "
        f"--seeds {record['args']['seeds']}"
        + "".join(f' --settings "{setting}"' for setting in record["args"]["settings"])
        + "`:",
        "",
        "| learner | setting | seed | seconds | epochs | s / epoch | stop | best validation loss | fraction correct % |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    for name, measured in record["learners"].items():
        for run in measured["runs"]:
            lines.append(
                f"| {name} | {run['setting']} | {run['seed']} | {run['seconds']:.0f} | {run['epochs_run']} "
                f"| {run['seconds_per_epoch']:.2f} | {run['stop_reason']} | {run['best_validation_loss']:.5f} "
                f"| {run['mean_fraction_correct']:.1f} |"
            )
    verdicts = "\n".join(f"- {line}" for line in record["headline"])
    return "\n".join(lines) + "\n\n" + verdicts + "\n\n" + where_measured(record) + "\n"


# docs/write_tables.py's tables of this benchmark's record: name -> (record, snapshot, how it is
# written); five runs (the record is rewritten by each): halved training sets, the settings between
# those and params.yaml's, then the training's kernels (fused Adam, denormals flushed, the CAE's
# sub-pixel up-sampling) against the ones before, and three more seeds of the CAE
TABLES = {
    name: ("benchmarks/results/bench_training_schedule.json", f"{name}.json", _bench_training_schedule)
    for name in (
        "bench_training_schedule",
        "bench_training_schedule_subsets",
        "bench_training_kernels",
        "bench_training_kernels_cae_seeds",
    )
}


if __name__ == "__main__":
    main()
