"""Typed sections: every key of params.yaml declared with its check, built from the shipped params, bad keys named."""

from __future__ import annotations

import copy
from dataclasses import FrozenInstanceError
from pathlib import Path

import pytest
import yaml

from seasonloop.params.section import _frozen
from seasonloop.params.settings import SCHEMA, SECTIONS, AblationConfig, EvaluateConfig, SplitConfig
from seasonloop.preset import composed_params

REPO = Path(__file__).resolve().parents[1]


@pytest.fixture
def params():
    return yaml.safe_load((REPO / "params.yaml").read_text())


def test_every_section_of_params_yaml_is_declared_with_a_check_for_each_key(params):
    # SCHEMA is read from the declarations: every key of params.yaml's sections has one
    learner_and_top = {"seed", "learners", *(name for name in params if name not in SCHEMA)}
    assert {section.NAME for section in SECTIONS} == set(params) - learner_and_top
    for section in SECTIONS:
        assert set(section.keys()) == set(params[section.NAME]), section.NAME
        assert all(callable(check) for check in SCHEMA[section.NAME].values())


@pytest.mark.parametrize("preset", [None, "full"])
def test_shipped_params_build_every_section(preset):
    path = REPO / "params.yaml"
    params = yaml.safe_load(path.read_text()) if preset is None else composed_params(preset, path, REPO / "presets")
    for section in SECTIONS:
        config = section.from_params(params)
        for key in section.keys():  # noqa: SIM118 (Section.keys, not a dict)
            value = params[section.NAME][key]
            assert getattr(config, key) == _frozen(value), (section.NAME, key)


def test_lists_become_tuples_and_configs_are_immutable(params):
    ablation = AblationConfig.from_params(params)
    assert isinstance(ablation.training_seasons, tuple) and isinstance(ablation.training_seasons[0], tuple)
    evaluate = EvaluateConfig.from_params(params)
    with pytest.raises(FrozenInstanceError):
        evaluate.metric = "euclidean"


def test_a_bad_key_is_named(params):
    bad = copy.deepcopy(params)
    bad["split"]["tets_fraction"] = bad["split"].pop("test_fraction")
    with pytest.raises(ValueError, match=r"split.tets_fraction: unknown key"):
        SplitConfig.from_params(bad)
    bad = copy.deepcopy(params)
    bad["split"]["gap"] = -1
    with pytest.raises(ValueError, match=r"split.gap"):
        SplitConfig.from_params(bad)
