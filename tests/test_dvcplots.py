import numpy as np
import pytest

from seasonloop.reporting.dvcplots import pr_long, training_curves


def test_pr_long_has_one_row_per_point_and_a_learner_column():
    table = pr_long(
        {"pca": (np.array([0.5, 1.0]), np.array([1.0, 0.5])), "pca+seq": (np.array([1.0]), np.array([0.9]))}
    )
    assert list(table.columns) == ["learner", "recall", "precision"]
    assert table["learner"].tolist() == ["pca", "pca", "pca+seq"]
    assert table["precision"].tolist() == [1.0, 0.5, 0.9]
    assert pr_long({}).columns.tolist() == ["learner", "recall", "precision"]


def test_training_curves_reads_dvclive_logs_of_the_learners_asked(tmp_path):
    log = tmp_path / "fae/plots/metrics/train"
    log.mkdir(parents=True)
    (log / "loss.tsv").write_text("step\tloss\n0\t1.0\n1\t0.5\n")
    (tmp_path / "cae/plots/metrics/train").mkdir(parents=True)
    (tmp_path / "cae/plots/metrics/train/loss.tsv").write_text("step\tloss\n0\t9\n")
    table = training_curves(tmp_path, ["pca", "fae"])  # pca has no log; cae is not asked for
    assert table["learner"].tolist() == ["fae", "fae"]
    assert table["metric"].tolist() == ["train/loss", "train/loss"]
    assert table["value"].tolist() == [1.0, 0.5]
    assert training_curves(tmp_path, ["pca"]).empty


def test_training_curves_rejects_a_non_step_log(tmp_path):
    log = tmp_path / "fae/plots/metrics"
    log.mkdir(parents=True)
    (log / "x.tsv").write_text("a\tb\n1\t2\n")
    with pytest.raises(ValueError, match="x.tsv"):
        training_curves(tmp_path, ["fae"])
