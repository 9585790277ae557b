"""Normalised (non-dimensional) design spaces and their planar charts (DESIGN.md section 3).

A design space maps normalised link lengths (and a length scale L in metres) to a mechanism's SI
design, and a planar chart maps the normalised lengths to two coordinates for atlases and for
synthesis. The maps use arithmetic only, so they accept floats, numpy arrays and CasADi expressions.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from matplotlib.path import Path as PolygonPath


@dataclass(frozen=True)
class DesignSpace:
    """A normalised design space with a planar chart.

    ``to_design(c, scale)`` and ``from_design(d) -> (c, scale)`` convert normalised coordinates c
    (last axis) to SI designs; ``to_chart(c)`` and ``from_chart(u, v)`` convert to and from the chart.
    ``polygon`` is the closure of the space in the chart (its vertices, counter-clockwise).
    """

    name: str
    doc: str
    coordinates: tuple[str, ...]
    chart_axes: tuple[str, str]
    to_design: Callable
    from_design: Callable
    to_chart: Callable
    from_chart: Callable
    polygon: tuple[tuple[float, float], ...]

    def chart_grid(self, resolution: int, *, inset: float = 1e-3) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """A regular chart grid: axes u (n,), v (n,) and a mask (n, n) of the nodes inside the space.

        Nodes closer than ``inset`` (chart units) to the boundary are left out: the boundary holds the
        degenerate designs (a zero length, or a base as long as the reach).
        """
        poly = np.array(self.polygon)
        u = np.linspace(poly[:, 0].min(), poly[:, 0].max(), resolution)
        v = np.linspace(poly[:, 1].min(), poly[:, 1].max(), resolution)
        U, V = np.meshgrid(u, v, indexing="ij")
        path = PolygonPath(poly)
        inside = path.contains_points(np.stack([U.ravel(), V.ravel()], 1), radius=-2 * inset)
        return u, v, inside.reshape(U.shape)
