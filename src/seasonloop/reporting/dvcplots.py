"""Tables for `dvc plots show` that hold every learner of a run in one file per figure.

dvc.yaml's top-level plots then name files that exist whatever the learners and seasons: a plot
that listed one file per learner and pair would miss files on any subset.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path

import numpy as np
import pandas as pd

CURVE_COLUMNS = ["learner", "recall", "precision"]
LOSS_COLUMNS = ["learner", "metric", "step", "value"]


def pr_long(curves: Mapping[str, tuple[np.ndarray, np.ndarray]]) -> pd.DataFrame:
    """label -> (recall, precision) as one long table, a `learner` column naming the curve."""
    frames = [
        pd.DataFrame({"learner": label, "recall": np.asarray(recall), "precision": np.asarray(precision)})
        for label, (recall, precision) in curves.items()
    ]
    return pd.concat(frames, ignore_index=True) if frames else pd.DataFrame(columns=CURVE_COLUMNS)


def training_curves(logs: Path, learners: Sequence[str]) -> pd.DataFrame:
    """Every dvclive step metric (logs/<learner>/plots/metrics/**/*.tsv) of `learners`, long.

    Learners that do not train in epochs have none; the table is then empty but has its columns.
    """
    frames = []
    for learner in learners:
        root = Path(logs) / learner / "plots" / "metrics"
        for tsv in sorted(root.rglob("*.tsv")):
            table = pd.read_csv(tsv, sep="\t")
            name = tsv.relative_to(root).with_suffix("").as_posix()
            value = [column for column in table.columns if column not in ("step", "timestamp")]
            if "step" not in table.columns or len(value) != 1:
                raise ValueError(f"{tsv}: expected a dvclive step log (step and one value column)")
            frames.append(
                pd.DataFrame({"learner": learner, "metric": name, "step": table["step"], "value": table[value[0]]})
            )
    return pd.concat(frames, ignore_index=True) if frames else pd.DataFrame(columns=LOSS_COLUMNS)
