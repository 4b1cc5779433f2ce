"""Test order for the two workers: the end-to-end files (minutes each) start first, one per worker,
and the unit tests fill in around them, so the suite takes about as long as its longest file."""

from __future__ import annotations

import pytest


def pytest_collection_modifyitems(items: list[pytest.Item]) -> None:
    # stable sort: e2e tests first (xdist hands out files in collection order), the rest as collected
    items.sort(key=lambda item: item.get_closest_marker("e2e") is None)
