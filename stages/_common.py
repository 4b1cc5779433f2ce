"""What every stage script shares: reading (and checking) params.yaml, and turning bad input into
one clear line. The pipeline's data sets are in _datasets.py.

Stage scripts are thin: they read params, call the seasonloop library and write their outputs.
"""

from __future__ import annotations

import functools
import sys
from collections.abc import Callable
from pathlib import Path
from typing import Any

import yaml

# A stage runs the library of its own checkout, the code dvc.yaml declares and DVC hashes: not
# whichever checkout pip installed in editable mode (another clone, or the repository that DVC's
# experiment queue copied this tree from, whose src/ may have changed since). Every stage imports
# this module before the library (_ground_truth.py imports it first too).
sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "src"))

from seasonloop.params.seasons import check_seasons  # noqa: E402
from seasonloop.registries.choices import check_params, check_whole  # noqa: E402

PARAMS_FILE = Path("params.yaml")


def load_params(*keys: str, path: Path = PARAMS_FILE) -> dict[str, Any]:
    """params.yaml, checked whole before any work (a typo anywhere stops the first stage that runs);
    `keys` are the sections or dotted keys the stage reads (tests/test_stage_deps.py holds them to it)."""
    if not path.is_file():
        raise FileNotFoundError(f"{path}: parameter file not found (run from the repository root)")
    params = yaml.safe_load(path.read_text()) or {}
    if not isinstance(params, dict):
        raise ValueError(f"{path}: expected a mapping of sections")
    check_whole(params)
    check_params(params, keys)
    return params


def param(params: dict[str, Any], dotted_key: str) -> Any:
    """params["a"]["b"] for "a.b", or a ValueError that names the missing key."""
    value: Any = params
    for part in dotted_key.split("."):
        if not isinstance(value, dict) or part not in value:
            raise ValueError(f"params.yaml: missing key '{dotted_key}'")
        value = value[part]
    return value


def data_seasons(params: dict[str, Any]) -> list[str]:
    return check_seasons(param(params, "data.seasons"), "data.seasons")


def train_seasons(params: dict[str, Any]) -> list[str]:
    """train.seasons, each of which must be among the data's seasons."""
    return check_seasons(param(params, "train.seasons"), "train.seasons", allowed=data_seasons(params))


def stage_main(run: Callable[[], None]) -> Callable[[], None]:
    """Run a stage; expected failures (bad params, missing or corrupt input, a full disk or other
    OS error while writing) print one line, exit 1."""

    @functools.wraps(run)
    def wrapper() -> None:
        try:
            run()
        except (ValueError, OSError, RuntimeError) as error:
            print(f"error: {error}", file=sys.stderr)
            sys.exit(1)

    return wrapper
