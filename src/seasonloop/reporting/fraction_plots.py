"""The fraction-correct figure of the summary (the study's Figures 10, 11, 16, 17): a panel per
pair, a bar per learner and matcher, each bar's 95% interval along the route as an error bar and the
study's numbers as diamonds."""

from __future__ import annotations

import numpy as np
import pandas as pd
from matplotlib.artist import Artist
from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from matplotlib.patches import Patch

from seasonloop.evaluation.matchers import MATCHER_TITLES
from seasonloop.plots import save_figure, series_styles


def _check_fractions(table: pd.DataFrame, name: str) -> None:
    values = table.to_numpy(dtype=np.float64)
    finite = values[~np.isnan(values)]
    if ((finite < 0) | (finite > 1)).any():
        raise ValueError(f"{name} must hold fractions in [0, 1] (NaN where absent), not percentages")


def plot_fraction_correct(
    table: pd.DataFrame,
    path,
    title: str = "Fraction of correct matches",
    reference: pd.DataFrame | None = None,
    intervals: tuple[pd.DataFrame, pd.DataFrame] | None = None,
) -> None:
    """Bars of the fraction of correct matches, in %: a panel per pair, a row per learner, a bar per
    variant ("+seq" hatched). table: rows = learners, columns = pairs, fractions in [0, 1];
    reference: the study's, same labels (NaN where it gives none), drawn as hollow diamonds;
    intervals: (low, high) tables like `table`, drawn as error bars."""
    if table.empty:
        raise ValueError("table is empty: nothing to plot")
    _check_fractions(table, "table")
    if reference is not None:
        if set(reference.index) != set(table.index) or set(reference.columns) != set(table.columns):
            raise ValueError("reference must have the same learners (rows) and pairs (columns) as table")
        _check_fractions(reference, "reference")
        reference = reference.loc[table.index, table.columns]
    if intervals is not None:
        for bound in intervals:
            _check_fractions(bound, "intervals")
        intervals = (intervals[0].loc[table.index, table.columns], intervals[1].loc[table.index, table.columns])

    learners, pairs = list(table.index), list(table.columns)
    bases = list(dict.fromkeys(str(learner).split("+")[0] for learner in learners))
    variants = list(dict.fromkeys(str(learner)[len(str(learner).split("+")[0]) :] for learner in learners))
    # one panel per pair, three to a row, learners down the side: ~1,500 px wide at 120 dpi
    n_columns = min(3, len(pairs))
    n_rows = int(np.ceil(len(pairs) / n_columns))
    height = (0.5 + 0.22 * len(bases) * len(variants)) * n_rows + 1.0
    figure = Figure(figsize=(4.2 * n_columns, height))
    grid = figure.subplots(n_rows, n_columns, squeeze=False, sharex=True, sharey=True)
    for axes, pair in zip(grid.flat, pairs):
        study = None if reference is None else 100.0 * reference[pair]
        bounds = None if intervals is None else (100.0 * intervals[0][pair], 100.0 * intervals[1][pair])
        _fraction_panel(axes, 100.0 * table[pair], study, bounds, (bases, variants))
        axes.set_title(str(pair), fontsize="medium")
    for axes in grid.flat[len(pairs) :]:
        axes.set_visible(False)
    grid[0, 0].set_yticks(np.arange(len(bases)), bases)
    grid[0, 0].invert_yaxis()
    for axes in grid[-1]:
        axes.set_xlabel("Correct matches (%)")
    handles = _legend_handles(bases, variants, intervals is not None, reference is not None)
    figure.suptitle(title)
    # below the panels, so it covers no bar
    figure.legend(handles=handles, loc="lower center", ncol=len(handles), frameon=False, bbox_to_anchor=(0.5, 0.0))
    figure.tight_layout(rect=(0.0, 0.4 / height, 1.0, 1.0))
    save_figure(figure, path)


def _legend_handles(bases: list[str], variants: list[str], intervals: bool, reference: bool) -> list[Artist]:
    """A patch per variant (its matcher's title and hatch), then the interval and study markers drawn."""
    names = {
        "": "single image",
        **{suffix: f"{suffix} ({title})" for suffix, title in MATCHER_TITLES.items() if suffix},
    }
    hatches = series_styles([bases[0] + variant for variant in variants])
    handles: list[Artist] = [
        Patch(
            facecolor="grey",
            hatch=hatches[bases[0] + v]["hatch"],
            edgecolor="white" if v else None,
            label=names.get(v, v),
        )
        for v in variants
    ]
    if intervals:
        handles.append(Line2D([], [], marker="|", color="black", label="95% interval (along the route)"))
    if reference:
        handles.append(Line2D([], [], marker="D", linestyle="", markerfacecolor="none", color="black", label="study"))
    return handles


def _fraction_panel(
    axes,
    percent: pd.Series,
    study: pd.Series | None,
    bounds: tuple[pd.Series, pd.Series] | None,
    rows: tuple[list[str], list[str]],
) -> None:
    """One pair's panel: a row per learner (base), a bar per variant (rows: bases, variants), its
    interval (bounds: low, high) as an error bar, the study's numbers as diamonds."""
    bases, variants = rows
    styles = series_styles(list(percent.index))
    bar_height = 0.8 / len(variants)
    for index, variant in enumerate(variants):
        offset = (index - (len(variants) - 1) / 2) * bar_height
        for row, base in enumerate(bases):
            learner = base + variant
            if learner not in percent.index:
                continue
            color, hatch = styles[learner]["color"], styles[learner]["hatch"]
            kind = {"hatch": hatch, "edgecolor": "white"} if hatch else {}
            axes.barh(row + offset, float(percent[learner]), bar_height, color=color, **kind)
            if bounds is not None and np.isfinite(bounds[0][learner]):
                value = float(percent[learner])
                spread = [[value - float(bounds[0][learner])], [float(bounds[1][learner]) - value]]
                axes.errorbar(value, row + offset, xerr=spread, color="black", linewidth=0.8, capsize=1.5)
            if study is not None and np.isfinite(study[learner]):
                axes.scatter(
                    float(study[learner]), row + offset, marker="D", facecolors="none", edgecolors="black", zorder=3
                )
    axes.set_xlim(0.0, 100.0)
    axes.grid(True, axis="x", alpha=0.3)
