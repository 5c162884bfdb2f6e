"""Figures without pyplot: fixed margins, plain-text log axes, written straight to PNG.

Figures are `matplotlib.figure.Figure` objects: no pyplot, so that drawing never selects a backend
or touches the caller's matplotlib state.
"""

from __future__ import annotations

import math

from matplotlib.figure import Figure
from matplotlib.ticker import FuncFormatter, LogFormatterSciNotation, LogLocator

# Margins in inches, fixed: an automatic layout (`tight_layout`) measures every tick label before
# the figure is drawn, which doubles the cost of writing it (~0.3 s a figure; a warm `jaxcontact
# run` writes three). These fit the longest labels drawn here (log-axis powers of ten, three lines
# of title at 8 pt); the gaps between panels hold a tick label and an axis label.
MARGINS = dict(left=0.95, right=0.25, bottom=0.6, top=0.55, between_columns=0.9, between_rows=0.35)


def figure(figsize=(6, 4.2), rows: int = 1, columns: int = 1) -> Figure:
    """A figure with the fixed margins above for a `rows` × `columns` grid, without pyplot."""
    width, height = figsize
    m = MARGINS
    across = width - m["left"] - m["right"]
    down = height - m["bottom"] - m["top"]
    fig = Figure(figsize=figsize)
    fig.subplots_adjust(
        left=m["left"] / width,
        right=1 - m["right"] / width,
        bottom=m["bottom"] / height,
        top=1 - m["top"] / height,
        # wspace and hspace are fractions of the mean panel width and height.
        wspace=m["between_columns"] / ((across - (columns - 1) * m["between_columns"]) / columns),
        hspace=m["between_rows"] / ((down - (rows - 1) * m["between_rows"]) / rows),
    )
    return fig


def subplots(rows: int = 1, columns: int = 1, **kw):
    """`(figure, axes)` as `pyplot.subplots` makes them, without pyplot."""
    fig = figure(kw.pop("figsize", (6, 4.2)), rows, columns)
    return fig, fig.subplots(rows, columns, **kw)


_SUPERSCRIPTS = str.maketrans("-0123456789", "⁻⁰¹²³⁴⁵⁶⁷⁸⁹")


def _power_of_ten(value, _position=None) -> str:
    """`10⁻⁷` in plain text for a power of ten, else no label."""
    exponent = math.log10(value) if value > 0 else math.nan
    if not math.isfinite(exponent) or abs(exponent - round(exponent)) > 1e-9:
        return ""
    return "10" + str(round(exponent)).translate(_SUPERSCRIPTS)


def _light_log_axes(fig) -> None:
    """Log axes with plain-text decade labels and minor ticks at 2 and 5 only.

    Matplotlib's default decade labels are mathtext, parsed with pyparsing when drawn, and its
    eight minor ticks a decade are each an artist: together a third of the time to write a
    figure. Formatters and locators chosen by the plot itself are left alone.
    """
    for ax in fig.axes:
        for axis in (ax.xaxis, ax.yaxis):
            if axis.get_scale() != "log":
                continue
            if type(axis.get_major_formatter()) is LogFormatterSciNotation:
                axis.set_major_formatter(FuncFormatter(_power_of_ten))
            if type(axis.get_minor_locator()) is LogLocator:
                axis.set_minor_locator(LogLocator(subs=(2.0, 5.0)))


def save_figure(fig, path) -> str:
    """Write a figure (PNG, 120 dpi); returns the path."""
    _light_log_axes(fig)
    fig.savefig(path, dpi=120)
    return str(path)
