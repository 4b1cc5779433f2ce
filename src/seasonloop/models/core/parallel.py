"""A learner's fits at once: the K folds' fits are independent, so they run through joblib (its
loky processes here; its Dask and Ray backends reach a cluster: docs/sharing.md), never a
scheduler written here. A fit's bytes depend on the threads its arithmetic uses (BLAS and torch
sum in another order), so each fit runs at a declared thread count, and the fits' bytes are the
same run one after another or at once (tests/test_parallel_fits.py)."""

from __future__ import annotations

import sys
from collections.abc import Callable, Iterator, Sequence
from contextlib import contextmanager
from typing import Any, TypeVar

T = TypeVar("T")


@contextmanager
def fit_threads(threads: int) -> Iterator[None]:
    """BLAS, OpenMP and (when imported) torch at `threads` threads inside; 0: as they are."""
    if not threads:
        yield
        return
    from threadpoolctl import threadpool_limits

    torch = sys.modules.get("torch")
    before = torch.get_num_threads() if torch is not None else None
    if torch is not None:
        torch.set_num_threads(threads)
    try:
        with threadpool_limits(limits=threads):
            yield
    finally:
        if torch is not None:
            torch.set_num_threads(before)


def run_each(function: Callable[[Any], T], items: Sequence[Any], jobs: int) -> list[T]:
    """[function(item) for item in items], `jobs` at a time (joblib: the active backend, loky by
    default, in processes), in the items' order."""
    if jobs <= 1 or len(items) <= 1:
        return [function(item) for item in items]
    from joblib import Parallel, delayed

    return Parallel(n_jobs=min(jobs, len(items)))(delayed(function)(item) for item in items)
