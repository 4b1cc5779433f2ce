"""The place-supervised network's fit beside the CAE's, side by side on the default run's training
set: each learner with params.yaml's settings, fitted as the fit stage fits it (every training
season, augmented, each image's place and traverse), timed, alternating which goes first over
`--repeats` rounds; how each fit ended (converged at its validation plateau or not) and its best
validation measure. Issue 67's target: place_cnn's fit takes no longer than the CAE's.

    dvc repro fit@cae            # the default run's data/split and data/augmented
    python -m benchmarks.speed.bench_place_cnn [--repeats 2]

Writes benchmarks/results/bench_place_cnn.json; the headline (place_cnn's median fit seconds over
the CAE's) is printed last.
"""

from __future__ import annotations

import argparse
import json
import statistics
from pathlib import Path

import numpy as np
import yaml

from benchmarks.common import load_note, save_and_report, timed
from seasonloop.data import datasets
from seasonloop.models.core.lookup import get_learner
from tools.records import machine

LEARNERS = ("cae", "place_cnn")
SPLIT, AUGMENTED = Path("data/split"), Path("data/augmented")


def training_set(params: dict) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The pipeline's training set as stages/fit.py makes it: (images, their places, their traverses)."""
    seasons = [season for season in params["data"]["seasons"] if season in params["train"]["seasons"]]
    copies = params["augment"]["copies"] if params["train"]["augmented"] else 0
    images = datasets.training_images(SPLIT, AUGMENTED if params["train"]["augmented"] else None, seasons)
    return images, datasets.training_places(SPLIT, seasons, copies), datasets.training_traverses(SPLIT, seasons, copies)


def fit_once(name: str, params: dict, training: tuple[np.ndarray, ...]) -> dict:
    """One fit of learner `name` on `training` (training_set)."""
    images, places, traverses = training
    learner = get_learner(name)(params[name], seed=int(params["seed"]))
    learner.import_libraries()
    info, seconds = timed(lambda: learner.fit(images, progress=False, places=places, traverses=traverses))
    ended = learner.how_fit_ended(info)
    return {
        "seconds": seconds,
        "converged": ended.get("converged"),
        "epochs_run": ended.get("epochs_run"),
        "best_validation_loss": ended.get("best_validation_loss"),
        "n_train_images": len(images),
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=2, help="rounds, each fitting both learners")
    arguments = parser.parse_args()
    if not (SPLIT / "split.json").is_file():
        raise SystemExit(f"{SPLIT}: not found (run `dvc repro fit@cae` first: the default run's training set)")
    params = yaml.safe_load(Path("params.yaml").read_text())
    measured_on = machine()
    training = training_set(params)  # read once: both learners, every round, fit the same images
    fits: dict[str, list[dict]] = {name: [] for name in LEARNERS}
    for round_ in range(arguments.repeats):
        for name in LEARNERS if round_ % 2 == 0 else reversed(LEARNERS):
            fits[name].append(fit_once(name, params, training))
            print(f"round {round_ + 1}: {name} {fits[name][-1]['seconds']:.1f} s", flush=True)
    median = {name: statistics.median(fit["seconds"] for fit in fits[name]) for name in LEARNERS}
    converged = {name: all(fit["converged"] for fit in fits[name]) for name in LEARNERS}
    ratio = median["place_cnn"] / median["cae"]
    headline = (
        f"place_cnn's fit takes {ratio:.2f}x the CAE's ({median['place_cnn']:.0f} s against {median['cae']:.0f} s, "
        f"median of {arguments.repeats}); converged at its plateau: place_cnn {str(converged['place_cnn']).lower()}, "
        f"CAE {str(converged['cae']).lower()}"
    )
    record = {"fits": fits, "median_seconds": median, "ratio": ratio, "headline": headline}
    record["load_note"] = load_note(measured_on)
    save_and_report("bench_place_cnn", record, measured_on)


def place_cnn_table(path: Path) -> str:
    """bench_place_cnn's record: each fit of the two learners, how it ended, the headline ratio."""
    from benchmarks.common import where_measured

    record = json.loads(path.read_text())
    lines = ["| learner | fit (s) | epochs | converged | best validation |", "|---|---|---|---|---|"]
    for name, fits in record["fits"].items():
        for fit in fits:
            # place_cnn's validation loss is 1 - recall@1 of held-out places; the CAE's its MSE
            best = (
                f"recall@1 {1 - fit['best_validation_loss']:.3f}"
                if name == "place_cnn"
                else (f"loss {fit['best_validation_loss']:.5f}")
            )
            lines.append(
                f"| {name} | {fit['seconds']:.1f} | {fit['epochs_run']} | {'yes' if fit['converged'] else 'no'} | {best} |"
            )
    return "\n".join(lines) + f"\n\n{record['headline']}.\n\n{where_measured(record)}\n"


TABLES = {"bench_place_cnn": ("benchmarks/results/bench_place_cnn.json", "bench_place_cnn.json", place_cnn_table)}


if __name__ == "__main__":
    main()
