"""A new learner is its module and its params section (with its name in `learners:` to run it), and
nothing else: a copy of the project gains a learner in exactly those two files and `dvc repro` runs
it to the report, its params checked by what the module declares, without rerunning the other
learners' stages."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest
import yaml

from tools.repository import dvc, git, tool_env
from workspaces import committed_run

# A learner the project has never seen: a seeded random projection of the pixels.
RANDOM_PROJECTION = '''"""Random projection of the pixels (Johnson-Lindenstrauss): a learner that learns nothing."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from seasonloop.models.core.learner import EpochCallback, FeatureLearner, to_float
from seasonloop.params.checks import integer


class RandomProjection(FeatureLearner):
    """Descriptor = the pixels times a seeded Gaussian matrix of n_dims columns."""

    name = "random_projection"
    PARAMS = {"n_dims": integer(1)}

    def _fit(self, images: np.ndarray, progress: bool, on_epoch: EpochCallback | None) -> dict[str, Any]:
        n_pixels = images.shape[1] * images.shape[2]
        self.matrix = np.random.default_rng(self.seed).standard_normal((n_pixels, self.params["n_dims"]))
        return {"n_train_images": len(images)}

    def _describe_batch(self, images: np.ndarray) -> np.ndarray:
        return to_float(images).reshape(len(images), -1) @ self.matrix.astype(np.float32)

    def _save_state(self, directory: Path) -> None:
        np.save(directory / "matrix.npy", self.matrix)

    def _load_state(self, directory: Path) -> None:
        self.matrix = np.load(directory / "matrix.npy")
'''


def add_learner(root: Path) -> None:
    """The module, its params section and its name in `learners`."""
    (root / "src/seasonloop/models/random_projection.py").write_text(RANDOM_PROJECTION)
    params = yaml.safe_load((root / "params.yaml").read_text())
    params["learners"].append("random_projection")
    params["random_projection"] = {"n_dims": 24}
    (root / "params.yaml").write_text(yaml.safe_dump(params, sort_keys=False))


@pytest.mark.e2e
def test_a_learner_added_in_its_module_and_its_params_runs_through_dvc_repro(tmp_path, small_seed_cache):
    root = committed_run(tmp_path / "workspace", small_seed_cache)  # the run it is added to
    add_learner(root)
    changed = git(root, "status", "--porcelain").stdout.split("\n")
    assert sorted(line[3:] for line in changed if line) == ["params.yaml", "src/seasonloop/models/random_projection.py"]

    # the copy's own library (the installed one is this checkout's)
    result = dvc(root, "repro")
    assert result.returncode == 0, result.stdout[-3000:] + result.stderr[-3000:]
    fitted = yaml.safe_load((root / "models/random_projection/learner.json").read_text())
    assert fitted["params"] == {"n_dims": 24}
    summary = yaml.safe_load((root / "metrics/mean_fraction_correct.json").read_text())
    assert {"random_projection", "random_projection+seq"} <= set(summary)
    assert "random_projection" in (root / "plots/report.html").read_text()
    # the learners the run had are neither refitted nor described or evaluated again (their stages
    # depend on their own modules, not on the registry of names)
    ran = {line.split("'")[1] for line in result.stdout.splitlines() if line.startswith("Running stage '")}
    assert {"fit@random_projection", "features@random_projection", "evaluate@random_projection"} <= ran
    assert not ran & {
        f"{stage}@{learner}" for stage in ("fit", "features", "evaluate") for learner in ("pca", "raw_patchnorm")
    }

    # its declared params are what params.yaml's check (the first thing every stage does) reads
    params = yaml.safe_load((root / "params.yaml").read_text())
    params["random_projection"] = {"n_dim": 24}
    (root / "params.yaml").write_text(yaml.safe_dump(params, sort_keys=False))
    check = "import yaml; from seasonloop.registries.choices import check_whole; check_whole(yaml.safe_load(open('params.yaml')))"
    result = subprocess.run(
        [sys.executable, "-c", check],
        cwd=root,
        env=tool_env(PYTHONPATH=str(root / "src")),
        capture_output=True,
        text=True,
    )
    assert result.returncode != 0
    assert "random_projection.n_dim: unknown key (known: n_dims)" in result.stderr
