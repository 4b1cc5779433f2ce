"""The implementation settings of benchmarks/speed/bench_training_schedule.py reach the code they
stand in for: a fit under `denormals=kept` never switches denormal flushing on."""

from __future__ import annotations

import contextlib
from unittest import mock

import numpy as np
import torch

from benchmarks.speed.bench_training_schedule import IMPLEMENTATIONS
from seasonloop.models.core.lookup import get_learner
from tools.repository import learner_params


def fit_flushes(context) -> bool:
    """Whether a tiny FAE fit asks torch to flush denormals, under `context` (None: as the pipeline)."""
    learner_class = get_learner("fae")
    learner = learner_class(learner_params("fae", learner_class.TINY_RUN), seed=0)
    images = np.random.default_rng(0).integers(0, 256, (48, 16, 32), dtype=np.uint8)
    with mock.patch.object(torch, "set_flush_denormal") as flush, (context or contextlib.nullcontext)():
        learner.fit(images, progress=False, places=np.arange(len(images)))
    return any(call.args == (True,) for call in flush.call_args_list)


def test_kept_denormals_keeps_the_fit_from_flushing_them():
    assert fit_flushes(None)
    assert not fit_flushes(IMPLEMENTATIONS["denormals"]["kept"])
