"""Stage compare: is a difference real? Paired comparisons of the evaluations on the same queries.

For every season pair of evaluate.pairs in data.seasons: every two learners under each evaluation,
each learner's +seq against its single-image matching, each extra metric against evaluate.metric;
the difference in fraction correct with its interval, its p-value along the route and Holm's
correction per table (seasonloop.significance.tables), from the evaluate stages' per-query
outcomes (data/outcomes/<learner>/). Writes metrics/comparisons.json (not a declared DVC metric:
thousands of numbers; `dvc exp show` keeps to metrics/mean_fraction_correct.json) and
plots/comparisons.md, its tables (seasonloop.reporting.comparisons) for docs/results.md.
"""

from __future__ import annotations

from pathlib import Path

from _common import data_seasons, load_params, param, stage_main
from seasonloop.evaluation.matchers import evaluations
from seasonloop.io import staged_file, write_json
from seasonloop.params.seasons import available_pairs, pair_name
from seasonloop.params.settings import EvaluateConfig, StatisticsConfig
from seasonloop.reporting.comparisons import comparisons_markdown, run_comparisons


@stage_main
def main() -> None:
    params = load_params("learners", "data.seasons", "evaluate", "statistics")
    evaluate = EvaluateConfig.from_params(params)
    pairs = [pair_name(a, b) for a, b in available_pairs(data_seasons(params), evaluate.pairs)]
    learners = list(param(params, "learners"))
    comparisons = run_comparisons(
        Path("data/outcomes"), learners, evaluations(evaluate), pairs, StatisticsConfig.from_params(params)
    )
    write_json(Path("metrics/comparisons.json"), comparisons)
    with staged_file(Path("plots/comparisons.md")) as markdown:
        markdown.write_text(comparisons_markdown(comparisons, learners))


if __name__ == "__main__":
    main()
