"""What the study reports, for side-by-side tables: fraction of correct matches in % (study.md).

These are the paper's published numbers, quoted for comparison only; nothing here is a result
of this project. Winter pairs: the study gives no numbers ("poor for all methods").
"""

from __future__ import annotations

STUDY_FRACTION_CORRECT: dict[str, dict[str, float]] = {
    "pca": {"summer-fall": 88, "spring-fall": 66, "summer-spring": 88},
    "ica": {"summer-fall": 91, "spring-fall": 68, "summer-spring": 83},
    "fae": {"summer-fall": 88, "spring-fall": 46, "summer-spring": 77},
    "cae": {"summer-fall": 83, "spring-fall": 43, "summer-spring": 59},
}
