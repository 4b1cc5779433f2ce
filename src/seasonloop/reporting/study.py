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

# The study's precision-recall landmarks (study.md), as fractions: pair -> learner -> metric key of
# seasonloop.evaluation.metrics.evaluate_pair -> value. Summer-fall, single-image matching: "precision 100%
# up to 67% recall for PCA and ICA; at 100% recall ICA 91.05%, PCA 84%". It states none for the
# auto-encoders. In the study's convention precision at 100% recall equals the fraction correct,
# yet its PCA numbers differ (84% here, 88% in its fraction-correct table); both are quoted as given.
STUDY_PR_LANDMARKS: dict[str, dict[str, dict[str, float]]] = {
    "summer-fall": {
        "pca": {"recall_at_100_precision": 0.67, "precision_at_full_recall": 0.84},
        "ica": {"recall_at_100_precision": 0.67, "precision_at_full_recall": 0.9105},
    }
}
