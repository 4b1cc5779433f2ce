"""Stage fit@<method>: fit one feature learner on the training images of train.seasons.

Writes models/<method>/ (the fitted learner), logs/<method>/ (dvclive training and validation
curves of the learners that train in epochs; an empty folder for the others) and metrics/fit/<method>.json (fit time, training-set
size, the learner's fit report such as ICA convergence or why an auto-encoder stopped, and the
torch threads and library versions, so that a different result elsewhere can be traced).
"""

from __future__ import annotations

import argparse
import platform
import sys
import time
from contextlib import ExitStack
from importlib.metadata import version
from pathlib import Path

from _common import load_params, param, stage_main, train_seasons
from _datasets import training_images, training_places
from seasonloop.data.datasets import trained_on
from seasonloop.io import staged_dir, write_json
from seasonloop.models.registry import get_learner


@stage_main
def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("method")
    method = parser.parse_args().method
    params = load_params("seed", "data.seasons", "train", "augment.copies", "split.test_fraction")
    learner_class = get_learner(method)
    seasons = train_seasons(params)
    # the learner checks its own section before the training images are loaded
    learner = learner_class(param(params, method), seed=int(param(params, "seed")))
    images = training_images(params, seasons)
    places = training_places(params, seasons)
    logs = Path("logs") / method
    with ExitStack() as opened:
        if learner_class.trains_in_epochs:
            # imported only here: dvclive (with pandas) is ~0.8 s of every other fit's start-up
            from dvclive import Live

            live = opened.enter_context(Live(dir=str(logs), save_dvc_exp=False, dvcyaml=None, report=None))
        else:
            logs.mkdir(parents=True, exist_ok=True)  # a declared output, empty: nothing to log

        def on_epoch(epoch: int, values: dict[str, float]) -> None:
            # one plot of both losses (logs/<method>/plots/metrics/loss/{train,validation}.tsv)
            live.log_metric("loss/train", values["train_loss"])
            live.log_metric("loss/validation", values["validation_loss"])
            live.log_metric("learning_rate", values["learning_rate"])
            live.next_step()

        learner.import_libraries()  # before the timer: fit_seconds is the fit, not Python's imports
        start = time.perf_counter()
        info = learner.fit(images, progress=True, on_epoch=on_epoch, places=places)
        fit_seconds = time.perf_counter() - start
    with staged_dir(Path("models") / method) as out:
        learner.save(out)
    write_json(
        Path("metrics/fit") / f"{method}.json",
        {
            "fit_seconds": fit_seconds,
            "n_train_images": len(images),
            "train_seasons": seasons,
            "trained_on": trained_on(learner_class.learns, seasons, param(params, "split.test_fraction") == 1),
            "info": info,
            "environment": {
                # None: the learner did not use torch (not imported here: 1.5 s of every fit's start-up)
                "torch_threads": sys.modules["torch"].get_num_threads() if "torch" in sys.modules else None,
                "python": platform.python_version(),
                **{
                    package: version(package)
                    for package in ("numpy", "scikit-learn", "torch", "opencv-python-headless")
                },
            },
        },
    )


if __name__ == "__main__":
    main()
