"""The paired comparisons as tables (seasonloop.reporting.comparisons): matrices read row against
column, claims found in either order, whole tables counted."""

from __future__ import annotations

import pytest

from seasonloop.reporting.comparisons import claim_cells, comparisons_markdown, find_comparison, learner_matrix


def row(first, second, difference, verdict):
    return {"first": first, "second": second, "difference": difference, "verdict": verdict}


RECORD = {
    "statistics": {"level": 0.95, "degrees_scale": 0.15, "persistence_scale": 0.38, "alpha": 0.05},
    "order": {"pairs": ["summer-fall"], "tables": ["learners", "matchers+seq"]},
    "pairs": {
        "summer-fall": {
            "learners": [row("pca", "ica", -0.05, "worse"), row("pca", "cae", 0.01, "no difference"),
                         row("ica", "cae", 0.06, "better")],
            "matchers+seq": [row("pca+seq", "pca", 0.1, "better"), row("ica+seq", "ica", 0.0, "no difference"),
                             row("cae+seq", "cae", 0.2, "better")],
        },
    },
}  # fmt: skip


def test_the_matrix_reads_row_against_column():
    matrix = learner_matrix(RECORD["pairs"]["summer-fall"]["learners"], ["pca", "ica", "cae"])
    assert matrix.loc["pca", "ica"] == "-5.0 ▼" and matrix.loc["ica", "pca"] == "+5.0 ▲"
    assert matrix.loc["cae", "pca"] == "-1.0 ·" and matrix.loc["pca", "pca"] == ""


def test_a_claim_is_found_in_either_order_or_refused():
    rows = RECORD["pairs"]["summer-fall"]["learners"]
    assert find_comparison(rows, "ica", "pca") == (0.05, "better")
    with pytest.raises(ValueError, match="no comparison of pca with fae"):
        find_comparison(rows, "pca", "fae")
    assert claim_cells(RECORD, {"table": "learners", "first": "ica", "second": "pca"}) == {"summer-fall": "+5.0 ▲"}
    assert claim_cells(RECORD, {"table": "matchers+seq"}) == {"summer-fall": "2 ▲ 0 ▼ of 3"}
    with pytest.raises(ValueError, match="no such table"):
        claim_cells(RECORD, {"table": "learners@cityblock"})


def test_the_markdown_names_its_settings_and_every_table():
    markdown = comparisons_markdown(RECORD, ["pca", "ica", "cae"])
    assert (
        "95% intervals along the route (degrees of freedom min(0.15 n^(2/3), 0.38 (n^2 / omega)^(1/3)), "
        "omega the runs' persistence), alpha 0.05" in markdown
    )
    assert "no difference shown at 5% (a t test" in markdown
    assert "**summer-fall: learner against learner, evaluate.metric, single images**" in markdown
    assert "| pca+seq vs pca | +10.0 ▲ |" in markdown
    assert "| matchers+seq | 2 / 3 |" in markdown
