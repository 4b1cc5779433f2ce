"""The CAE width sweep: channels per width, closeness to the raw image, and the sweep's record."""

import json
from pathlib import Path

import numpy as np
import pytest
import yaml
from sequence_settings import sequence_config

from seasonloop.ablations.cae_widths import (
    agreement,
    mean_cosine,
    run_width_sweep,
    width_channels,
    width_label,
    width_table,
    write_skipped_sweep,
    write_width_sweep,
)
from seasonloop.data.ground_truth import aligned_truth
from seasonloop.evaluation.context import EvaluationContext
from seasonloop.models.cae import ConvolutionalAutoEncoder
from seasonloop.models.raw_patchnorm import RawPatchNorm
from seasonloop.params.settings import EvaluateConfig, StatisticsConfig
from seasonloop.registries.choices import check_whole
from seasonloop.reporting.html import build_report
from seasonloop.reporting.model_sections import cae_widths_section
from tools.repository import learner_params

PARAMS = Path(__file__).resolve().parents[1] / "params.yaml"


def test_widths_are_fractions_of_table_5():
    assert width_channels(1) == [96, 256, 384]
    assert width_channels(0.0625) == [6, 16, 24]
    assert width_channels(0.001) == [1, 1, 1]
    assert (width_label(0.0625), width_label(0.25), width_label(1.0)) == ("1/16", "1/4", "1")
    for bad in (0, 1.5, "half", True):
        with pytest.raises(ValueError, match="cae_widths.widths"):
            width_channels(bad)


def test_mean_cosine_and_agreement():
    rng = np.random.default_rng(0)
    vectors = rng.normal(size=(5, 8))
    assert mean_cosine(vectors, 3 * vectors) == pytest.approx(1.0)
    assert mean_cosine(vectors, -vectors) == pytest.approx(-1.0)
    assert mean_cosine(np.zeros((2, 8)), vectors[:2]) == 0.0
    database = rng.normal(size=(6, 8))
    queries = database + rng.normal(0, 0.01, size=(6, 8))
    # the same descriptors, and a scaled copy, choose the same best matches
    assert agreement((database, queries), (2 * database, 2 * queries), "cosine") == 1.0
    # reversed queries: each query's best match moves
    assert agreement((database, queries), (database, queries[::-1]), "euclidean") == 0.0


def textured_images(n: int, seed: int) -> np.ndarray:
    """(n, 8, 16) uint8 in [0, 200): room to brighten without clipping."""
    return (np.random.default_rng(seed).random((n, 8, 16)) * 200).astype(np.uint8)


def test_sweep_record_table_and_figure(tmp_path):
    places = np.arange(12)
    summer = textured_images(12, 1)
    test = {"summer": summer, "fall": np.clip(summer.astype(int) + 5, 0, 255).astype(np.uint8)}
    evaluate = EvaluateConfig(
        pairs=("summer-fall",),
        metric="cosine",
        extra_metrics=(),
        confidence="distance",
        ratio_exclusion=0,
        tolerance_frames=0,
        tolerance_m=10.0,
        matchers=("single",),
    )
    sequence = sequence_config(v_min=0.8, v_max=1.2, v_steps=3, window=2)
    raw = RawPatchNorm(learner_params("raw_patchnorm", {"patch_size": 4}), seed=0)
    raw.fit(summer, progress=False)
    fitted_channels = []

    def new_cae(channels):
        fitted_channels.append(channels)
        return ConvolutionalAutoEncoder(
            learner_params(
                "cae",
                {
                    "channels": channels,
                    "kernels": [3, 3, 3],
                    "max_epochs": 2,
                    "batch_size": 8,
                    "patch_size": 4,
                    "validation_block": 3,
                    "precision": "float32",
                    "max_train_images": 0,
                    "max_validation_images": 0,
                },
            ),
            seed=0,
        )

    training = textured_images(60, 2), np.tile(np.arange(30), 2)
    context = EvaluationContext(
        test,
        {("summer", "fall"): aligned_truth(places, places, 0)},
        [("summer", "fall")],
        evaluate,
        sequence,
        StatisticsConfig(level=0.95, degrees_scale=0.15, persistence_scale=0.38, alpha=0.05),
        batch_size=16,
    )
    record = run_width_sweep([1 / 32, 1 / 48], new_cae, raw, training, context)
    assert fitted_channels == [[3, 8, 12], [2, 5, 8]]
    # every fraction correct with its interval: here too few queries for one, and it says so
    for descriptor in (record["widths"]["1/32"]["output_patchnorm"], record["raw_patchnorm"]):
        interval = descriptor["interval"]["summer-fall"]
        assert interval["low"] is None and "not enough queries" in interval["reason"]
    assert list(record["widths"]) == ["1/32", "1/48"]
    row = record["widths"]["1/32"]
    assert row["channels"] == [3, 8, 12] and row["stop_reason"] == "max_epochs" and row["converged"] is False
    assert -1 <= row["cosine_with_input"] <= 1
    for descriptor in ("output_patchnorm", "code"):
        assert 0 <= row[descriptor]["fraction_correct"]["summer-fall"] <= 1
        assert 0 <= row[descriptor]["agreement_with_raw"]["summer-fall"] <= 1
    # the raw image's own row: the fall images are the summer ones a little brighter, which
    # patch normalisation removes
    assert record["raw_patchnorm"]["fraction_correct"]["summer-fall"] == 1.0
    table = width_table(record)
    assert table.count("\n") == 2 + 2 + 1 and "| 1/32 | 3/8/12 | no: max_epochs (2) |" in table
    write_width_sweep(record, tmp_path / "sweep.json", tmp_path / "sweep.png", tmp_path / "sweep.md")
    assert json.loads((tmp_path / "sweep.json").read_text()) == json.loads(json.dumps(record))
    assert (tmp_path / "sweep.md").read_text() == table
    # read back from JSON (keys sorted as text: "1/32" < "1/48"), the rows still go narrowest first
    reread = width_table(json.loads((tmp_path / "sweep.json").read_text()))
    assert reread.index("| 1/48 |") < reread.index("| 1/32 |") and reread == width_table(
        {**record, "widths": dict(reversed(record["widths"].items()))}
    )
    assert (tmp_path / "sweep.png").read_bytes().startswith(b"\x89PNG")


def test_an_empty_sweep_writes_that_it_was_skipped(tmp_path):
    outputs = (tmp_path / "cae_widths.json", tmp_path / "cae_widths.png", tmp_path / "cae_widths.md")
    write_skipped_sweep(*outputs)
    assert json.loads(outputs[0].read_text()) == {"skipped": "skipped: cae_widths.widths is empty"}
    assert outputs[1].read_bytes().startswith(b"\x89PNG") and "skipped" in outputs[2].read_text()
    section = cae_widths_section(json.loads(outputs[0].read_text()), outputs[1].read_bytes())
    page = build_report("r", [section])
    assert "The CAE width sweep was skipped: cae_widths.widths is empty." in page


def test_the_params_accept_an_empty_sweep_and_no_other_empty_list():
    params = yaml.safe_load(PARAMS.read_text())
    check_whole({**params, "cae_widths": {**params["cae_widths"], "widths": []}})
    with pytest.raises(ValueError, match="cae_widths.pairs: expected a non-empty list"):
        check_whole({**params, "cae_widths": {**params["cae_widths"], "pairs": []}})
