"""benchmarks/speed/bench_ica.py's reading of gradient traces: a time counts once the gradient stays below
its target, and scikit-learn's FastICA is traced like the torch solvers."""

from __future__ import annotations

import pytest
from ica_data import images

from benchmarks.speed import bench_ica
from seasonloop.models.core.lookup import get_learner
from tools.repository import learner_params


def result(trace: list[tuple[float, float]], final: float) -> dict:
    return {"trace": trace, "record": {"gradient": final}}


def test_a_gradient_that_dips_below_the_target_and_rises_again_does_not_count():
    trace = [(1.0, 5e-3), (2.0, 5e-4), (3.0, 2e-3), (4.0, 8e-4), (5.0, 1e-4)]
    assert bench_ica.time_to_stay_below(result(trace, 1e-4), 1e-3) == 4.0
    assert bench_ica.time_to_stay_below(result(trace, 1e-4), 1e-2) == 1.0
    assert bench_ica.time_to_stay_below(result(trace, 1e-4), 1e-5) is None
    # the stored model decides at the end: above the target, never reached
    assert bench_ica.time_to_stay_below(result(trace, 2e-3), 1e-3) is None


def test_sklearn_fastica_is_traced_iterate_by_iterate():
    train = images(400, 0)
    learner = get_learner("ica")(
        learner_params("ica", {"n_components": 6, "solver": "sklearn", "max_iter": 3, "change_tol": 1e-12}), seed=1
    )
    record, seconds, trace = bench_ica.traced_sklearn_fit(lambda: learner.fit(train, progress=False), "logcosh")
    # the initial matrix, then each of its iterations
    assert len(trace) == record["n_iter"] + 1 == 4
    times = [moment for moment, _ in trace]
    assert times == sorted(times) and 0 < times[-1] <= seconds
    # far from convergence, where the stored model's float32 rounding is small against the gradient
    assert trace[-1][1] == pytest.approx(record["gradient"], rel=1e-3) and record["gradient"] > 1e-3
    # the wrapper is gone afterwards
    import sklearn.decomposition._fastica as fastica_module

    assert fastica_module._ica_par.__module__ == "sklearn.decomposition._fastica"
