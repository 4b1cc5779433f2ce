"""Figures of the study, written as PNG files.

Figures are built with matplotlib's object API (matplotlib.figure.Figure, rendered by the Agg
canvas): no pyplot, so no global figure registry to leak into and nothing to close; each figure is
released when the function returns.
"""

from __future__ import annotations

import textwrap
from collections.abc import Mapping, Sequence
from pathlib import Path

import matplotlib
import numpy as np
from matplotlib.cm import ScalarMappable
from matplotlib.colors import Normalize
from matplotlib.figure import Figure


def save_figure(figure: Figure, path) -> None:
    """Write the figure as a PNG at path, creating parent directories."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    figure.savefig(path, format="png", dpi=120, bbox_inches="tight")


# how the variants of a learner ("pca+seq", "pca+delta", ...) are told apart, in the order they first
# appear among the labels (single images: solid lines, plain bars)
VARIANT_LINESTYLES = ("--", ":", "-.")
VARIANT_HATCHES = ("//", "..", "xx")


def series_styles(labels: Sequence[str]) -> dict[str, dict]:
    """One colour per learner, shared by its variants ("pca" and "pca+seq"); each variant its own
    line style and bar hatch (VARIANT_LINESTYLES, VARIANT_HATCHES), so a dozen series stay tellable
    apart."""
    bases = list(dict.fromkeys(str(label).split("+")[0] for label in labels))
    variants = [
        suffix for suffix in dict.fromkeys(str(label)[len(str(label).split("+")[0]) :] for label in labels) if suffix
    ]
    palette = matplotlib.colormaps["tab10" if len(bases) <= 10 else "tab20"]
    styles = {}
    for label in labels:
        base = str(label).split("+")[0]
        suffix = str(label)[len(base) :]
        index = variants.index(suffix) if suffix else None
        styles[label] = {
            "color": palette(bases.index(base)),
            "linestyle": "-" if index is None else VARIANT_LINESTYLES[index % len(VARIANT_LINESTYLES)],
            "hatch": None if index is None else VARIANT_HATCHES[index % len(VARIANT_HATCHES)],
        }
    return styles


def plot_pr_curves(curves: Mapping[str, tuple[np.ndarray, np.ndarray]], title: str, path) -> None:
    """Overlay precision-recall curves, label -> (recall, precision), on 0..1 axes."""
    if not curves:
        raise ValueError("curves is empty: nothing to plot")
    figure = Figure(figsize=(7.5, 4.5))
    axes = figure.add_subplot()
    styles = series_styles(list(curves))
    for label, (recall, precision) in curves.items():
        recall, precision = np.asarray(recall), np.asarray(precision)
        if recall.ndim != 1 or recall.shape != precision.shape:
            raise ValueError(
                f"curve {label!r}: recall and precision must be 1-D of equal length, "
                f"got shapes {recall.shape} and {precision.shape}"
            )
        axes.plot(
            recall,
            precision,
            label=label,
            linewidth=1.5,
            color=styles[label]["color"],
            linestyle=styles[label]["linestyle"],
        )
    axes.set_xlim(0.0, 1.0)
    axes.set_ylim(0.0, 1.02)
    axes.set_xlabel("Recall")
    axes.set_ylabel("Precision")
    axes.set_title(title)
    axes.grid(True, alpha=0.3)
    # beside the axes: a dozen curves would hide the high-precision corner
    axes.legend(loc="center left", bbox_to_anchor=(1.02, 0.5), fontsize="small")
    save_figure(figure, path)


def plot_similarity_grid(thumbnails: Mapping[str, Mapping[str, np.ndarray]], path, title: str) -> None:
    """Every learner's similarity matrix of every pair in one figure, thumbnails[learner][pair]:
    (queries, database) similarity in [0, 1] (NaN: blank), as seasonloop.evaluation.learner_evaluation
    writes them. One row per learner, one column per pair, each label once, one colour bar; sized
    to be read at a laptop's width (1,366 px)."""
    rows = list(thumbnails)
    if not rows or not thumbnails[rows[0]]:
        raise ValueError("thumbnails is empty: nothing to plot")
    columns = list(thumbnails[rows[0]])
    for row in rows:
        if list(thumbnails[row]) != columns:
            raise ValueError(f"thumbnails[{row!r}] has pairs {list(thumbnails[row])}, expected {columns}")
    # inches a panel (120 dpi): at most ~1,340 px wide with the row labels and the colour bar
    cell = min(1.6, 9.4 / len(columns))
    figure = Figure(figsize=(len(columns) * cell + 1.8, len(rows) * cell + 1.0), layout="constrained")
    grid = figure.subplots(len(rows), len(columns), squeeze=False)
    for row_index, row in enumerate(rows):
        for col_index, column in enumerate(columns):
            axes = grid[row_index, col_index]
            matrix = np.asarray(thumbnails[row][column], dtype=np.float64)
            axes.imshow(matrix, cmap="viridis", vmin=0.0, vmax=1.0, aspect="auto", interpolation="nearest")
            axes.set_xticks([])
            axes.set_yticks([])
            if col_index == 0:
                axes.set_ylabel(row, fontsize="medium")
            if row_index == 0:
                # long traverse names (a date, say) break at hyphens rather than run into the next panel
                axes.set_title(textwrap.fill(column, _chars_across(cell)), fontsize="medium")
            if row_index == len(rows) - 1:
                axes.set_xlabel("database", fontsize="small")
    # every panel shares the fixed [0, 1] scale, so the colour bar is that scale's, not one panel's
    scale = ScalarMappable(Normalize(0.0, 1.0), cmap="viridis")
    figure.colorbar(scale, ax=grid, shrink=0.6, label="similarity, scaled per matrix (1: nearest)")
    figure.suptitle(textwrap.fill(title, _chars_across(figure.get_figwidth(), fontsize=12)))
    save_figure(figure, path)


def _chars_across(inches: float, fontsize: float = 10) -> int:
    """About how many characters of text at `fontsize` points fit across `inches` (a character of
    DejaVu Sans is ~0.6 of its size wide)."""
    return max(8, int(inches * 72 / (0.6 * fontsize)))


def plot_image_grid(
    images: Sequence[Sequence[np.ndarray]],
    path,
    row_labels: Sequence[str] | None = None,
    col_labels: Sequence[str] | None = None,
    title: str | None = None,
    cmap: str = "gray",
) -> None:
    """Grid of images, images[row][col]: 2-D arrays each scaled to its own min..max, or
    (H, W, 3) RGB uint8 arrays shown as they are.

    Rows may be of different lengths (missing cells stay blank). Used for the PCA projections,
    ICA filters, visual words, example matches and data previews.
    """
    if len(images) == 0 or max(len(row) for row in images) == 0:
        raise ValueError("images is empty: nothing to plot")
    n_rows, n_cols = len(images), max(len(row) for row in images)
    if row_labels is not None and len(row_labels) != n_rows:
        raise ValueError(f"row_labels has {len(row_labels)} entries for {n_rows} rows")
    if col_labels is not None and len(col_labels) != n_cols:
        raise ValueError(f"col_labels has {len(col_labels)} entries for {n_cols} columns")
    first = np.asarray(next(image for row in images for image in row))
    aspect = first.shape[1] / first.shape[0] if first.ndim in (2, 3) and first.shape[0] else 1.0
    cell_height = 1.2
    figure = Figure(figsize=(max(2.0, n_cols * cell_height * aspect + 1.0), max(1.5, n_rows * cell_height + 0.6)))
    grid = figure.subplots(n_rows, n_cols, squeeze=False)
    for row_index in range(n_rows):
        for col_index in range(n_cols):
            axes = grid[row_index, col_index]
            axes.set_xticks([])
            axes.set_yticks([])
            if col_index < len(images[row_index]):
                image = np.asarray(images[row_index][col_index])
                if image.ndim == 3 and image.shape[2] == 3 and image.dtype == np.uint8:
                    axes.imshow(image, interpolation="nearest")
                elif image.ndim == 2:
                    axes.imshow(image.astype(np.float64), cmap=cmap, interpolation="nearest")
                else:
                    raise ValueError(
                        f"images[{row_index}][{col_index}] must be 2-D or (H, W, 3) uint8, got shape {image.shape}"
                    )
            else:
                axes.set_axis_off()
            if row_labels is not None and col_index == 0:
                axes.set_ylabel(str(row_labels[row_index]), fontsize="small")
            if col_labels is not None and row_index == 0:
                axes.set_title(str(col_labels[col_index]), fontsize="small")
    if title is not None:
        figure.suptitle(title)
    save_figure(figure, path)


def plot_series(
    series: Mapping[str, tuple[Sequence[str], Sequence[float]]],
    path,
    title: str,
    xlabel: str,
    ylabel: str,
    bands: Mapping[str, tuple[Sequence[float], Sequence[float]]] | None = None,
) -> None:
    """Lines with markers over categorical x ticks, label -> (x tick labels, values); bands[label]
    = (lows, highs) at the same ticks, drawn as error bars (an interval per point)."""
    if not series:
        raise ValueError("series is empty: nothing to plot")
    figure = Figure(figsize=(6.0, 4.0))
    axes = figure.add_subplot()
    for label, (tick_values, series_values) in series.items():
        ticks, values = [str(tick) for tick in tick_values], np.asarray(series_values, dtype=np.float64)
        if values.ndim != 1 or len(ticks) != values.size:
            raise ValueError(f"series {label!r}: {len(ticks)} x tick labels but values of shape {values.shape}")
        line = axes.plot(ticks, values, marker="o", label=label)[0]
        if bands is not None and label in bands:
            low, high = (np.asarray(bound, dtype=np.float64) for bound in bands[label])
            axes.errorbar(
                ticks, values, yerr=[values - low, high - values], fmt="none", color=line.get_color(), capsize=3
            )
    axes.set_xlabel(xlabel)
    axes.set_ylabel(ylabel)
    axes.set_title(title)
    axes.grid(True, alpha=0.3)
    axes.legend(fontsize="small")
    axes.tick_params(axis="x", labelrotation=15)
    save_figure(figure, path)


def percent_bands(intervals: Sequence[Mapping[str, float | None]]) -> tuple[list[float], list[float]]:
    """plot_series' (lows, highs) in % of intervals {low, high} in fractions; NaN (no bar) where an
    interval was refused (low None: too few queries)."""
    lows = [np.nan if interval["low"] is None else 100 * interval["low"] for interval in intervals]
    highs = [np.nan if interval["high"] is None else 100 * interval["high"] for interval in intervals]
    return lows, highs


def plot_loss_curves(curves: Mapping[str, Mapping[str, Sequence[float]]], path, title: str) -> None:
    """One panel per model, its loss per epoch on a log scale, curves[model][name] (e.g. "train",
    "validation"); the lowest point of a curve named "validation" is marked (the weights kept)."""
    if not curves or not all(curves.values()):
        raise ValueError("curves is empty: nothing to plot")
    figure = Figure(figsize=(4.5 * len(curves), 3.6))
    panels = figure.subplots(1, len(curves), squeeze=False)[0]
    for axes, (model, by_name) in zip(panels, curves.items()):
        for name, curve in by_name.items():
            values = np.asarray(curve, dtype=np.float64)
            epochs = np.arange(1, len(values) + 1)
            axes.plot(epochs, values, marker="." if len(values) < 40 else None, label=name)
            if name == "validation":
                best = int(np.argmin(values))
                axes.plot(epochs[best], values[best], "k*", markersize=10, label=f"kept (epoch {epochs[best]})")
        axes.set_yscale("log")
        axes.set_xlabel("epoch")
        axes.set_ylabel("mean squared error")
        axes.set_title(model)
        axes.grid(True, alpha=0.3)
        axes.legend(fontsize="small")
    figure.suptitle(title)
    save_figure(figure, path)


def plot_message(path, text: str) -> None:
    """A figure that only says why there is nothing to plot (a declared output must still exist)."""
    figure = Figure(figsize=(6.0, 1.5))
    figure.text(0.5, 0.5, text, ha="center", va="center", wrap=True)
    save_figure(figure, path)
