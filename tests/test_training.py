"""The auto-encoders' training loop: held-out validation places, early stopping, best weights,
learning-rate schedule, budget, and precision choice."""

import subprocess
import sys

import numpy as np
import pytest
import torch
from torch import nn

from seasonloop.models.core import arithmetic
from seasonloop.models.core import training as _training
from seasonloop.models.core.arithmetic import resolve_precision
from seasonloop.models.core.autoencoder_training import mean_loss, train_until_plateau
from seasonloop.models.core.lookup import get_learner
from seasonloop.models.core.training import TrainingConfig, validation_places
from tools.repository import learner_params

CPU = torch.device("cpu")


def config(**overrides) -> TrainingConfig:
    values = dict(
        max_epochs=50,
        batch_size=16,
        learning_rate=1e-2,
        patience=3,
        min_delta=0.01,
        lr_patience=1,
        lr_factor=0.5,
        budget_seconds=0,
        seed=0,
    )
    return TrainingConfig(**{**values, **overrides})


def images(n: int, seed: int) -> torch.Tensor:
    """Smooth random images (N, 1, 8, 8) in [0, 1]: learnable by a small auto-encoder."""
    generator = torch.Generator().manual_seed(seed)
    low = torch.rand(n, 1, 2, 2, generator=generator)
    return nn.functional.interpolate(low, size=(8, 8), mode="bilinear", align_corners=False)


def small_autoencoder() -> nn.Module:
    torch.manual_seed(0)
    return nn.Sequential(
        nn.Flatten(), nn.Linear(64, 8), nn.ReLU(), nn.Linear(8, 64), nn.Sigmoid(), nn.Unflatten(1, (1, 8, 8))
    )


def test_validation_places_are_whole_blocks_seeded_and_never_all():
    places = np.repeat(np.arange(100, 200), 2)  # two images (original + copy) per place
    held_out = validation_places(places, fraction=0.2, block=10, seed=1)
    assert len(held_out) == 20 and set(held_out) <= set(places)
    # whole blocks of 10 consecutive places
    blocks = {(place - 100) // 10 for place in held_out}
    assert len(blocks) == 2 and set(held_out) == {100 + 10 * block + i for block in blocks for i in range(10)}
    np.testing.assert_array_equal(held_out, validation_places(places, 0.2, 10, seed=1))
    assert not np.array_equal(held_out, validation_places(places, 0.2, 10, seed=2))
    assert len(validation_places(places, 0.0, 10, 0)) == 10  # never empty
    assert len(validation_places(places, 0.99, 10, 0)) == 90  # never every place
    with pytest.raises(ValueError, match="at least 2 blocks"):
        validation_places(np.arange(5), 0.1, 10, 0)


def test_stops_on_plateau_and_keeps_the_best_weights():
    model = small_autoencoder()
    train, validation = images(256, 0), images(64, 1)
    result = train_until_plateau(model, train, validation, config(), CPU, progress=False)
    info = result.info()
    assert info["stop_reason"] == "plateau" and info["converged"] is True
    assert info["epochs_run"] < 50
    losses = info["validation_loss_per_epoch"]
    assert info["best_validation_loss"] == min(losses) == losses[info["best_epoch"] - 1]
    # stopped 3 epochs after the last improvement of 1% over the loss of the previous such improvement
    reference, last_improvement = np.inf, 0
    for epoch, loss in enumerate(losses, start=1):
        if loss < 0.99 * reference:
            reference, last_improvement = loss, epoch
    assert info["epochs_run"] == last_improvement + 3
    # it learned: the best validation loss is well below the first epoch's
    assert info["best_validation_loss"] < 0.8 * losses[0]
    # the model holds the best epoch's weights, not the last epoch's
    assert mean_loss(model, validation, 16, CPU, torch.float32, torch.contiguous_format) == pytest.approx(
        info["best_validation_loss"], rel=1e-6
    )
    # the schedule cut the learning rate on the way to the plateau
    assert info["learning_rate_per_epoch"][-1] < info["learning_rate_per_epoch"][0]
    assert info["images_seen"] == 256 * info["epochs_run"]


def test_max_epochs_and_budget_stop_without_converging():
    train, validation = images(64, 0), images(16, 1)
    by_epochs = train_until_plateau(
        small_autoencoder(), train, validation, config(max_epochs=2), CPU, progress=False
    ).info()
    assert (by_epochs["stop_reason"], by_epochs["converged"], by_epochs["epochs_run"]) == ("max_epochs", False, 2)
    by_budget = train_until_plateau(
        small_autoencoder(), train, validation, config(budget_seconds=1e-9), CPU, progress=False
    ).info()
    assert (by_budget["stop_reason"], by_budget["converged"], by_budget["epochs_run"]) == ("budget", False, 1)


def test_training_is_reproducible_and_leaves_the_global_rng_alone():
    train, validation = images(64, 0), images(16, 1)
    # built first: small_autoencoder seeds the global generator itself
    models = small_autoencoder(), small_autoencoder()
    state = torch.random.get_rng_state()
    first = train_until_plateau(models[0], train, validation, config(max_epochs=3), CPU, progress=False)
    assert torch.equal(state, torch.random.get_rng_state())
    second = train_until_plateau(models[1], train, validation, config(max_epochs=3), CPU, progress=False)
    assert first.validation_loss == second.validation_loss


def test_training_asks_for_deterministic_kernels_and_restores_the_callers_choice():
    assert not torch.are_deterministic_algorithms_enabled()
    with _training.deterministic_algorithms(CPU):
        assert torch.are_deterministic_algorithms_enabled()
        assert not torch.is_deterministic_algorithms_warn_only_enabled()  # on the CPU a kernel without one raises
        assert torch.backends.cudnn.deterministic and not torch.backends.cudnn.benchmark
    assert not torch.are_deterministic_algorithms_enabled() and not torch.backends.cudnn.deterministic
    torch.use_deterministic_algorithms(True, warn_only=True)
    try:
        with _training.deterministic_algorithms(torch.device("cuda")):
            assert torch.is_deterministic_algorithms_warn_only_enabled()  # CUDA: some kernels only warn
        assert torch.are_deterministic_algorithms_enabled() and torch.is_deterministic_algorithms_warn_only_enabled()
    finally:
        torch.use_deterministic_algorithms(False)


def test_precision_choice(monkeypatch):
    assert resolve_precision("float32", CPU, "fae.precision") == torch.float32
    assert resolve_precision("bfloat16", CPU, "fae.precision") == torch.bfloat16
    monkeypatch.setattr(arithmetic, "cpu_has_native_bfloat16", lambda: True)
    assert resolve_precision("auto", CPU, "fae.precision") == torch.bfloat16
    monkeypatch.setattr(arithmetic, "cpu_has_native_bfloat16", lambda: False)
    assert resolve_precision("auto", CPU, "fae.precision") == torch.float32
    with pytest.raises(ValueError, match=r"cae\.precision"):
        resolve_precision("half", CPU, "cae.precision")


@pytest.mark.parametrize("name", ["fae", "cae"])
def test_bfloat16_training_keeps_float32_weights_loss_and_descriptors(name):
    rng = np.random.default_rng(0)
    frames = (rng.random((60, 8, 16)) * 255).astype(np.uint8)
    params = {"max_epochs": 2, "batch_size": 16, "precision": "bfloat16", "patch_size": 4, "validation_block": 3}
    if name == "cae":
        params |= {"channels": [2, 4, 4], "kernels": [3, 3, 3], "max_validation_images": 0}
    learner = get_learner(name)(learner_params(name, params), seed=0)
    info = learner.fit(frames, progress=False, places=np.tile(np.arange(30), 2))
    assert info["precision"] == "bfloat16" and np.isfinite(info["best_validation_loss"])
    assert all(parameter.dtype == torch.float32 for parameter in learner.model.parameters())
    assert learner.describe(frames[:4]).dtype == np.float32


def test_validation_holds_out_every_image_of_its_places():
    rng = np.random.default_rng(0)
    frames = (rng.random((120, 8, 16)) * 255).astype(np.uint8)
    places = np.tile(np.arange(60), 2)  # originals then one augmented copy each
    learner = get_learner("fae")(
        learner_params(
            "fae", {"max_epochs": 1, "hidden": 4, "patch_size": 4, "validation_fraction": 0.2, "validation_block": 10}
        ),
        seed=0,
    )
    info = learner.fit(frames, progress=False, places=places)
    assert info["n_validation_places"] == 10 and info["n_validation_images"] == 20
    assert info["n_train_images"] == 100 and info["torch_threads"] == torch.get_num_threads()
    with pytest.raises(ValueError, match="places of shape"):
        learner.fit(frames, progress=False, places=places[:10])


def test_learning_rate_is_cut_at_the_lr_patience_th_epoch_without_improvement():
    # params.yaml: "the learning rate is halved after lr_patience such epochs"; torch's own
    # patience cuts one epoch later, so the schedule must translate
    for lr_patience in (1, 2, 3):
        optimiser = torch.optim.SGD([nn.Parameter(torch.zeros(1))], lr=1.0)
        schedule = _training.learning_rate_schedule(optimiser, config(lr_patience=lr_patience))
        schedule.step(1.0)  # the first epoch sets the reference
        rates = []
        for _ in range(lr_patience):
            schedule.step(1.0)  # no improvement
            rates.append(optimiser.param_groups[0]["lr"])
        assert rates == [1.0] * (lr_patience - 1) + [0.5], lr_patience
    with pytest.raises(ValueError, match="lr_patience"):
        _training.learning_rate_schedule(optimiser, config(lr_patience=0))
    with pytest.raises(ValueError, match=r"fae\.lr_patience"):
        get_learner("fae")(learner_params("fae", {"lr_patience": 0}))


class BlowsUpAfter(nn.Module):
    """small_autoencoder() whose weights turn NaN after `steps` training batches, as an exploding
    gradient would leave them."""

    def __init__(self, steps: int):
        super().__init__()
        self.inner, self.steps = small_autoencoder(), steps

    def forward(self, batch: torch.Tensor) -> torch.Tensor:
        if self.training:
            self.steps -= 1
            if self.steps < 0:
                with torch.no_grad():
                    for parameter in self.inner.parameters():
                        parameter.fill_(float("nan"))
        return self.inner(batch)


def test_a_run_that_diverges_says_so_and_keeps_its_last_finite_weights():
    train, validation = images(64, 0), images(16, 1)
    model = BlowsUpAfter(steps=2 * 4)  # 4 batches an epoch: epochs 1-2 train, epoch 3 diverges
    info = train_until_plateau(model, train, validation, config(patience=50), CPU, progress=False).info()
    # NaN fails both comparisons of the plateau test: before the fix this read "plateau", converged
    assert (info["stop_reason"], info["converged"], info["epochs_run"]) == ("diverged", False, 3)
    assert np.isnan(info["validation_loss_per_epoch"][-1])
    assert info["best_epoch"] in (1, 2) and np.isfinite(info["best_validation_loss"])
    assert all(torch.isfinite(parameter).all() for parameter in model.parameters())


def test_denormals_are_flushed_on_the_cpu_from_the_fit_on():
    """A subprocess (the floating-point mode is the process's): before flush_denormals a float32
    below ~1.2e-38 survives a product, after it the product is zero; a CUDA device leaves the CPU
    mode alone."""
    script = (
        "import torch\n"
        "from seasonloop.models.core.arithmetic import flush_denormals\n"
        "tiny = torch.tensor([1e-30], dtype=torch.float32)\n"
        "before = (tiny * 1e-10).item()\n"
        "flush_denormals(torch.device('cuda'))\n"
        "untouched = (tiny * 1e-10).item()\n"
        "flush_denormals(torch.device('cpu'))\n"
        "print(before > 0, untouched > 0, (tiny * 1e-10).item() == 0)\n"
    )
    result = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, check=True)
    assert result.stdout.split() == ["True", "True", "True"]
