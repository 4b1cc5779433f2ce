"""Whether a difference is real: intervals on every fraction of queries and paired tests between
evaluations, pure functions of the evaluations' per-query outcomes (seasonloop.evaluation.outcomes)."""
