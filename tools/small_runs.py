"""Small configurations of the pipeline (overrides of params.yaml): runs that still have every stage
but take seconds to a minute on 2 cores, for the end-to-end tests (tests/workspaces.py) and the
benchmarks that measure what those tests pay (benchmarks/speed/bench_dvc_yaml.py)."""

from __future__ import annotations

from seasonloop.models.core.lookup import LEARNERS, get_learner

# Small enough for CI on 2 cores, large enough that every stage has real work: three seasons
# (so pairs are filtered to the seasons present), every learner, both matchers.
TINY = {
    "data": {"seasons": ["summer", "fall", "winter"]},
    "train": {"seasons": ["summer", "fall", "winter"]},
    "synthetic": {"seconds": 300, "fps": 2, "width": 128, "height": 72},
    "extract": {"height": 36, "width": 64},
    "split": {"section_length": 100, "test_fraction": 0.3, "gap": 3},
    # each learner's own small settings (its class's TINY_RUN)
    **{name: dict(get_learner(name).TINY_RUN) for name in LEARNERS if get_learner(name).TINY_RUN},
    # 1/32 is the CAE's own width (reused from fit@cae), 1/16 is trained by the sweep
    "cae_widths": {"widths": [0.03125, 0.0625]},
    # one learner that learns: the ablation stage is the same for every learner (ica's fits, ~10 s
    # here, add nothing the unit tests of seasonloop.ablations do not check)
    "ablation": {"learners": ["pca"], "training_seasons": [["summer"], ["summer", "winter"]], "pair": "summer-fall"},
}

# the smallest run that still has every stage: two learners, two matchers, one distance, the
# training-free learner's ablation, and the CAE width sweep skipped (its stage writes that it was).
# TINY's run trains both (test_pipeline checks them): a sweep's torch import and fit are ~4 s of a
# ~20 s tiny run, and pca's ablation fit ~2.5 s (mostly scikit-learn's import) each time an
# experiment of a SMALL workspace changes pca
SMALL = {
    **{key: value for key, value in TINY.items() if key != "ablation"},
    "learners": ["raw_patchnorm", "pca"],
    # single images and SeqSLAM under one distance: TINY's run evaluates every matcher and distance
    "evaluate": {"matchers": ["single", "sequence"], "extra_metrics": []},
    "ablation": {"learners": ["raw_patchnorm"], "pair": "summer-fall", "training_seasons": [["summer"]]},
    "cae_widths": {"widths": []},
}

# the tests of other data (test_real_frames, test_other_datasets): nothing is restored for them, so
# the fewest stages that still go through the report: one learner, SMALL's ablation's
DATA_PATH = {**SMALL, "learners": ["raw_patchnorm"]}
