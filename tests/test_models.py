import ast
import inspect
import json
import subprocess
import sys
import warnings

import numpy as np
import pytest
import torch
from sklearn.decomposition import PCA
from sklearn.exceptions import ConvergenceWarning

from seasonloop.models.core.learner import RUN_KEYS, FeatureLearner, to_float
from seasonloop.models.core.lookup import LEARNERS, get_learner, load_learner
from seasonloop.models.core.upsampling import UpsampledConv2d
from tools.repository import learner_params

N_PER_FAMILY = 100
HEIGHT, WIDTH = 16, 32

# Small, fast settings per learner and the descriptor length they give on 16x32 images.
TEST_PARAMS = {
    "raw_patchnorm": ({}, HEIGHT * WIDTH),
    "pca": ({"n_discard": 2, "n_keep": 16}, 16),
    "pca_whiten": ({"n_discard": 2, "n_keep": 16}, 16),
    # 200 images < 512 pixels: svd whitening copes with the rank deficiency without a warning.
    "ica": ({"n_components": 16, "whiten_solver": "svd"}, 16),
    "ica_bovw": ({"patch_size": 4, "stride": 4, "n_train_patches": 5000, "n_components": 15, "n_words": 16}, 16),
    "fae": ({"hidden": 32, "max_epochs": 5, "batch_size": 32}, HEIGHT * WIDTH),
    "cae": (
        {
            "channels": [8, 16, 16],
            "kernels": [5, 3, 3],
            "max_epochs": 5,
            "batch_size": 32,
            "max_train_images": 0,
            "max_validation_images": 0,
        },
        HEIGHT * WIDTH,
    ),
}


def gratings(n: int, orientation: str, rng: np.random.Generator) -> np.ndarray:
    """Noisy sinusoidal gratings of random period and phase, as uint8 (n, HEIGHT, WIDTH)."""
    rows, cols = np.mgrid[0:HEIGHT, 0:WIDTH].astype(np.float32)
    coordinate = rows if orientation == "horizontal" else cols
    period = rng.uniform(5, 9, size=(n, 1, 1))
    phase = rng.uniform(0, 2 * np.pi, size=(n, 1, 1))
    images = 0.5 + 0.3 * np.sin(2 * np.pi * coordinate / period + phase) + rng.normal(0, 0.1, (n, HEIGHT, WIDTH))
    return (np.clip(images, 0, 1) * 255).astype(np.uint8)


@pytest.fixture(scope="module")
def families() -> tuple[np.ndarray, np.ndarray]:
    """Two clearly different image families (horizontal vs vertical gratings) and their labels."""
    rng = np.random.default_rng(0)
    images = np.concatenate([gratings(N_PER_FAMILY, "horizontal", rng), gratings(N_PER_FAMILY, "vertical", rng)])
    return images, np.repeat([0, 1], N_PER_FAMILY)


@pytest.fixture(scope="module")
def fitted(families):
    """Fit each learner once per module, on demand."""
    cache: dict[str, FeatureLearner] = {}

    def get(name: str) -> FeatureLearner:
        if name not in cache:
            learner = get_learner(name)(learner_params(name, TEST_PARAMS[name][0]), seed=3)
            learner.fit(families[0], progress=False)
            cache[name] = learner
        return cache[name]

    return get


def nearest_neighbour_same_family(descriptors: np.ndarray, labels: np.ndarray) -> float:
    distances = ((descriptors[:, None, :] - descriptors[None, :, :]) ** 2).sum(axis=-1)
    np.fill_diagonal(distances, np.inf)
    return float((labels[distances.argmin(axis=1)] == labels).mean())


def test_every_module_of_the_models_package_is_the_learner_of_its_name():
    # the registry is the package's modules (no list to keep beside them): each holds its learner
    assert "pca" in LEARNERS and "core" not in LEARNERS
    for name in LEARNERS:
        learner_class = get_learner(name)
        assert learner_class.name == name and learner_class.__module__ == f"seasonloop.models.{name}"
        learner_class(learner_params(name), seed=0)  # params.yaml's section passes its validation


def test_a_learners_tiny_run_settings_are_checked_keys_of_its_section():
    # what the tests' tiny runs set for a learner (tools.small_runs) is the learner's own to say
    for name in LEARNERS:
        learner_class = get_learner(name)
        learner_class.check_params(learner_params(name, learner_class.TINY_RUN))


def test_the_registry_imports_only_the_learner_asked_for():
    # a stage that fits pca must not run (or depend on) the auto-encoders' modules, nor import torch
    code = (
        "import sys; from seasonloop.models.core.lookup import get_learner; get_learner('pca'); "
        "print(sorted(m for m in sys.modules if m.startswith('seasonloop.models.') or m == 'torch'))"
    )
    loaded = subprocess.run([sys.executable, "-c", code], check=True, capture_output=True, text=True).stdout
    assert "seasonloop.models.pca'" in loaded
    assert "seasonloop.models.cae" not in loaded and "seasonloop.models.ica" not in loaded and "'torch'" not in loaded


def imports_inside_functions(module: object) -> set[str]:
    """The modules imported inside the functions of `module`'s source (the imports a learner defers)."""
    tree = ast.parse(inspect.getsource(module))
    found: set[str] = set()
    for function in (node for node in ast.walk(tree) if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef))):
        for node in ast.walk(function):
            if isinstance(node, ast.Import):
                found |= {alias.name for alias in node.names}
            elif isinstance(node, ast.ImportFrom) and node.module and not node.level:
                found.add(node.module)
    return found


@pytest.mark.parametrize("name", list(LEARNERS))
def test_a_learner_lists_every_library_its_methods_import(name):
    # the fit stage imports LIBRARIES before its timer: an import a learner defers and the list
    # leaves out would count Python's import in fit_seconds
    learner = get_learner(name)
    modules = {sys.modules[cls.__module__] for cls in learner.__mro__ if cls.__module__.startswith("seasonloop.")}
    deferred = set().union(*(imports_inside_functions(module) for module in modules))
    listed = set(learner.LIBRARIES)
    missing = sorted(
        m for m in deferred if not any(m == lib or m.startswith(lib + ".") or lib.startswith(m + ".") for lib in listed)
    )
    # tqdm draws a progress bar and TYPE_CHECKING imports never run
    assert not [m for m in missing if m.split(".")[0] != "tqdm"], missing


@pytest.mark.parametrize("name", list(TEST_PARAMS))
def test_descriptor_shape_and_family_separation(name, fitted, families):
    images, labels = families
    learner = fitted(name)
    descriptors = learner.describe(images)
    assert descriptors.shape == (len(images), TEST_PARAMS[name][1])
    assert descriptors.dtype == np.float32 and np.isfinite(descriptors).all()
    assert nearest_neighbour_same_family(descriptors, labels) > 0.9
    json.dumps(learner.fit_info)  # fit info must be JSON-serialisable
    np.testing.assert_allclose(learner.describe(images, batch_size=7), descriptors, rtol=1e-4, atol=1e-5)


@pytest.mark.parametrize("name", list(TEST_PARAMS))
def test_fit_is_deterministic_for_a_seed(name, fitted, families):
    refit = get_learner(name)(learner_params(name, TEST_PARAMS[name][0]), seed=3)
    refit.fit(families[0], progress=False)
    np.testing.assert_array_equal(refit.describe(families[0]), fitted(name).describe(families[0]))


@pytest.mark.parametrize("name", list(TEST_PARAMS))
def test_a_models_bytes_are_its_content(name, fitted, families, tmp_path):
    """The same fit twice saves byte-identical files: no time, device or thread count in models/
    (those are the run's facts: fit returns them for metrics/fit/), so DVC sees the same model."""
    refit = get_learner(name)(learner_params(name, TEST_PARAMS[name][0]), seed=3)
    info = refit.fit(families[0], progress=False)
    assert refit.fit_info is not None and not set(RUN_KEYS) & set(refit.fit_info)
    for saved, learner in (("first", fitted(name)), ("second", refit)):
        learner.save(tmp_path / saved)
    files = sorted(path.name for path in (tmp_path / "first").iterdir())
    assert files == sorted(path.name for path in (tmp_path / "second").iterdir())
    for file in files:
        assert (tmp_path / "first" / file).read_bytes() == (tmp_path / "second" / file).read_bytes(), file
    assert {key: value for key, value in info.items() if key not in RUN_KEYS} == refit.fit_info


# pca's default solver (covariance_eigh) is exact and uses no randomness, so the seed cannot
# change it; its randomized solver does use the seed.
@pytest.mark.parametrize("name", ["ica", "ica_bovw", "fae"])
def test_other_seed_changes_the_model(name, fitted, families):
    other = get_learner(name)(learner_params(name, TEST_PARAMS[name][0]), seed=4)
    other.fit(families[0], progress=False)
    assert not np.array_equal(other.describe(families[0]), fitted(name).describe(families[0]))


@pytest.mark.parametrize("name", list(TEST_PARAMS))
def test_saved_learner_loads_with_identical_descriptors(name, fitted, families, tmp_path):
    learner = fitted(name)
    learner.save(tmp_path)
    record = json.loads((tmp_path / "learner.json").read_text())
    assert record["name"] == name and record["seed"] == 3 and record["input_shape"] == [HEIGHT, WIDTH]
    loaded = load_learner(tmp_path)
    assert type(loaded) is type(learner) and loaded.params == learner.params
    np.testing.assert_array_equal(loaded.describe(families[0]), learner.describe(families[0]))
    with pytest.raises(ValueError, match="holds a"):
        get_learner("raw_patchnorm" if name != "raw_patchnorm" else "pca").load(tmp_path)


def test_a_model_saved_before_a_params_key_existed_names_its_file(fitted, tmp_path):
    # code that added a key to a learner's section cannot load a model saved without it (train.fitted:
    # elsewhere at an older clone's models/): the error names that model's learner.json
    fitted("pca").save(tmp_path)
    record = json.loads((tmp_path / "learner.json").read_text())
    del record["params"]["n_keep"]
    (tmp_path / "learner.json").write_text(json.dumps(record))
    with pytest.raises(ValueError, match=r"learner\.json: pca\.n_keep: missing .*fit it again"):
        load_learner(tmp_path)


def test_pca_without_discard_reconstructs_like_sklearn(families):
    images = families[0]
    learner = get_learner("pca")(learner_params("pca", {"n_discard": 0, "n_keep": 12}), seed=5)
    learner.fit(images, progress=False)
    flat = to_float(images).reshape(len(images), -1)
    reference = PCA(n_components=12, svd_solver="randomized", random_state=5).fit(flat)
    expected = reference.inverse_transform(reference.transform(flat)).reshape(images.shape)
    np.testing.assert_allclose(learner.reconstruct(images, 0, 12), expected, atol=1e-4)
    # Later components alone carry no mean, so they reconstruct a zero-mean residual.
    partial = learner.reconstruct(images, 6, 12)
    assert abs(partial.mean()) < 0.05 < abs(expected.mean())
    with pytest.raises(ValueError, match="component range"):
        learner.reconstruct(images, 0, 13)


def test_pca_fit_info_and_too_many_components(families):
    learner = get_learner("pca")(learner_params("pca", {"n_discard": 3, "n_keep": 5}), seed=0)
    info = learner.fit(families[0], progress=False)
    assert 0 < info["explained_variance_ratio_kept"] < info["explained_variance_ratio_discarded"] < 1
    with pytest.raises(ValueError, match=r"pca\.n_discard \+ pca\.n_keep"):
        get_learner("pca")(learner_params("pca", {"n_discard": 150, "n_keep": 100})).fit(families[0], progress=False)


def independent_pattern_images(n: int, seed: int) -> np.ndarray:
    """uint8 (n, 8, 16) images: 6 fixed patterns weighted by independent Laplace sources, plus a
    little noise, so the top 6 principal components stand far above the rest."""
    patterns = np.random.default_rng(100).normal(size=(6, 8 * 16))
    rng = np.random.default_rng(seed)
    pixels = 128 + 6 * rng.laplace(size=(n, 6)) @ patterns + rng.normal(0, 1, (n, 8 * 16))
    return np.clip(pixels, 0, 255).astype(np.uint8).reshape(n, 8, 16)


def test_whitened_pca_matches_ica_distances_under_cosine_and_euclidean_only():
    from seasonloop.evaluation.distances import distance_matrix

    train, database, queries = (independent_pattern_images(n, seed) for n, seed in ((3000, 0), (60, 1), (50, 2)))
    k = 6
    ica = get_learner("ica")(learner_params("ica", {"n_components": k, "max_iter": 400}), seed=0)
    assert ica.fit(train, progress=False)["converged"]
    whitened = get_learner("pca_whiten")(learner_params("pca_whiten", {"n_discard": 0, "n_keep": k}), seed=0)
    whitened.fit(train, progress=False)
    # Unit variance on the training images, as FastICA's sources.
    np.testing.assert_allclose(whitened.describe(train).std(axis=0), 1.0, atol=1e-4)
    described = {
        name: (learner.describe(database), learner.describe(queries))
        for name, learner in (("ica", ica), ("pca_whiten", whitened))
    }
    deviation = {}
    for metric in ("cosine", "euclidean", "cityblock"):
        ica_distances, pca_distances = (distance_matrix(*described[name], metric) for name in ("ica", "pca_whiten"))
        deviation[metric] = np.abs(ica_distances - pca_distances).max() / np.abs(ica_distances).max()
    # Same subspace and orthogonal W: only float32 rounding of two separate eigen-decompositions and
    # of FastICA's orthogonalisation differs (~1e-6 relative, 2 orders below the bound).
    assert deviation["cosine"] < 1e-4 and deviation["euclidean"] < 1e-4
    # The bound is meaningful: under L1 the rotation changes distances by far more.
    assert deviation["cityblock"] > 1e-2


@pytest.mark.parametrize("solver", ["full", "covariance_eigh"])
def test_pca_whiten_refuses_components_it_cannot_resolve(solver):
    # 60 images of 6 patterns plus faint noise span 59 directions once centred; a 60th would be
    # rounding noise scaled up to unit variance. In float64 (core/projection.py) covariance_eigh,
    # which forms the uncentred X^T X, resolves the faint ones too (in float32 it did not).
    few = independent_pattern_images(60, 0)
    get_learner("pca_whiten")(learner_params("pca_whiten", {"n_keep": 59, "svd_solver": solver})).fit(
        few, progress=False
    )
    with pytest.raises(
        ValueError, match=rf"pca_whiten\.n_discard \+ pca_whiten\.n_keep = 60 exceeds the 59 .*'{solver}'"
    ):
        get_learner("pca_whiten")(learner_params("pca_whiten", {"n_keep": 60, "svd_solver": solver})).fit(
            few, progress=False
        )


def test_ica_records_non_convergence_without_warning(families):
    learner = get_learner("ica")(
        learner_params("ica", {"n_components": 8, "max_iter": 2, "whiten_solver": "svd"}), seed=0
    )
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        info = learner.fit(families[0], progress=False)
    assert not [warning for warning in caught if issubclass(warning.category, ConvergenceWarning)]
    assert info["converged"] is False and info["n_iter"] == info["max_iter"] == 2
    assert info["convergence_warnings"]


def test_ica_training_subset_and_component_limit(families):
    learner = get_learner("ica")(
        learner_params("ica", {"n_components": 8, "whiten_solver": "svd", "max_train_images": 50}), seed=0
    )
    info = learner.fit(families[0], progress=False)
    assert info["n_train_images"] == 50 and info["n_train_images_available"] == 2 * N_PER_FAMILY
    with pytest.raises(ValueError, match=r"ica\.n_components"):
        get_learner("ica")(learner_params("ica", {"n_components": 60, "max_train_images": 50})).fit(
            families[0], progress=False
        )


def test_ica_bovw_histograms_filters_and_word_examples(fitted, families):
    learner = fitted("ica_bovw")
    descriptors = learner.describe(families[0][:10])
    np.testing.assert_allclose(descriptors.sum(axis=1), 1.0, rtol=1e-6)
    assert (descriptors >= 0).all()
    assert learner.filters().shape == (15, 4, 4)
    examples = learner.word_examples(families[0], n_words=5, n_examples=3)
    assert examples.shape == (5, 3, 4, 4)
    assert np.nanmin(examples) >= 0 and np.nanmax(examples) <= 1
    with pytest.raises(ValueError, match="n_components"):
        get_learner("ica_bovw")(learner_params("ica_bovw", {"patch_size": 4, "n_components": 16}))


@pytest.mark.parametrize("name, code_length", [("fae", 32), ("cae", 16 * (HEIGHT // 4) * (WIDTH // 4))])
def test_autoencoder_descriptors_and_epoch_callback(name, code_length, fitted, families):
    images = families[0][:12]
    learner = fitted(name)
    assert learner.describe_as(images, "code").shape == (12, code_length)
    output = learner.describe_as(images, "output")
    assert output.shape == (12, HEIGHT * WIDTH) and output.min() >= 0 and output.max() <= 1
    np.testing.assert_array_equal(learner.describe_as(images, "output_patchnorm"), learner.describe(images))
    with pytest.raises(ValueError, match="descriptor"):
        learner.describe_as(images, "bottleneck")
    # one forward pass for Figure 19 gives what the two separate passes give, batch size aside
    code, output_once = learner.describe_code_and_output(images, batch_size=5)
    np.testing.assert_array_equal(code, learner.describe_as(images, "code", batch_size=5))
    np.testing.assert_array_equal(output_once, learner.describe_as(images, "output", batch_size=5))
    epochs_seen = []
    params = {**TEST_PARAMS[name][0], "max_epochs": 2, "max_train_images": 40}
    info = get_learner(name)(learner_params(name, params)).fit(
        families[0], progress=False, on_epoch=lambda epoch, metrics: epochs_seen.append((epoch, metrics))
    )
    assert [epoch for epoch, _ in epochs_seen] == [1, 2] and info["n_train_images"] == 40
    assert get_learner(name).trains_in_epochs  # stages/fit.py logs its epochs with dvclive
    assert [metrics["train_loss"] for _, metrics in epochs_seen] == info["loss_per_epoch"]
    assert [metrics["validation_loss"] for _, metrics in epochs_seen] == info["validation_loss_per_epoch"]
    assert info["stop_reason"] == "max_epochs" and info["converged"] is False and info["epochs_run"] == 2


@pytest.mark.parametrize("name", ["raw_patchnorm", "pca", "pca_whiten", "ica"])
def test_learners_without_epochs_say_so_and_report_none(name, families):
    epochs_seen = []
    get_learner(name)(learner_params(name, TEST_PARAMS[name][0])).fit(
        families[0], progress=False, on_epoch=lambda epoch, metrics: epochs_seen.append(epoch)
    )
    assert epochs_seen == [] and not get_learner(name).trains_in_epochs


def test_cae_layers_match_table_5():
    from seasonloop.ablations.cae_widths import TABLE5_CHANNELS

    learner = get_learner("cae")(
        learner_params("cae", {"channels": list(TABLE5_CHANNELS), "kernels": [11, 5, 3]}), seed=0
    )
    learner.input_shape = (32, 64)
    model = learner._build_model(32, 64)
    convolutions = [module for module in model.modules() if isinstance(module, torch.nn.Conv2d)]
    assert [(conv.in_channels, conv.out_channels, conv.kernel_size) for conv in convolutions] == [
        (1, 96, (11, 11)),
        (96, 256, (5, 5)),
        (256, 384, (3, 3)),
        (384, 384, (3, 3)),
        (384, 256, (5, 5)),
        (256, 96, (11, 11)),
        (96, 1, (3, 3)),
    ]
    assert sum(isinstance(module, torch.nn.MaxPool2d) for module in model.encoder) == 2
    assert sum(isinstance(module, UpsampledConv2d) for module in model.decoder) == 2
    with torch.no_grad():
        code = model.encoder(torch.rand(2, 1, 32, 64))
        output = model.decoder(code)
    assert code.shape == (2, 384, 8, 16) and output.shape == (2, 1, 32, 64)
    assert output.min() >= 0 and output.max() <= 1


@pytest.mark.parametrize("kernel", [1, 2, 3, 4, 5, 6, 11])
@pytest.mark.parametrize("channels_last", [False, True])
def test_upsampled_conv_is_upsample_then_same_conv(kernel, channels_last):
    """The fused layer (a sub-pixel convolution from kernel 4 on) computes nn.Upsample + a "same"
    nn.Conv2d with its weights, forward and backward, to float32 rounding."""
    torch.manual_seed(kernel)
    fused = UpsampledConv2d(5, 3, kernel)
    reference = torch.nn.Conv2d(5, 3, kernel, padding="same")
    reference.load_state_dict(fused.state_dict())
    inputs = torch.randn(2, 5, 7, 9)
    if channels_last:
        inputs = inputs.to(memory_format=torch.channels_last)
    inputs.requires_grad_(True)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)  # torch's note on even kernels with padding="same"
        outputs = fused(inputs)
        expected = reference(torch.nn.functional.interpolate(inputs, scale_factor=2, mode="nearest"))
    assert fused.sub_pixel == (kernel >= 4)
    grad = torch.randn_like(expected)
    got = torch.autograd.grad(outputs, [inputs, fused.weight, fused.bias], grad)
    want = torch.autograd.grad(expected, [inputs, reference.weight, reference.bias], grad)
    for name, value, truth in zip(
        ["output", "input grad", "weight grad", "bias grad"], (outputs, *got), (expected, *want)
    ):
        assert value.shape == truth.shape, name
        assert (value - truth).abs().max() <= 1e-5 * truth.abs().max(), name


def test_cae_rejects_size_not_divisible_by_4():
    images = np.zeros((4, 18, 32), dtype=np.uint8)
    with pytest.raises(ValueError, match="divisible by 4"):
        get_learner("cae")(learner_params("cae", {"channels": [2, 2, 2], "patch_size": 2})).fit(images, progress=False)


@pytest.mark.skipif(torch.cuda.is_available(), reason="needs a machine without CUDA")
def test_cuda_requested_without_cuda_raises(families):
    with pytest.raises(ValueError, match=r"fae\.device"):
        get_learner("fae")(learner_params("fae", {"device": "cuda"})).fit(families[0], progress=False)


@pytest.mark.parametrize(
    "name, params, match",
    [
        ("pca", {"n_kept": 3}, r"^pca\.n_kept: unknown key"),
        ("fae", {"descriptor": "code_vector"}, r"fae\.descriptor"),
        ("cae", {"channels": [8, 16]}, r"cae\.channels"),
        ("ica", {"max_iter": 0}, r"ica\.max_iter"),
        ("raw_patchnorm", {"mode": "l2"}, r"raw_patchnorm\.mode"),
        ("fae", {"device": "tpu"}, r"fae\.device"),
        ("fae", {"precision": "float16"}, r"fae\.precision"),
        ("cae", {"patience": 0}, r"cae\.patience"),
        ("fae", {"validation_fraction": 1.0}, r"fae\.validation_fraction"),
        ("fae", {"lr_factor": 1.5}, r"fae\.lr_factor"),
        ("cae", {"budget_seconds": -1}, r"cae\.budget_seconds"),
        ("fae", {"epochs": 3}, r"^fae\.epochs: unknown key"),
    ],
)
def test_bad_params_raise_naming_the_key(name, params, match):
    with pytest.raises(ValueError, match=match):
        get_learner(name)(learner_params(name, params))


def test_unknown_learner_and_missing_directory(tmp_path):
    with pytest.raises(ValueError, match=r"unknown learner 'sift'.*pca"):
        get_learner("sift")
    with pytest.raises(FileNotFoundError, match="learner.json"):
        load_learner(tmp_path)
    # a saved learner of a kind this installation does not know: one line, no traceback
    (tmp_path / "learner.json").write_text(json.dumps({"name": "sift"}))
    with pytest.raises(ValueError, match=r"unknown learner 'sift'.*pca"):
        load_learner(tmp_path)


@pytest.mark.parametrize("name", list(LEARNERS))
def test_describe_and_save_before_fit_raise(name, tmp_path):
    learner = get_learner(name)(learner_params(name), seed=0)
    with pytest.raises(RuntimeError, match="fit"):
        learner.describe(np.zeros((2, 32, 64), dtype=np.uint8))
    with pytest.raises(RuntimeError, match="fit"):
        learner.save(tmp_path)


def test_describe_progress_bar_counts_batches_and_changes_nothing(fitted, families, capsys):
    learner = fitted("pca")
    images = families[0][:12]
    shown = learner.describe(images, batch_size=5, progress=True)
    bar = capsys.readouterr().err
    assert "pca describe" in bar and "0/3 " in bar  # 12 images in batches of 5
    np.testing.assert_array_equal(shown, learner.describe(images, batch_size=5))


def test_describe_rejects_other_image_size(fitted):
    with pytest.raises(ValueError, match="shape"):
        fitted("raw_patchnorm").describe(np.zeros((2, 32, 64), dtype=np.uint8))


def test_to_float():
    images = np.array([[[0, 255]]], dtype=np.uint8)
    converted = to_float(images)
    assert converted.dtype == np.float32 and converted.tolist() == [[[0.0, 1.0]]]
    assert to_float(np.full((1, 2, 2), 0.5)).dtype == np.float32
    with pytest.raises(ValueError, match="shape"):
        to_float(np.zeros((2, 2), dtype=np.uint8))
    with pytest.raises(ValueError, match="dtype"):
        to_float(np.zeros((1, 2, 2), dtype=np.int64))


def test_pca_seed_matters_only_to_the_randomized_solver(families):
    fitted = {}
    for solver in ("covariance_eigh", "randomized"):
        for seed in (3, 4):
            learner = get_learner("pca")(
                learner_params("pca", {"n_discard": 2, "n_keep": 16, "svd_solver": solver}), seed=seed
            )
            learner.fit(families[0], progress=False)
            fitted[solver, seed] = learner.describe(families[0])
    np.testing.assert_array_equal(fitted["covariance_eigh", 3], fitted["covariance_eigh", 4])
    assert not np.array_equal(fitted["randomized", 3], fitted["randomized", 4])
