"""seasonloop.models.core.parallel: fits run at once give the bytes of fits run one after another, at
the same threads a fit; and jobs at once without threads stated are refused by name."""

from __future__ import annotations

import hashlib
from functools import partial
from pathlib import Path

import numpy as np
import pytest

from seasonloop.models.core.lookup import get_learner
from seasonloop.models.core.parallel import fit_threads, run_each
from seasonloop.params.across import check_fit_threads
from tools.repository import learner_params

# small sections: the learners take their other settings' defaults
SECTIONS = {"pca": {"n_discard": 0, "n_keep": 12}, "ica": {"n_components": 8, "max_iter": 200}}


def fitted_bytes(name: str, section: dict, folder: Path, fold: int) -> str:
    """A small learner fitted on fold `fold`'s images at 1 thread, saved; the sha256 of its files."""
    rng = np.random.default_rng(fold)
    images = rng.integers(0, 256, (120, 16, 32), dtype=np.uint8)  # 512 pixels: seconds, not minutes
    learner = get_learner(name)(learner_params(name, section), seed=0)
    learner.import_libraries()
    with fit_threads(1):
        learner.fit(images, progress=False, places=np.arange(len(images)))
    out = folder / f"{name}_{fold}"
    learner.save(out)
    digest = hashlib.sha256()
    for path in sorted(p for p in out.rglob("*") if p.is_file() and p.suffix != ".json"):
        digest.update(path.read_bytes())
    return digest.hexdigest()


@pytest.mark.parametrize("name", ["pca", "ica"])
def test_fits_at_once_are_the_fits_one_after_another(tmp_path, name):
    section = SECTIONS[name]
    one = run_each(partial(fitted_bytes, name, section, tmp_path / "one"), [0, 1, 2], jobs=1)
    two = run_each(partial(fitted_bytes, name, section, tmp_path / "two"), [0, 1, 2], jobs=2)
    assert one == two and len(set(one)) == 3  # three folds, three different models, the same bytes


def test_jobs_without_threads_are_refused_by_name():
    check_fit_threads({"train": {"jobs": 1, "threads": 0}})
    check_fit_threads({"train": {"jobs": 2, "threads": 1}})
    with pytest.raises(ValueError, match=r"train.jobs: 2 fits at once need train.threads set"):
        check_fit_threads({"train": {"jobs": 2, "threads": 0}})
