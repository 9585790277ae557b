"""Figures a reader can read: one way to make and save a figure, colour limits that an outlier does not
flatten, and a check that no text leaves the canvas or covers another.

Every figure pkm draws is made by :func:`figure` (an Agg canvas, constrained layout) and written by
:func:`save`, the one place a figure becomes a file: a test can replace it to collect the figures and
pass each to :func:`text_problems`.

A colour map scaled to its extremes shows one flat colour when a few values lie far from the rest (a
design next to a singularity, a pose where an index grows without bound). :func:`robust_limits` scales it
to the bulk of the finite values instead and says on which side values are clipped; :func:`colour_bar`
draws the bar with a triangle at each clipped end (``extend``) and its label says where the clip is.
"""

from __future__ import annotations

import os
import textwrap
from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from itertools import combinations
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from pkm import io
from pkm.errors import PkmError

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.colorbar import Colorbar
    from matplotlib.figure import Figure
    from matplotlib.text import Text
    from matplotlib.transforms import Bbox

PERCENTILES = (5.0, 95.0)  # the bulk of the values a colour map spans
SLACK = 1.0  # a value beyond the bulk by more than this times its span is an outlier
MIN_COUNT = 20  # fewer values have no bulk to tell an outlier from
TOLERANCE = 0.5  # pixels: extents that overlap or leave the canvas by less are taken as touching


def figure(width: float, height: float) -> Figure:
    """A figure of ``width`` x ``height`` inches on an Agg canvas with constrained layout (titles, labels
    and colour bars placed so that they do not overlap)."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=(width, height), layout="constrained")
    FigureCanvasAgg(fig)
    return fig


def save(fig: Figure, path: str | os.PathLike, *, dpi: int) -> Path:
    """Write ``fig`` to ``path`` atomically (:func:`pkm.io.atomic_write`) in the format its suffix names
    (PNG without one), at ``dpi`` dots per inch; returns the path. The layout the figure was drawn with is kept
    afterwards (its layout engine set to none): a later save in another format places nothing again, so its
    axes are where the first format's are, and the constrained layout's passes, most of a save's time, are
    paid once."""
    path = Path(path)
    kind = path.suffix[1:].lower() or "png"
    written = io.atomic_write(path, lambda tmp: fig.savefig(tmp, format=kind, dpi=dpi))
    if fig.get_layout_engine() is not None:
        fig.set_layout_engine("none")
    return written


@dataclass(frozen=True)
class ColourLimits:
    """The range a colour map spans: ``vmin``, ``vmax``, and whether finite values lie below ``vmin``
    (``below``) or above ``vmax`` (``above``) and are drawn in the end colours."""

    vmin: float
    vmax: float
    below: bool = False
    above: bool = False

    @property
    def extend(self) -> str:
        """matplotlib's ``extend`` of a colour bar or filled contours: ``"neither"``, ``"min"``,
        ``"max"`` or ``"both"``."""
        if self.below and self.above:
            return "both"
        return "min" if self.below else "max" if self.above else "neither"

    @property
    def clipped(self) -> str:
        """Where values are clipped, in words (empty when none is): ``"clipped below 0.1 and above 2"``."""
        sides = [f"below {self.vmin:.3g}" if self.below else "", f"above {self.vmax:.3g}" if self.above else ""]
        return f"clipped {' and '.join(filter(None, sides))}" if any(sides) else ""

    def levels(self, count: int = 12) -> np.ndarray:
        """About ``count`` round contour levels over [vmin, vmax]. At a clipped limit the first or last
        level is the limit itself (the values past it are the ones drawn in the end colour, and a round
        level within half a step of it is left out); at a limit not clipped, the nearest round level
        outside."""
        from matplotlib.ticker import MaxNLocator

        ticks = MaxNLocator(count).tick_values(self.vmin, self.vmax)
        apart = 0.5 * (ticks[1] - ticks[0])  # a round level closer than this to a clipped limit gives way
        if self.below:
            ticks = np.concatenate([[self.vmin], ticks[ticks > self.vmin + apart]])
        if self.above:
            ticks = np.concatenate([ticks[ticks < self.vmax - apart], [self.vmax]])
        return ticks


def robust_limits(values: Any, *, percentiles: tuple[float, float] = PERCENTILES, slack: float = SLACK) -> ColourLimits:
    """Colour limits over the finite entries of ``values`` that outliers do not stretch.

    The bulk of the values lies between the ``percentiles`` (each taken at a value, inwards: a single
    outlier among a few values does not move them); a value beyond the bulk by more than ``slack`` times
    its span is an outlier. The limits are the smallest and the largest value that is not an outlier, so
    that only outliers are clipped, and ``below`` and ``above`` say whether any is. Fewer than
    ``MIN_COUNT`` values, or a bulk of (next to) no span, are all drawn; when they are all equal, the
    limits are that value +-0.5 (+-half its size when it is not 0).

    Raises
    ------
    PkmError
        When ``values`` has no finite entry, the percentiles are not 0 <= lower < upper <= 100 or slack
        is negative.
    """
    lower, upper = percentiles
    if not 0 <= lower < upper <= 100:
        raise PkmError(f"percentiles = {percentiles} violates 0 <= lower < upper <= 100")
    if not slack >= 0:
        raise PkmError(f"slack = {slack} violates slack >= 0")
    finite = np.asarray(values, dtype=float)
    finite = finite[np.isfinite(finite)]
    if finite.size == 0:
        raise PkmError("values violate: at least one finite value to scale a colour map to")
    smallest, largest = float(finite.min()), float(finite.max())
    if smallest == largest:
        half = 0.5 * abs(smallest) or 0.5
        return ColourLimits(smallest - half, largest + half)
    lo = float(np.percentile(finite, lower, method="higher"))
    hi = float(np.percentile(finite, upper, method="lower"))
    if finite.size < MIN_COUNT or hi - lo <= 1e-9 * (largest - smallest):
        return ColourLimits(smallest, largest)
    reach = slack * (hi - lo)
    kept = finite[(finite >= lo - reach) & (finite <= hi + reach)]
    vmin, vmax = float(kept.min()), float(kept.max())
    return ColourLimits(vmin, vmax, smallest < vmin, largest > vmax)


def colour_bar(fig: Figure, mappable: Any, limits: ColourLimits, *, ax: Axes | list[Axes], label: str,
               **options: Any) -> Colorbar:
    """A colour bar of ``mappable`` beside ``ax`` with a triangle at each clipped end and ``label``
    followed, on a line of its own, by where values are clipped; ``options`` go to ``fig.colorbar``."""
    text = "\n".join(filter(None, [label, f"({limits.clipped})" if limits.clipped else ""]))
    return fig.colorbar(mappable, ax=ax, label=text, extend=limits.extend, **options)


def legends_below(axes: Sequence[Axes], *, gap: float = 4.0, **options: Any) -> None:
    """Place the legend of each of ``axes`` (all of one figure) centred below its x tick labels and
    x label, ``gap`` points under them; ``options`` go to ``ax.legend``.

    The distance is measured in points, where tick labels and axis labels keep their size when the layout
    resizes the axes (a distance in axes fractions would shrink with the axes onto the label): it needs no
    layout, only the axis's texts as they are.
    """
    from matplotlib.transforms import ScaledTranslation

    axes = list(axes)
    if not axes:
        return
    fig = axes[0].figure
    renderer = fig.canvas.get_renderer()
    for ax in axes:
        drop = (ax.bbox.y0 - ax.xaxis.get_tightbbox(renderer).y0) * 72 / fig.dpi + gap
        shift = ScaledTranslation(0, -drop / 72, fig.dpi_scale_trans)
        ax.legend(loc="upper center", bbox_to_anchor=(0.5, 0), bbox_transform=ax.transAxes + shift, **options)


def hide_overlapping(fig: Figure, texts: Iterable[Text]) -> int:
    """Hide each of ``texts``, in order, that overlaps one kept before it or leaves its axes once the
    figure is laid out; returns how many were hidden.

    For labels placed in data coordinates, which no layout moves apart: contour labels
    (``ax.clabel``), whose spacing on the page depends on the data, the grid and the size of the axes.
    """
    fig.draw_without_rendering()
    renderer = fig.canvas.get_renderer()
    kept, hidden = [], 0
    for text in texts:
        box = text.get_window_extent(renderer)
        frame = fig.bbox if text.axes is None else text.axes.bbox
        if _outside(box, frame) > TOLERANCE or any(_overlap(box, other) for other in kept):
            text.set_visible(False)
            hidden += 1
        else:
            kept.append(box)
    return hidden


def _outside(box: Bbox, frame: Bbox) -> float:
    """How far an extent reaches beyond a frame on its farthest side (<= 0 inside)."""
    return max(frame.x0 - box.x0, box.x1 - frame.x1, frame.y0 - box.y0, box.y1 - frame.y1)


def _overlap(a: Bbox, b: Bbox) -> tuple[float, float] | None:
    """Width and height of the overlap of two extents, or None when they are apart (within TOLERANCE)."""
    width = min(a.x1, b.x1) - max(a.x0, b.x0)
    height = min(a.y1, b.y1) - max(a.y0, b.y0)
    return (width, height) if width > TOLERANCE and height > TOLERANCE else None


def _axis_texts(axis: Any, name: str, place: str) -> list[tuple[str, Text]]:
    """The texts an axis draws, each named by ``name`` (x or y) and its ``place``: its label, its offset
    text and the labels of the ticks inside its view interval (the ticks outside are kept by matplotlib
    but not drawn)."""
    if not axis.get_visible():
        return []
    low, high = sorted(axis.get_transform().transform(np.asarray(axis.get_view_interval(), dtype=float)))
    room = 1e-10 * (high - low)
    out = [(f"{name} label of {place}", axis.label), (f"{name} offset text of {place}", axis.offsetText)]
    for tick in [*axis.get_major_ticks(), *axis.get_minor_ticks()]:
        where = float(axis.get_transform().transform(np.array([tick.get_loc()], dtype=float))[0])
        if low - room <= where <= high + room:
            out += [(f"{name} tick label of {place}", tick.label1), (f"{name} tick label of {place}", tick.label2)]
    return out


def _texts(fig: Figure) -> list[tuple[str, Text]]:
    """Every text of a drawn figure with where it is: its own texts (suptitle among them) and legends,
    and of each visible axes its titles, texts and annotations, legend and axis texts; only the visible
    ones that are not empty."""
    from matplotlib.text import Text

    found = [("figure text", t) for t in fig.texts]
    found += [("figure legend", t) for legend in fig.legends for t in [legend.get_title(), *legend.get_texts()]]
    for k, ax in enumerate(fig.axes):
        if not ax.get_visible():
            continue
        title = textwrap.shorten(ax.get_title(), 40)
        place = f"axes {k}" + (" (colour bar)" if ax.get_label() == "<colorbar>" else f" {title!r}" if title else "")
        found += [(f"title of axes {k}" if t is ax.title else f"text in {place}", t) for t in ax.get_children()
                  if isinstance(t, Text)]
        legend = ax.get_legend()
        if legend is not None and legend.get_visible():
            found += [(f"legend text in {place}", t) for t in [legend.get_title(), *legend.get_texts()]]
        if ax.axison:
            found += _axis_texts(ax.xaxis, "x", place) + _axis_texts(ax.yaxis, "y", place)
    return [(where, t) for where, t in found if t.get_visible() and t.get_text().strip()]


def text_problems(fig: Figure) -> list[str]:
    """Lay ``fig`` out and draw it (on an Agg canvas, without rasterising), then describe each visible
    text whose extent leaves the canvas and each pair of visible texts whose extents overlap (tick labels
    of one axis included); empty when the figure is readable.

    Texts are the figure's texts and suptitle, axes titles, axis labels, tick labels (the drawn ones),
    offset texts, legend texts, colour-bar labels and ticks, and the texts and annotations of each axes.
    Extents that touch within 0.5 pixel count as apart.
    """
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    if not isinstance(fig.canvas, FigureCanvasAgg):
        FigureCanvasAgg(fig)
    fig.draw_without_rendering()
    renderer = fig.canvas.get_renderer()
    placed = [(f"{where} {t.get_text()!r}", t.get_window_extent(renderer)) for where, t in _texts(fig)]
    problems = []
    for name, box in placed:
        if (outside := _outside(box, fig.bbox)) > TOLERANCE:
            problems.append(f"{name} leaves the canvas by {outside:.0f} px")
    for (name_a, a), (name_b, b) in combinations(placed, 2):
        if overlap := _overlap(a, b):
            problems.append(f"{name_a} overlaps {name_b} ({overlap[0]:.0f} x {overlap[1]:.0f} px)")
    return problems
