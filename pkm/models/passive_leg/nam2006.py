"""Nam and Park's performance indices (section 6.1) and their composition (eq. 31), in two readings.

eta_1 is the region mean of 1/kappa (eq. 27), eta_2 the region mean of the manipulability (eq. 29) and
eta_3 the workspace's area per the footprint S (eq. 30), each over the workspace region of section 4.
The text leaves four choices open; a :class:`Reading` fixes them:

* the area element dW: the plane of (x_c, y_c) (dW = l_c dtheta dl_c, region ``workspace``) or eq. 28
  as printed (dW = dtheta dl_c, region ``workspace_eq28``);
* the manipulability's matrix: the forward Jacobian (|det J_f|, Yoshikawa's measure of output velocity
  per input, index ``manipulability``) or the J = J_q^-1 J_x of eq. 21 as printed (``jacobian_determinant``);
* the condition number's norm: the weighted Frobenius norm of Gao 1998, which the paper cites for
  eq. 27 (``gci``), or the 2-norm (``gci_2``);
* the normalisation "with respect to its extreme values": (eta - min) / (max - min) over the design
  space (``range``) or eta / max (``max``).

``SUPPORTED`` is the reading the paper's statements support (docs/papers/nam2006.md shows which
statement each reading reproduces); ``LITERAL`` the equations as printed; ``KAPPA_2`` and
``MAX_NORMALISED`` change one choice of ``SUPPORTED`` each. Extremes are taken over the
admissible designs of a grid over the design space (those whose indices are defined: no singularity, joint
limit or unreached pose inside the region).
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from functools import cache

import numpy as np

from pkm import registry
from pkm.errors import PkmError
from pkm.regions.quadrature import admissible, parametrised_global

MODE = "out_out"
EXTREMES_GRID = 31  # chart nodes per axis of the grid whose admissible designs give the extremes
EXTREMES_RESOLUTION = 4  # the means change by less than 1e-4 from there on (tests/test_passive_leg.py)
RESOLUTION = 8


@dataclass(frozen=True)
class Reading:
    """The four choices the text leaves open (module docstring)."""

    name: str
    region: str
    eta1: str
    eta2: str
    normalise: str

    @property
    def indices(self) -> tuple[str, str, str]:
        return self.eta1, self.eta2, "space_utilization"


SUPPORTED = Reading("supported", "workspace", "gci", "manipulability", "range")
LITERAL = Reading("literal", "workspace_eq28", "gci", "jacobian_determinant", "range")
KAPPA_2 = Reading("kappa_2", "workspace", "gci_2", "manipulability", "range")
MAX_NORMALISED = Reading("max_normalised", "workspace", "gci", "manipulability", "max")
READINGS = {r.name: r for r in (SUPPORTED, LITERAL, KAPPA_2, MAX_NORMALISED)}


def reading(name: str | Reading) -> Reading:
    if isinstance(name, Reading):
        return name
    if name not in READINGS:
        raise PkmError(f"unknown reading {name!r}; expected one of {', '.join(READINGS)}")
    return READINGS[name]


def chart_designs(mech, u: np.ndarray, v: np.ndarray) -> np.ndarray:
    """Design vectors (n, n_p) of chart points (r/R, l_b/R) of the nam2006 space with R = 1."""
    space = mech.design_spaces["nam2006"]
    return np.asarray(space.designs(mech.parameters, [np.asarray(u, float), np.asarray(v, float)], check=False))


def etas(mech, designs: np.ndarray, which: str | Reading = SUPPORTED, *, resolution: int = RESOLUTION) -> np.ndarray:
    """(eta_1, eta_2, eta_3) of designs (D, n_p): an array (D, 3), NaN where a design is not admissible."""
    r = reading(which)
    region = mech.region(r.region)
    branch = mech.working_mode(MODE)
    designs = np.atleast_2d(np.asarray(designs, dtype=float))
    out = np.full((len(designs), 3), np.nan)
    kept = np.flatnonzero(designs[:, mech.parameter_names().index("l_a")] > 0)
    kept = kept[admissible(mech, region, designs[kept], branch=branch)]
    if kept.size:
        checked = replace(region, guard=None)  # the guard holds for these designs: checked once, not per index
        for k, name in enumerate(r.indices):
            out[kept, k] = parametrised_global(mech, registry.global_index(name), checked, designs[kept],
                                               branch=branch, resolution=resolution)
    return out


@cache
def extremes(which: str | Reading = SUPPORTED, grid: int = EXTREMES_GRID, resolution: int = EXTREMES_RESOLUTION
             ) -> tuple[tuple[float, float], ...]:
    """(min, max) of each eta over the admissible designs of a grid x grid chart over the design space."""
    mech = registry.mechanism("passive_leg")
    u = np.linspace(0.5, 2.0, grid)
    U, V = np.meshgrid(u, u, indexing="ij")
    values = etas(mech, chart_designs(mech, U.ravel(), V.ravel()), which, resolution=resolution)
    admissible = np.all(np.isfinite(values), axis=1)
    if not admissible.any():
        raise PkmError("no admissible design on the grid over the nam2006 design space")
    kept = values[admissible]
    return tuple((float(lo), float(hi)) for lo, hi in zip(kept.min(axis=0), kept.max(axis=0), strict=True))


def normalised(values, bounds: tuple[tuple[float, float], ...], how: str):
    """The hatted indices of eq. 31: (eta - min) / (max - min) or eta / max, per column (arrays or
    CasADi expressions given as a list of three)."""
    out = []
    for k, (lo, hi) in enumerate(bounds):
        value = values[k] if isinstance(values, list | tuple) else values[..., k]
        out.append((value - lo) / (hi - lo) if how == "range" else value / hi)
    return out


def composed(values, bounds: tuple[tuple[float, float], ...], how: str):
    """eta = eta_1^ eta_2^ eta_3^ (eq. 31)."""
    a, b, c = normalised(values, bounds, how)
    return a * b * c
