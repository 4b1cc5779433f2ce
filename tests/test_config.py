"""The params schema: every key of every section checked, errors naming the key."""

from __future__ import annotations

import copy
import inspect
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import torch
import yaml

from seasonloop.evaluation.sequence import enhance_distance_contrast
from seasonloop.models import ica
from seasonloop.models.core.ica_densities import DENSITIES
from seasonloop.models.core.lookup import LEARNERS, get_learner
from seasonloop.models.core.torch_ica import WHITEN_SOLVERS
from seasonloop.models.fae import ACTIVATIONS
from seasonloop.params import choices
from seasonloop.params.schema import TOP_LEVEL
from seasonloop.params.settings import SCHEMA
from seasonloop.preset import composed_params
from seasonloop.registries.choices import CHOICES, check_params, check_whole

REPO = Path(__file__).resolve().parents[1]
ALL_KEYS = [*SCHEMA, *TOP_LEVEL]


@pytest.fixture
def params():
    return yaml.safe_load((REPO / "params.yaml").read_text())


@pytest.mark.parametrize("preset", [None, *sorted(path.stem for path in (REPO / "presets").glob("*.yaml"))])
def test_the_shipped_params_pass(preset):
    params = REPO / "params.yaml"
    check_whole(
        yaml.safe_load(params.read_text()) if preset is None else composed_params(preset, params, REPO / "presets")
    )


def test_every_section_of_params_yaml_has_a_schema(params):
    # a section nobody checks would accept typos silently
    for name in params:
        assert name in SCHEMA or name in TOP_LEVEL or name in LEARNERS, name
    for name, section in SCHEMA.items():
        assert set(params[name]) == set(section), name
    for name in LEARNERS:
        assert set(params[name]) == set(get_learner(name).PARAMS), name


@pytest.mark.parametrize(
    "section, key, value, message",
    [
        ("split", "tets_fraction", 0.1, "split.tets_fraction: unknown key"),
        ("evaluate", "metirc", "cosine", "evaluate.metirc: unknown key"),
    ],
)
def test_a_typo_is_an_error_naming_the_key(params, section, key, value, message):
    params[section][key] = value
    with pytest.raises(ValueError, match=message.replace(".", r"\.")):
        check_params(params, [section])


@pytest.mark.parametrize(
    "key, value, message",
    [
        ("split.test_fraction", 0.9, r"split\.test_fraction: expected a number in \(0, 0.5\]"),
        ("split.gap", -1, r"split\.gap: expected an integer >= 0"),
        ("evaluate.metric", "manhattan", r"evaluate\.metric: unknown value 'manhattan'"),
        ("evaluate.tolerance_frames", 1.5, r"evaluate\.tolerance_frames: expected an integer"),
        ("evaluate.matchers", ["single", "seq"], r"evaluate\.matchers: unknown value 'seq'"),
        ("evaluate.pairs", ["summer-autumn"], r"evaluate\.pairs: unknown traverse 'autumn'"),
        ("data.frame_step", 0, r"data\.frame_step: expected an integer >= 1"),
        ("data.source", "vidoes", r"data\.source: unknown value 'vidoes'"),
        ("extract.trim_to_shortest", "yes", r"extract\.trim_to_shortest: expected true or false"),
        ("augment.width_shift", 1.0, r"augment\.width_shift"),
        ("ablation.learners", ["pca", "sift"], r"ablation\.learners: unknown value 'sift'"),
        (
            "ablation.training_seasons",
            [["summer"], ["autumn"]],
            r"ablation\.training_seasons: unknown traverse 'autumn'",
        ),
        ("report.example_pair", "summer_fall", r"report\.example_pair"),
        ("data.video_files", {"autumn": "a.mp4"}, r"data\.video_files: unknown traverse 'autumn'"),
        ("synthetic.cruise_speed", 5.0, r"synthetic\.cruise_speed: expected a number in \[10, 70\]"),
        ("synthetic.tunnel_every_s", 0, r"synthetic\.tunnel_every_s: expected a number in \(0, inf\)"),
        ("synthetic.stop_min_s", 0, r"synthetic\.stop_min_s: expected an integer >= 1"),
        ("synthetic.event_gap_s", 2.5, r"synthetic\.event_gap_s: expected an integer"),
        ("synthetic.winter_contrast", 0.0, r"synthetic\.winter_contrast: expected a number in \(0, 2\]"),
    ],
)
def test_a_bad_value_is_an_error_naming_the_key(params, key, value, message):
    section, name = key.split(".")
    params[section][name] = value
    with pytest.raises(ValueError, match=message) as error:
        check_params(params, [section])
    assert "\n" not in str(error.value)  # one line
    # the dotted key alone is checked too
    with pytest.raises(ValueError, match=message):
        check_params(params, [key])


def test_checks_across_a_section(params):
    bad = copy.deepcopy(params)
    bad["split"].update(section_length=10, test_fraction=0.5, gap=3)
    with pytest.raises(ValueError, match="leaves no training place"):
        check_params(bad, ["split"])
    bad = copy.deepcopy(params)
    bad["synthetic"].update(tunnel_min_s=30, tunnel_max_s=20)
    with pytest.raises(ValueError, match=r"synthetic\.tunnel_max_s: 20 is below synthetic\.tunnel_min_s 30"):
        check_params(bad, ["synthetic"])
    bad = copy.deepcopy(params)
    bad["sequence"].update(v_min=1.2, v_max=0.8)
    with pytest.raises(ValueError, match=r"sequence\.v_max"):
        check_params(bad, ["sequence"])
    bad = copy.deepcopy(params)
    bad["evaluate"].update(metric="cosine", extra_metrics=["cityblock", "cosine"])
    with pytest.raises(ValueError, match=r"^evaluate\.extra_metrics: 'cosine' is already evaluate\.metric$"):
        check_params(bad, ["evaluate"])


def test_missing_and_unknown_top_level_keys(params):
    del params["evaluate"]["metric"]
    with pytest.raises(ValueError, match=r"missing key 'evaluate\.metric'"):
        check_params(params, ["evaluate"])
    params["evaluat"] = {}
    with pytest.raises(ValueError, match="params.yaml: unknown key 'evaluat'"):
        check_whole(params)
    del params["evaluat"]
    with pytest.raises(ValueError, match=r"unknown key 'split\.tets_fraction'"):
        check_params(params, ["split.tets_fraction"])


def test_only_the_keys_asked_for_are_checked(params):
    # a stage checks what it reads: another section's bad value is that stage's business
    params["split"]["test_fraction"] = 0.9
    check_params(params, ["data.seasons", "evaluate"])
    # a learner's section is checked by its class when asked for
    params["pca"]["n_kep"] = 3
    check_params(params, ["data.seasons"])
    with pytest.raises(ValueError, match=r"^pca\.n_kep: unknown key"):
        check_params(params, ["pca"])


def test_every_choice_is_a_declared_key_and_its_registry_holds_names(params):
    # a choice is checked against the library's registry itself (seasonloop.registries.CHOICES)
    for key, names in CHOICES.items():
        section, _, sub = key.partition(".")
        assert (sub in SCHEMA[section]) if sub else (key in TOP_LEVEL), key
        assert names and all(isinstance(name, str) for name in names), key


@pytest.mark.parametrize("key", list(CHOICES))
def test_a_name_no_registry_holds_is_refused_with_its_key(params, key):
    section, _, sub = key.partition(".")
    holder, name = (params[section], sub) if sub else (params, key)
    holder[name] = ["nosuch"] if isinstance(holder[name], list) else "nosuch"
    with pytest.raises(ValueError, match=rf"^{key}: unknown value 'nosuch'"):
        check_whole(params)


def test_checking_params_imports_no_heavy_module():
    # every stage checks the whole params.yaml first, reading the registries and every learner's
    # declared params: that must not import torch, scikit-learn, pandas or OpenCV (seconds a stage)
    code = (
        "import sys, yaml; from seasonloop.registries.choices import check_whole; "
        "check_whole(yaml.safe_load(open('params.yaml'))); "
        "print(sorted({'torch', 'sklearn', 'pandas', 'joblib', 'cv2'} & set(sys.modules)))"
    )
    result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True, cwd=REPO)
    assert result.stdout.strip() == "[]"


def test_the_whole_file_is_checked_before_any_stage_works():
    # a typo in a section the first stages never read still stops them (stages/_common.load_params)
    params = yaml.safe_load((REPO / "params.yaml").read_text())
    check_whole(params)
    params["evaluate"]["metirc"] = params["evaluate"].pop("metric")
    with pytest.raises(ValueError, match=r"^evaluate.metirc: unknown key"):
        check_whole(params)
    params = yaml.safe_load((REPO / "params.yaml").read_text())
    params["cae"]["chanels"] = [6, 16, 24]
    with pytest.raises(ValueError, match=r"^cae.chanels: unknown key"):
        check_whole(params)


def test_a_learner_has_no_default_of_its_own_so_params_yaml_holds_the_only_one():
    # a learner declares each key's check, never a value: a section without a key is refused with
    # the key's name, so no value can hide in the code and differ from params.yaml's
    params = yaml.safe_load((REPO / "params.yaml").read_text())
    for name in LEARNERS:
        learner = get_learner(name)
        assert all(callable(check) and not hasattr(check, "default") for check in learner.PARAMS.values())
        learner.check_params(params[name])
        key = next(iter(learner.PARAMS))
        partial = {k: v for k, v in params[name].items() if k != key}
        with pytest.raises(ValueError, match=rf"^{name}\.{key}: missing"):
            learner(partial)


def test_what_a_learner_passes_its_settings_to_declares_no_default_for_them():
    # the ICA estimators and the contrast step take params.yaml's values explicitly: a default there
    # would be a second value of ica.tol, preprocess.clahe_clip, ... that the reader could trust
    from seasonloop.data.preprocess import enhance_image_contrast
    from seasonloop.models.core.fastica_sklearn import fit_fastica
    from seasonloop.models.core.torch_ica import TorchICA

    for function in (TorchICA.__init__, fit_fastica, enhance_image_contrast):
        defaults = [p.name for p in inspect.signature(function).parameters.values() if p.default is not p.empty]
        assert defaults == [], f"{function.__qualname__} declares defaults for {defaults}"


def test_the_torch_ica_solvers_implement_every_value_ica_declares():
    # ica.fun and ica.whiten_solver are scikit-learn FastICA's values; the torch solvers implement each
    assert tuple(DENSITIES) == ica.ICA_FUNCTIONS
    assert tuple(WHITEN_SOLVERS) == ica.WHITEN_SOLVERS
    for activation in ACTIVATIONS.values():
        assert issubclass(getattr(torch.nn, activation), torch.nn.Module)


def test_a_bad_learner_value_stops_the_whole_file_check():
    # a value out of range in a learner's section is caught before any stage works, not at its fit
    params = yaml.safe_load((REPO / "params.yaml").read_text())
    params["pca"]["svd_solver"] = "ful"
    with pytest.raises(ValueError, match=r"^pca.svd_solver: unknown value 'ful'"):
        check_whole(params)


def test_the_schema_accepts_only_what_the_code_accepts():
    # sequence.window: the schema's lowest value runs, the one below it fails in both
    distances = np.random.default_rng(0).random((6, 8))
    enhance_distance_contrast(distances, window=choices.MIN_SEQUENCE_WINDOW)
    with pytest.raises(ValueError):
        enhance_distance_contrast(distances, window=choices.MIN_SEQUENCE_WINDOW - 1)
    with pytest.raises(ValueError, match="sequence.window"):
        SCHEMA["sequence"]["window"]("sequence.window", choices.MIN_SEQUENCE_WINDOW - 1)
