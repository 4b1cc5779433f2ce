"""How an iterative fit ended, read from its fit info: the record that says whether a learner
reached its definition of done (ICA's tolerance, the auto-encoders' validation plateau)."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

# Fit-info keys that say how an iterative fit ended
ENDING_KEYS = ("converged", "gradient", "tol", "n_iter", "stop_reason", "epochs_run", "best_validation_loss")


def how_fit_ended(info: Mapping[str, Any]) -> dict[str, Any]:
    """The ENDING_KEYS of a fit's info, the bag of words' patch ICA (nested under "ica") and
    k-means iterations included; empty for a closed-form fit."""
    ended = {key: info[key] for key in ENDING_KEYS if key in info}
    nested = info.get("ica")
    if isinstance(nested, Mapping):
        ended.update({f"ica {key}": nested[key] for key in ENDING_KEYS if key in nested})
    if "kmeans_n_iter" in info:
        ended["kmeans n_iter"] = info["kmeans_n_iter"]
    return ended
