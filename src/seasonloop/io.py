"""Output helpers that never leave a half-written result behind.

A stage that fails part-way must not leave files that look like valid results (DVC would not
cache them, but a person or a later stage could read them), so every output is first written
under a temporary name and moved into place only once complete.
"""

from __future__ import annotations

import contextlib
import json
import os
import shutil
import tempfile
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import numpy as np


def _default_mode(directory: bool) -> int:
    """The permissions a plain mkdir/open would give: tempfile's private 0o700/0o600 would
    otherwise stick to the renamed result."""
    umask = os.umask(0)
    os.umask(umask)
    return (0o777 if directory else 0o666) & ~umask


def _staging_prefix(final: Path) -> str:
    # distinct per final name: ".pca.staging-" never matches the staging of "pca.json"
    return f".{final.name}.staging-"


def remove_stale_staging(final: Path) -> list[Path]:
    """Remove what a killed run left while staging `final` (a SIGKILL skips the cleanup below);
    one writer per final path, so anything found is stale. Returns what was removed."""
    stale = sorted(Path(final).parent.glob(_staging_prefix(Path(final)) + "*"))
    for path in stale:
        shutil.rmtree(path, ignore_errors=True) if path.is_dir() and not path.is_symlink() else path.unlink(
            missing_ok=True
        )
    return stale


@contextlib.contextmanager
def staged_dir(final: Path) -> Iterator[Path]:
    """Yield an empty temporary directory beside `final`; it replaces `final` only on success."""
    final = Path(final)
    final.parent.mkdir(parents=True, exist_ok=True)
    remove_stale_staging(final)
    tmp = Path(tempfile.mkdtemp(prefix=_staging_prefix(final), dir=final.parent))
    os.chmod(tmp, _default_mode(directory=True))
    try:
        yield tmp
    except BaseException:
        shutil.rmtree(tmp, ignore_errors=True)
        raise
    if final.exists():
        shutil.rmtree(final) if final.is_dir() else final.unlink()
    os.replace(tmp, final)


@contextlib.contextmanager
def staged_file(final: Path) -> Iterator[Path]:
    """Yield a temporary path beside `final`; it is renamed to `final` only on success."""
    final = Path(final)
    final.parent.mkdir(parents=True, exist_ok=True)
    remove_stale_staging(final)
    fd, name = tempfile.mkstemp(prefix=_staging_prefix(final), suffix=final.suffix, dir=final.parent)
    os.close(fd)
    tmp = Path(name)
    os.chmod(tmp, _default_mode(directory=False))
    try:
        yield tmp
    except BaseException:
        tmp.unlink(missing_ok=True)
        raise
    os.replace(tmp, final)


def write_json(path: Path, data: Any) -> None:
    """Write JSON atomically, keys in a stable order so identical results give identical bytes."""
    with staged_file(Path(path)) as tmp:
        tmp.write_text(json.dumps(data, indent=2, sort_keys=True) + "\n")


def save_array(path: Path, array: np.ndarray) -> None:
    """np.save, atomically."""
    with staged_file(Path(path)) as tmp, open(tmp, "wb") as handle:
        np.save(handle, array)


def read_json(path: Path) -> Any:
    path = Path(path)
    if not path.is_file():
        raise FileNotFoundError(f"{path}: file not found")
    return json.loads(path.read_text())


def load_array(path: Path, mmap: bool = False) -> np.ndarray:
    path = Path(path)
    if not path.is_file():
        raise FileNotFoundError(f"{path}: file not found (run the stage that writes it first)")
    return np.load(path, mmap_mode="r" if mmap else None)
