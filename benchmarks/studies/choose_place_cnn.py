"""Which settings of the place-supervised network, judged on validation places alone: place_cnn
fitted as the fit stage fits it (every training season, augmented, each image's place and
traverse) to its validation plateau under params.yaml's section with each candidate's widths and
learning rate (and first layer: pooled or strided), recording recall@1 of the held-out training places after every epoch, where the
stopping rule ended it and how long the fit took. No test place enters: the candidates are told
apart by the network's own validation, the measure its stopping rule reads.

    dvc repro fit@place_cnn      # the default run's data/split and data/augmented
    python -m benchmarks.studies.choose_place_cnn [--seeds 0]

Writes benchmarks/results/choose_place_cnn.json (table: docs/pipeline.md, "How the
place-supervised network is trained").
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import numpy as np
import yaml

from benchmarks.common import load_note, save_and_report, timed
from benchmarks.speed.bench_place_cnn import SPLIT, training_set
from seasonloop.models.core.lookup import get_learner
from tools.records import machine

WIDE, NARROW = [16, 32, 64], [8, 16, 32, 64]
# the widths, learning rates and first layers compared; every other setting is params.yaml's
CANDIDATES = {
    f"{name} lr {rate:g}": {"channels": channels, "learning_rate": rate, "first_downsampling": "pool"}
    for name, channels in (("wide", WIDE), ("narrow", NARROW))
    for rate in (1e-3, 3e-3, 1e-2)
} | {
    # the first convolution strided instead of pooled: a quarter of its positions
    f"wide strided lr {rate:g}": {"channels": WIDE, "learning_rate": rate, "first_downsampling": "stride"}
    for rate in (3e-3, 1e-2)
}


def fit_candidate(changes: dict, params: dict, seed: int, training: tuple[np.ndarray, ...]) -> dict:
    """place_cnn with `changes` over params.yaml's section, fitted to its plateau on `training`
    (bench_place_cnn.training_set): its validation recall after every epoch and how the fit ended."""
    images, places, traverses = training
    learner = get_learner("place_cnn")({**params["place_cnn"], **changes}, seed=seed)
    learner.import_libraries()
    curve: list[float] = []
    info, seconds = timed(
        lambda: learner.fit(
            images,
            progress=False,
            places=places,
            traverses=traverses,
            on_epoch=lambda epoch, values: curve.append(1.0 - values["validation_loss"]),
        )
    )
    return {
        "seed": seed,
        "seconds": seconds,
        "seconds_per_epoch": seconds / len(curve),
        "validation_recall": curve,
        **{key: info[key] for key in ("epochs_run", "best_epoch", "converged", "best_validation_recall")},
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, nargs="+", default=[0], help="each candidate fitted from each")
    arguments = parser.parse_args()
    if not (SPLIT / "split.json").is_file():
        raise SystemExit(f"{SPLIT}: not found (run `dvc repro fit@place_cnn` first: the default run's training set)")
    params = yaml.safe_load(Path("params.yaml").read_text())
    measured_on = machine()
    training = training_set(params)  # read once: every candidate fits the same images
    fits: dict[str, list[dict]] = {}
    for name, changes in CANDIDATES.items():
        fits[name] = [fit_candidate(changes, params, seed, training) for seed in arguments.seeds]
        for fit in fits[name]:
            print(
                f"{name} seed {fit['seed']}: recall@1 {fit['best_validation_recall']:.3f} at epoch "
                f"{fit['best_epoch']} of {fit['epochs_run']}, {fit['seconds']:.0f} s",
                flush=True,
            )
    best = max(fits, key=lambda name: min(fit["best_validation_recall"] for fit in fits[name]))
    headline = f"highest validation recall@1: {best} ({fits[best][0]['best_validation_recall']:.3f}, seed {arguments.seeds[0]})"
    record = {"candidates": CANDIDATES, "fits": fits, "headline": headline, "load_note": load_note(measured_on)}
    save_and_report("choose_place_cnn", record, measured_on)


def choose_place_cnn_table(path: Path) -> str:
    """choose_place_cnn's record: each candidate's best validation recall, where it stopped, its time."""
    from benchmarks.common import where_measured

    record = json.loads(path.read_text())
    lines = [
        "| candidate | channels | first layer | learning rate | seed | best validation recall@1 | best epoch | epochs "
        "| converged | fit (s) | s an epoch |",
        "|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for name, fits in record["fits"].items():
        changes = record["candidates"][name]
        for fit in fits:
            lines.append(
                f"| {name} | {changes['channels']} | {changes.get('first_downsampling', 'pool')} | "
                f"{changes['learning_rate']:g} | {fit['seed']} | "
                f"{fit['best_validation_recall']:.3f} | {fit['best_epoch']} | {fit['epochs_run']} | "
                f"{'yes' if fit['converged'] else 'no'} | {fit['seconds']:.0f} | {fit['seconds_per_epoch']:.1f} |"
            )
    return "\n".join(lines) + f"\n\n{record['headline']}.\n\n{where_measured(record)}\n"


TABLES = {
    "choose_place_cnn": ("benchmarks/results/choose_place_cnn.json", "choose_place_cnn.json", choose_place_cnn_table)
}


if __name__ == "__main__":
    main()
