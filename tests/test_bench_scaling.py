"""benchmarks/speed/bench_scaling.py's reading of runs at several sizes: growth exponents, shares of the
full run, and which stages grow faster than linearly."""

from __future__ import annotations

import pytest

from benchmarks.speed import bench_scaling


def record(stages: dict[str, tuple[float, float]]) -> dict:
    return {
        "stages": {name: {"seconds": s, "peak_rss_mb": m} for name, (s, m) in stages.items()},
        "total_seconds": sum(s for s, _ in stages.values()),
    }


def test_exponents_shares_and_the_superlinear_stages():
    sizes = [1000, 2000, 4000, 8000]
    runs = {
        n: record(
            {
                "extract": (0.01 * n, 100.0 + 0.1 * n),  # linear time
                "evaluate": (1e-6 * n**2, 50.0),  # quadratic time, constant memory
                "fit@cae": (300.0, 900.0),  # a fixed training set: constant
            }
        )
        for n in sizes
    }
    table, superlinear = bench_scaling.scaling_table(runs)
    assert table["extract"]["time_exponent"] == pytest.approx(1.0)
    assert table["evaluate"]["time_exponent"] == pytest.approx(2.0)
    assert table["fit@cae"]["time_exponent"] == pytest.approx(0.0, abs=1e-12)
    assert table["evaluate"]["memory_exponent"] == pytest.approx(0.0, abs=1e-12)
    assert set(superlinear) == {"evaluate"}
    total = 80.0 + 64.0 + 300.0
    assert table["evaluate"]["share_of_full_run"] == pytest.approx(64.0 / total)
    assert sum(row["share_of_full_run"] for row in table.values()) == pytest.approx(1.0)


def test_a_stage_missing_at_a_size_counts_zero_and_too_few_points_give_no_exponent():
    runs = {100: record({"a": (1.0, 1.0)}), 200: record({"a": (2.0, 1.0), "b": (5.0, 1.0)})}
    table, _ = bench_scaling.scaling_table(runs)
    assert table["b"]["seconds"] == [0.0, 5.0]
    assert table["b"]["time_exponent"] is None


def test_each_fraction_keeps_the_twelve_sections():
    for fraction in (0.125, 0.25, 0.5):
        sizes = bench_scaling.overrides(fraction)
        full = bench_scaling.overrides(1.0)
        assert sizes["synthetic.seconds"] / sizes["split.section_length"] == pytest.approx(
            full["synthetic.seconds"] / full["split.section_length"], rel=0.01
        )
