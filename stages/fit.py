"""Stage fit@<learner>: fit one feature learner on the training images of train.seasons, or, with
train.fitted: elsewhere, take the learner already fitted in train.models_dir/<learner> (another
run's models/, another dataset: as the field's published learners are trained elsewhere).

Writes models/<learner>/ (the fitted learner), logs/<learner>/ (dvclive training and validation
curves of the learners that train in epochs; an empty folder for the others) and metrics/fit/<learner>.json (fit time, training-set
size, what it was trained on, the learner's fit report such as ICA convergence or why an
auto-encoder stopped, and the torch threads and library versions, so that a different result
elsewhere can be traced). With split.folds K > 1 a learner is fitted on each fold's training
images into its fold folder (seasonloop.data.datasets.fold_dir; the study's fold is logged and
recorded as before, the others under "folds" of the record); a training-free learner, or one
fitted elsewhere, is the same model for every fold and is fitted once.
"""

from __future__ import annotations

import argparse
import platform
import sys
import time
from contextlib import ExitStack
from functools import partial
from importlib.metadata import version
from pathlib import Path
from typing import Any

import numpy as np

from _common import load_params, param, stage_main, train_seasons
from _datasets import SPLIT, training_images, training_places, training_traverses
from seasonloop.data.datasets import count_folds, fold_dir, split_images_file, trained_on
from seasonloop.io import staged_dir, write_json
from seasonloop.models.core.learner import FeatureLearner
from seasonloop.models.core.lookup import get_learner, load_fitted_elsewhere
from seasonloop.models.core.parallel import fit_threads, run_each


def fit_here(
    name: str, params: dict[str, Any], seasons: list[str], fold: int = -1, folds: int = 1
) -> tuple[FeatureLearner, dict, dict]:
    """The learner fitted on the training images of fold `fold` of `folds` (-1: the study's split,
    the one whose epochs logs/<learner> holds); (learner, its fit info, the record's facts)."""
    learner_class = get_learner(name)
    # the learner checks its own section before the training images are loaded
    learner = learner_class(param(params, name), seed=int(param(params, "seed")))
    images = training_images(params, seasons, fold, folds)
    places = training_places(params, seasons, fold, folds)
    traverses = training_traverses(params, seasons, fold, folds)
    logs = Path("logs") / name
    logged = fold % folds == folds - 1
    with ExitStack() as opened:
        if learner_class.trains_in_epochs and logged:
            # imported only here: dvclive (with pandas) is ~0.8 s of every other fit's start-up
            from dvclive import Live

            live = opened.enter_context(Live(dir=str(logs), save_dvc_exp=False, dvcyaml=None, report=None))
        else:
            logs.mkdir(parents=True, exist_ok=True)  # a declared output, empty: nothing to log

        def on_epoch(epoch: int, values: dict[str, float]) -> None:
            if not logged:
                return
            # one plot of both losses (logs/<learner>/plots/metrics/loss/{train,validation}.tsv)
            live.log_metric("loss/train", values["train_loss"])
            live.log_metric("loss/validation", values["validation_loss"])
            live.log_metric("learning_rate", values["learning_rate"])
            live.next_step()

        learner.import_libraries()  # before the timer: fit_seconds is the fit, not Python's imports
        with fit_threads(int(param(params, "train.threads"))):
            start = time.perf_counter()
            info = learner.fit(images, progress=True, on_epoch=on_epoch, places=places, traverses=traverses)
            fit_seconds = time.perf_counter() - start
    whole_route = param(params, "split.test_fraction") == 1
    facts = {
        "fit_seconds": fit_seconds,
        "n_train_images": len(images),
        "train_seasons": seasons,
        "trained_on": trained_on(learner_class.learns, seasons, whole_route),
    }
    return learner, info, facts


def fitted_elsewhere(name: str, models_dir: Path, season: str) -> tuple[FeatureLearner, dict, dict]:
    """The learner fitted in models_dir/<learner> (load_fitted_elsewhere); nothing is fitted here."""
    size = tuple(np.load(split_images_file(SPLIT, season, "test"), mmap_mode="r").shape[1:])
    learner, info = load_fitted_elsewhere(models_dir, name, size)
    Path("logs", name).mkdir(parents=True, exist_ok=True)  # a declared output, empty: nothing trained here
    facts = {
        "fit_seconds": None,
        "n_train_images": None,
        "train_seasons": [],
        "trained_on": f"elsewhere: {models_dir / name} (not this dataset; its own params)",
    }
    return learner, info, facts


def save_fold(learner: FeatureLearner, out: Path, fold: int, folds: int) -> None:
    folder = fold_dir(out, fold, folds)
    folder.mkdir(parents=True, exist_ok=True)
    learner.save(folder)


def fit_fold(name: str, params: dict[str, Any], seasons: list[str], folds: int, out: Path, fold: int):
    """fit_here of fold `fold` saved in its folder of `out` (run_each may run it in another
    process: the learner stays there); (its fit info, the record's facts)."""
    learner, info, facts = fit_here(name, params, seasons, fold, folds)
    save_fold(learner, out, fold % folds, folds)
    return info, facts


@stage_main
def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("learner")
    name = parser.parse_args().learner
    params = load_params("seed", "data.seasons", "train", "augment.copies", "split.test_fraction")
    seasons = train_seasons(params)
    folds = count_folds(SPLIT)
    others: list[dict[str, Any]] = []  # the record of each fold but the study's
    with staged_dir(Path("models") / name) as out:
        elsewhere = param(params, "train.fitted") == "elsewhere"
        if elsewhere or not get_learner(name).learns:
            # one model, the same in every fold's folder
            if elsewhere:
                learner, info, facts = fitted_elsewhere(name, Path(param(params, "train.models_dir")), seasons[0])
            else:
                learner, info, facts = fit_here(name, params, seasons, -1, folds)
            for fold in range(folds):
                save_fold(learner, out, fold, folds)
        else:
            # the study's fold last: the one logs/<learner> and the record's own keys describe
            fitted = run_each(
                partial(fit_fold, name, params, seasons, folds, out),
                [*range(folds - 1), -1],
                int(param(params, "train.jobs")),
            )
            others = [{"fold": fold, **facts, "info": info} for fold, (info, facts) in enumerate(fitted[:-1])]
            info, facts = fitted[-1]
    write_json(
        Path("metrics/fit") / f"{name}.json",
        {
            **facts,
            "info": info,
            **({"folds": others} if folds > 1 else {}),
            "environment": {
                # None: the learner did not use torch (not imported here: 1.5 s of every fit's start-up)
                "torch_threads": sys.modules["torch"].get_num_threads() if "torch" in sys.modules else None,
                "python": platform.python_version(),
                **{
                    package: version(package)
                    for package in ("numpy", "scikit-learn", "torch", "opencv-contrib-python-headless")
                },
            },
        },
    )


if __name__ == "__main__":
    main()
