"""Parametrised regions: small shape classes sharing one protocol (DESIGN.md section 5).

A region is placed by the design: a generated function ``design -> (centre, size)`` (a maximum
inscribed circle, a task rectangle), or fixed with
:meth:`PlacedRegion.at`. Each shape has a fixed quadrature on its reference domain (the unit disc, the
cube [-1, 1]^d, or the unit square for a domain between curves) which is mapped into the placed region:
the nodes and their weights (area or volume elements) are CasADi expressions of the design, so every
global index built on them is differentiable in the design.

Protocol, shared by every shape:

* ``guard``: the name of a mechanism function (q, x, design) -> margins that must all hold (>= 0) over
  the region (checked at the nodes of its extreme rule at a fixed resolution: interior, centre and rim,
  see :func:`pkm.regions.quadrature.guard_holds`); where one does not, an index over the region is
  undefined (NaN) rather than an integral across a singularity or a joint limit;

* ``quadrature(functions, design, resolution, reduce) -> (points, weights)``: points d x n and
  weights 1 x n, CasADi when the design is CasADi, numpy (n, d) and (n,) when it is numeric. For an
  extreme (``reduce="min"`` or ``"max"``) the nodes include the centre and the boundary, with zero weight;
* ``sample(functions, design, resolution, reduce) -> (points, cell)``: the cell centres (m, d) of a
  regular grid inside the region and the cell measure, for an independent check by sampling (with the
  boundary points for a minimum);
* ``node_count(resolution, reduce)``;
* ``pieces()``: the simple shapes the region's nodes come from, in node order, each with
  ``reference(resolution, reduce)`` (its nodes and weights in reference coordinates), ``to_pose(functions,
  design, u)`` (a reference point, CasADi, to the pose), ``element(functions, design, u)`` (the measure
  element there: a node's weight is its reference weight times the element) and ``project(u)``
  (reference points (n, d) onto the closed reference domain): what :mod:`pkm.regions.extremes` needs to
  refine a region's extreme between the nodes, and :mod:`pkm.regions.integrand` to integrate point by
  point.

Reference rules: on the unit disc Gauss-Legendre in the radius with weight rho and ``4 resolution``
equally spaced angles (exact area pi); on [-1, 1]^d and on the unit square Gauss-Legendre with
``2 resolution`` points per axis; a cylinder is the product of the disc and the segment.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from functools import lru_cache

import casadi as ca
import numpy as np
from numpy.typing import ArrayLike

from pkm.batch import evaluate
from pkm.errors import PkmError, check_integer
from pkm.regions.region import Array, Functions, Piece, Region

RIM_INSET = 1e-9  # of the span between the curves (a MappedSquare) or of the radius (a disc), for rim nodes
CURVE_SAMPLES = 512  # abscissae at which the curves of a MappedSquare are sampled for its bounding box


MAX_RESOLUTION = 1024  # a quadrature of (2 MAX_RESOLUTION)^2 nodes per part, a sampled axis of as many cells
MAX_SAMPLES = 50_000_000  # cells of a sampled grid


MAX_NODES = 1 << 24  # poses or nodes one evaluation of a global index may take (a few hundred MB of values)


def check_resolution(resolution: int, minimum: int) -> int:
    return check_integer("resolution", resolution, minimum, MAX_RESOLUTION)


def check_nodes(resolution: int, count: int, what: str) -> None:
    """PkmError naming ``resolution`` where it gives more than MAX_NODES poses or nodes (``count``)."""
    if count > MAX_NODES:
        raise PkmError(f"resolution = {resolution} violates: at most {MAX_NODES:,} poses or nodes over {what}; it "
                       f"gives {count:,}")


@lru_cache(maxsize=32)
def gauss_legendre(count: int) -> tuple[np.ndarray, np.ndarray]:
    """Gauss-Legendre nodes and weights on [-1, 1]."""
    return np.polynomial.legendre.leggauss(count)


@lru_cache(maxsize=32)
def disc_quadrature(resolution: int) -> tuple[np.ndarray, np.ndarray]:
    """Nodes (n, 2) and weights (n,) on the unit disc; n = 4 resolution^2; exact area pi."""
    resolution = check_resolution(resolution, 1)
    t, w = gauss_legendre(resolution)
    rho, w_rho = (t + 1) / 2, w / 2 * (t + 1) / 2
    m = 4 * resolution
    angle = 2 * np.pi * (np.arange(m) + 0.5) / m
    nodes = np.stack([np.outer(rho, np.cos(angle)).ravel(), np.outer(rho, np.sin(angle)).ravel()], axis=1)
    weights = np.outer(w_rho, np.full(m, 2 * np.pi / m)).ravel()
    return nodes, weights


def ring(count: int, offset: float = 0.5) -> np.ndarray:
    """``count`` equally spaced points on the unit circle, the first at ``offset`` steps from angle 0."""
    angle = 2 * np.pi * (np.arange(count) + offset) / count
    return np.stack([np.cos(angle), np.sin(angle)], axis=1)


def axes_of_disc() -> np.ndarray:
    """The four points where the unit disc's axes cross its rim: the extremes of a mechanism symmetric
    about an axis often lie there, and the rim of the rule, offset by half a step, never reaches them."""
    return ring(4, offset=0.0)


def square_perimeter(count: int) -> np.ndarray:
    """``count`` equally spaced points on the boundary of [-1, 1]^2, counter-clockwise from (-1, -1)."""
    t = (np.arange(count) + 0.5) / count
    side, u = np.divmod(4 * t, 1.0)
    u = 2 * u - 1
    one = np.ones_like(u)
    edges = {0: (u, -one), 1: (one, u), 2: (-u, one), 3: (-one, -u)}
    out = np.zeros((count, 2))
    for k, (a, b) in edges.items():
        on = side == k
        out[on] = np.stack([a[on], b[on]], axis=1)
    return out


def square_rim(count: int) -> np.ndarray:
    """``count`` points on the boundary of [-1, 1]^2 (:func:`square_perimeter`) and its four corners,
    where extremes over a rectangle often lie."""
    corners = np.array([[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]])
    return np.concatenate([square_perimeter(count), corners])


EXTREMES = ("min", "max")


def _with_centre_and_rim(nodes: np.ndarray, weights: np.ndarray, rim: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """A 2-D rule with the centre first and the rim last, both with zero weight."""
    return (
        np.concatenate([np.zeros((1, 2)), nodes, rim]),
        np.concatenate([[0.0], weights, np.zeros(len(rim))]),
    )


def disc_rule(resolution: int, reduce: str) -> tuple[np.ndarray, np.ndarray]:
    """The unit disc's nodes and weights; for an extreme also its centre, a rim of ``4 resolution``
    points and the points of :func:`axes_of_disc`, with zero weight. The rim lies RIM_INSET inside the
    unit circle: a disc inscribed in a workspace touches its boundary, where the mechanism is singular
    and a local index is a limit that round-off decides."""
    nodes, weights = disc_quadrature(resolution)
    if reduce not in EXTREMES:
        return nodes, weights
    rim = np.concatenate([ring(4 * resolution), axes_of_disc()])
    return _with_centre_and_rim(nodes, weights, _onto_unit_disc(rim, 1 - RIM_INSET))


def square_rule(resolution: int, reduce: str) -> tuple[np.ndarray, np.ndarray]:
    """[-1, 1]^2 by Gauss-Legendre with ``2 resolution`` points per axis; for an extreme also its
    centre and :func:`square_rim` with ``8 resolution`` points, with zero weight."""
    t, w = gauss_legendre(2 * resolution)
    nodes, weights = product((t[:, None], w), (t[:, None], w))
    if reduce not in EXTREMES:
        return nodes, weights
    return _with_centre_and_rim(nodes, weights, square_rim(8 * resolution))


def product(*rules: tuple[np.ndarray, np.ndarray]) -> tuple[np.ndarray, np.ndarray]:
    """The tensor product of quadrature rules given as (nodes (n_k, d_k), weights (n_k,))."""
    nodes, weights = rules[0]
    for more, w in rules[1:]:
        nodes = np.hstack([np.repeat(nodes, len(more), axis=0), np.tile(more, (len(nodes), 1))])
        weights = np.outer(weights, w).ravel()
    return nodes, weights


def _segment(resolution: int, with_ends: bool) -> tuple[np.ndarray, np.ndarray]:
    t, w = gauss_legendre(2 * resolution)
    if with_ends:
        t, w = np.concatenate([t, [-1.0, 0.0, 1.0]]), np.concatenate([w, [0.0, 0.0, 0.0]])
    return t[:, None], w


def grid(box: np.ndarray, resolution: int) -> tuple[np.ndarray, float]:
    """Cell centres (resolution^d, d) of a d-dimensional box (d, 2) and the cell measure."""
    resolution = check_resolution(resolution, 2)
    box = np.asarray(box, dtype=float)
    if resolution ** len(box) > MAX_SAMPLES:
        raise PkmError(f"resolution = {resolution} violates: resolution^{len(box)} <= {MAX_SAMPLES} cells")
    axes = [lo + (hi - lo) * (np.arange(resolution) + 0.5) / resolution for lo, hi in box]
    mesh = np.meshgrid(*axes, indexing="ij")
    cell = float(np.prod([(hi - lo) / resolution for lo, hi in box]))
    return np.stack([m.ravel() for m in mesh], axis=1), cell


def _numeric(design: Array) -> bool:
    return not isinstance(design, ca.MX | ca.SX | ca.DM)


def _as_numpy(points: ca.DM, weights: ca.DM) -> tuple[np.ndarray, np.ndarray]:
    return np.asarray(points).T.copy(), np.asarray(weights).ravel()


@dataclass(frozen=True)
class PlacedRegion:
    """A shape at a centre with a size: from the generated function ``function`` (design -> (centre,
    size)) or ``fixed`` (centre, size) values. Subclasses set ``dimension`` and the reference rule."""

    name: str
    doc: str
    function: str | None = None
    fixed: tuple[tuple[float, ...], tuple[float, ...]] | None = None
    guard: str | None = None

    dimension = 2

    def at(self, centre: ArrayLike, size: ArrayLike) -> PlacedRegion:
        """The same shape fixed at ``centre`` with ``size`` instead of following the design."""
        return replace(self, fixed=(tuple(np.ravel(centre).tolist()), tuple(np.ravel(size).tolist())))

    def placement(self, functions: Functions, design: Array) -> tuple[Array, Array]:
        """(centre, size) for a design: CasADi column vectors (DM for a numeric design)."""
        if self.fixed is not None:
            return ca.DM(self.fixed[0]), ca.DM(self.fixed[1])
        if self.function is None:
            raise PkmError(f"region {self.name} has neither a placement function nor a fixed placement")
        centre, size = functions[self.function](ca.DM(design) if _numeric(design) else design)
        return centre, size

    def scale(self, size: Array) -> Array:
        """Half-extent of the region along each pose axis (a d x 1 CasADi vector)."""
        return size

    def reference(self, resolution: int, reduce: str) -> tuple[np.ndarray, np.ndarray]:
        raise NotImplementedError

    def inside_reference(self, u: np.ndarray) -> np.ndarray:
        """Mask of reference points (n, d) strictly inside the reference domain."""
        return np.all(np.abs(u) < 1, axis=1)

    def boundary_reference(self, count: int) -> np.ndarray:
        raise NotImplementedError

    def node_count(self, resolution: int, reduce: str = "mean") -> int:
        return len(self.reference(check_resolution(resolution, 1), reduce)[1])

    def pieces(self) -> tuple[Piece, ...]:
        return (self,)

    def to_pose(self, functions: Functions, design: Array, u: Array) -> Array:
        """The pose (d x 1) at the reference point u (d x 1, CasADi)."""
        centre, size = self.placement(functions, design)
        return centre + self.scale(size) * u

    def element(self, functions: Functions, design: Array, u: Array) -> Array:  # noqa: ARG002
        """The measure element at the reference point u: the product of the half extents, the same at
        every u."""
        _, size = self.placement(functions, design)
        return _product(self.scale(size))

    def project(self, u: np.ndarray) -> np.ndarray:
        """Reference points (n, d) moved onto the closed reference domain [-1, 1]^d."""
        return np.clip(u, -1.0, 1.0)

    def quadrature(self, functions: Functions, design: Array, resolution: int, reduce: str = "mean"):
        nodes, weights = self.reference(check_resolution(resolution, 1), reduce)
        centre, size = self.placement(functions, design)
        scale = self.scale(size)
        points = ca.repmat(centre, 1, len(nodes)) + ca.diag(scale) @ ca.DM(nodes.T)
        w = ca.DM(weights).T * _product(scale)
        if _numeric(design):
            return _as_numpy(ca.DM(points), ca.DM(w))
        return points, w

    def sample(
        self, functions: Functions, design: Array, resolution: int, reduce: str = "mean"
    ) -> tuple[np.ndarray, float]:
        resolution = check_resolution(resolution, 2)
        centre, size = (np.asarray(a, dtype=float).ravel() for a in self.placement(functions, np.asarray(design)))
        scale = np.asarray(self.scale(ca.DM(size)), dtype=float).ravel()
        box = np.stack([centre - scale, centre + scale], axis=1)
        points, cell = grid(box, resolution)
        points = points[self.inside_reference((points - centre) / scale)]
        if reduce in EXTREMES:
            points = np.concatenate([points, centre + scale * self.boundary_reference(4 * resolution)])
        return points, cell


def _product(scale: Array) -> Array:
    out = scale[0]
    for k in range(1, scale.numel()):
        out = out * scale[k]
    return out


@dataclass(frozen=True)
class Disc(PlacedRegion):
    """A disc: centre (2,), size (radius,)."""

    dimension = 2

    def scale(self, size):
        return ca.repmat(size[0], 2, 1)

    def reference(self, resolution, reduce):
        return disc_rule(resolution, reduce)

    def inside_reference(self, u):
        return np.sum(u**2, axis=1) < 1

    def project(self, u):
        return _onto_unit_disc(u, 1 - RIM_INSET)

    def boundary_reference(self, count):
        return ring(count)


def _onto_unit_disc(u: np.ndarray, radius: float = 1.0) -> np.ndarray:
    """Points (n, 2) moved radially onto the closed disc of ``radius`` about the origin."""
    norm = np.linalg.norm(u, axis=1, keepdims=True)
    return np.where(norm > radius, u * (radius / np.where(norm > radius, norm, 1.0)), u)


@dataclass(frozen=True)
class Rectangle(PlacedRegion):
    """An axis-aligned rectangle: centre (2,), size (half width, half height)."""

    dimension = 2

    def reference(self, resolution, reduce):
        return square_rule(resolution, reduce)

    def boundary_reference(self, count):
        return square_rim(count)


@dataclass(frozen=True)
class Box(PlacedRegion):
    """An axis-aligned box in three pose coordinates: centre (3,), size (three half extents). For a
    minimum the nodes of each axis add -1, 0 and 1: the centre, the faces, edges and corners."""

    dimension = 3

    def reference(self, resolution, reduce):
        axis = _segment(resolution, reduce in EXTREMES)
        return product(axis, axis, axis)

    def boundary_reference(self, count):
        k = max(2, math.ceil(math.sqrt(count / 6)))
        t = np.linspace(-1, 1, k)[:, None]
        nodes, _ = product((t, np.ones(k)), (t, np.ones(k)), (t, np.ones(k)))
        return nodes[np.any(np.abs(nodes) == 1, axis=1)]


@dataclass(frozen=True)
class Cylinder(PlacedRegion):
    """A cylinder in three pose coordinates with its axis along pose coordinate ``axis``: centre (3,),
    size (radius, half length). The product of the disc rule and the Gauss-Legendre segment; for a
    minimum, of the disc's nodes with its centre and rim and the segment's with its ends and middle."""

    axis: int = 0
    dimension = 3

    def _order(self) -> list[int]:
        """Positions of (disc u, disc v, axial) in the pose coordinates."""
        others = [k for k in range(3) if k != self.axis]
        return [others[0], others[1], self.axis]

    def scale(self, size):
        out = [None, None, None]
        out[self._order()[0]] = size[0]
        out[self._order()[1]] = size[0]
        out[self.axis] = size[1]
        return ca.vertcat(*out)

    def _arrange(self, nodes: np.ndarray) -> np.ndarray:
        out = np.empty_like(nodes)
        out[:, self._order()] = nodes
        return out

    def reference(self, resolution, reduce):
        nodes, weights = product(disc_rule(resolution, reduce), _segment(resolution, reduce in EXTREMES))
        return self._arrange(nodes), weights

    def inside_reference(self, u):
        order = self._order()
        return (u[:, order[0]] ** 2 + u[:, order[1]] ** 2 < 1) & (np.abs(u[:, self.axis]) < 1)

    def project(self, u):
        order = self._order()
        out = np.array(u, dtype=float)
        out[:, order[:2]] = _onto_unit_disc(out[:, order[:2]], 1 - RIM_INSET)
        out[:, self.axis] = np.clip(out[:, self.axis], -1.0, 1.0)
        return out

    def boundary_reference(self, count):
        k = max(2, math.ceil(math.sqrt(count)))
        side, _ = product((ring(k), np.ones(k)), (np.linspace(-1, 1, k)[:, None], np.ones(k)))
        caps, _ = product((disc_quadrature(max(1, k // 4))[0], np.ones(4 * max(1, k // 4) ** 2)),
                          (np.array([[-1.0], [1.0]]), np.ones(2)))
        return self._arrange(np.concatenate([side, caps]))


@dataclass(frozen=True)
class MappedSquare:
    """A two-dimensional domain between design-dependent curves, mapped from the unit square.

    The first pose coordinate a runs over [a_lo, a_hi] (the generated function ``bounds``: design ->
    (a_lo, a_hi)); at each a the second runs from lower(a) to upper(a) (the generated function
    ``curves``: (a, design) -> (lower, upper)). The unit square (u, v) maps to a = a_lo + (a_hi - a_lo)
    u, b = lower(a) + (upper(a) - lower(a)) v with the area element (a_hi - a_lo)(upper(a) - lower(a)).
    With ``grading`` p > 1, b = lower + (upper - lower)(1 - (1 - v)^p) instead (element times
    p (1 - v)^(p - 1)): nodes crowd towards the upper curve, and an integrand that behaves like the square
    root of the distance to it (p = 2) becomes smooth in v. Rim nodes (of the extreme rules) lie RIM_INSET
    inside the curves, where a pose on a curve may be out of reach by round-off.
    """

    name: str
    doc: str
    bounds: str
    curves: str
    guard: str | None = None
    grading: int = 1

    dimension = 2

    def reference(self, resolution: int, reduce: str) -> tuple[np.ndarray, np.ndarray]:
        nodes, weights = square_rule(resolution, reduce)
        return (nodes + 1) / 2, weights / 4

    def node_count(self, resolution: int, reduce: str = "mean") -> int:
        return len(self.reference(check_resolution(resolution, 1), reduce)[1])

    def pieces(self) -> tuple[Piece, ...]:
        return (self,)

    def to_pose(self, functions: Functions, design: Array, u: Array) -> Array:
        """The pose (2 x 1) at the point u (2 x 1, CasADi) of the unit square, as :meth:`quadrature`
        maps its nodes."""
        lo, hi = functions[self.bounds](design)
        v = ca.fmin(ca.fmax(1 - (1 - u[1]) ** self.grading, RIM_INSET), 1 - RIM_INSET)
        a = lo + (hi - lo) * u[0]
        lower, upper = functions[self.curves](a, design)
        return ca.vertcat(a, lower + (upper - lower) * v)

    def element(self, functions: Functions, design: Array, u: Array) -> Array:
        """The area element at the point u of the unit square, as :meth:`quadrature` weighs its nodes."""
        lo, hi = functions[self.bounds](design)
        lower, upper = functions[self.curves](lo + (hi - lo) * u[0], design)
        slope = self.grading * (1 - u[1]) ** (self.grading - 1) if self.grading > 1 else 1
        return (hi - lo) * (upper - lower) * slope

    def project(self, u: np.ndarray) -> np.ndarray:
        """Points (n, 2) moved onto the closed unit square."""
        return np.clip(u, 0.0, 1.0)

    def _map(self, functions: Functions, design: Array, nodes: np.ndarray):
        lo, hi = functions[self.bounds](design)
        u = ca.DM(nodes[:, 0]).T
        v = ca.DM(np.clip(1 - (1 - nodes[:, 1]) ** self.grading, RIM_INSET, 1 - RIM_INSET)).T
        slope = ca.DM(self.grading * (1 - nodes[:, 1]) ** (self.grading - 1)).T
        a = lo + (hi - lo) * u
        lower, upper = functions[self.curves].map(len(nodes))(a, design)
        b = lower + (upper - lower) * v
        return ca.vertcat(a, b), (hi - lo) * (upper - lower) * slope

    def quadrature(self, functions: Functions, design: Array, resolution: int, reduce: str = "mean"):
        nodes, weights = self.reference(check_resolution(resolution, 1), reduce)
        numeric = _numeric(design)
        points, element = self._map(functions, ca.DM(design) if numeric else design, nodes)
        w = ca.DM(weights).T * element
        if numeric:
            return _as_numpy(ca.DM(points), ca.DM(w))
        return points, w

    def sample(
        self, functions: Functions, design: Array, resolution: int, reduce: str = "mean"
    ) -> tuple[np.ndarray, float]:
        resolution = check_resolution(resolution, 2)
        d = np.asarray(design, dtype=float)
        lo, hi = (float(v) for v in functions[self.bounds](d))
        a = np.linspace(lo, hi, CURVE_SAMPLES)
        lower, upper = (v[:, 0, 0] for v in evaluate(functions[self.curves], a[:, None], d))
        box = np.array([[lo, hi], [float(lower.min()), float(upper.max())]])
        points, cell = grid(box, resolution)
        at_lower, at_upper = (v[:, 0, 0] for v in evaluate(functions[self.curves], points[:, :1], d))
        points = points[(points[:, 1] > at_lower) & (points[:, 1] < at_upper)]
        if reduce in EXTREMES:
            rim, _ = self._map(functions, ca.DM(d), (square_rim(4 * resolution) + 1) / 2)
            points = np.concatenate([points, np.asarray(rim).T])
        return points, cell


@dataclass(frozen=True)
class Mapped:
    """A shape in other coordinates, mapped into the pose by the generated function ``to_pose``
    ((y, design) -> x). Weights and measures stay those of the shape's own coordinates (a task region
    stated in the coordinates a designer specifies it in), or with ``element`` (the generated function
    (y, design) -> |det dx/dy|) they are the pose's own. ``modes``, where given, are the working modes
    the region is defined on (those whose joint ranges its guard checks)."""

    name: str
    doc: str
    inner: Region
    to_pose: str
    element: str | None = None
    guard: str | None = None
    modes: tuple[str, ...] | None = None

    @property
    def dimension(self) -> int:
        return self.inner.dimension

    def node_count(self, resolution: int, reduce: str = "mean") -> int:
        return self.inner.node_count(resolution, reduce)

    def pieces(self) -> tuple[Piece, ...]:
        return tuple(MappedPiece(p, self.to_pose, self.element) for p in self.inner.pieces())

    def quadrature(self, functions: Functions, design: Array, resolution: int, reduce: str = "mean"):
        numeric = _numeric(design)
        d = ca.DM(design) if numeric else design
        points, weights = self.inner.quadrature(functions, d, resolution, reduce)
        mapped = functions[self.to_pose].map(points.size2())(points, d)
        if self.element is not None:
            weights = weights * functions[self.element].map(points.size2())(points, d)
        if numeric:
            return _as_numpy(ca.DM(mapped), ca.DM(weights))
        return mapped, weights

    def sample(
        self, functions: Functions, design: Array, resolution: int, reduce: str = "mean"
    ) -> tuple[np.ndarray, float | np.ndarray]:
        """The inner shape's samples mapped to the pose, with the cell measure of each (scaled by the
        area element where there is one)."""
        points, cell = self.inner.sample(functions, design, resolution, reduce)
        d = np.asarray(design, dtype=float)
        (mapped,) = evaluate(functions[self.to_pose], points, d)
        if self.element is not None:
            (element,) = evaluate(functions[self.element], points, d)
            cell = cell * np.abs(element[:, 0, 0])
        return mapped[:, :, 0], cell


@dataclass(frozen=True)
class MappedPiece:
    """A piece of a :class:`Mapped` region: the inner piece's reference points carried into the pose by
    the generated function ``map_to_pose`` ((y, design) -> x), with the region's ``map_element``."""

    inner: Piece
    map_to_pose: str
    map_element: str | None = None

    @property
    def dimension(self) -> int:
        return self.inner.dimension

    def reference(self, resolution: int, reduce: str) -> tuple[np.ndarray, np.ndarray]:
        return self.inner.reference(resolution, reduce)

    def node_count(self, resolution: int, reduce: str = "mean") -> int:
        return self.inner.node_count(resolution, reduce)

    def to_pose(self, functions: Functions, design: Array, u: Array) -> Array:
        return functions[self.map_to_pose](self.inner.to_pose(functions, design, u), design)

    def element(self, functions: Functions, design: Array, u: Array) -> Array:
        inner = self.inner.element(functions, design, u)
        if self.map_element is None:
            return inner
        return inner * functions[self.map_element](self.inner.to_pose(functions, design, u), design)

    def project(self, u: np.ndarray) -> np.ndarray:
        return self.inner.project(u)


@dataclass(frozen=True)
class Union:
    """Shapes side by side (disjoint but for their common boundaries), one region: the nodes and weights of
    every part, so that each part's rule stays smooth where the region's boundary has a kink."""

    name: str
    doc: str
    parts: tuple[Region, ...]
    guard: str | None = None

    @property
    def dimension(self) -> int:
        return self.parts[0].dimension

    def node_count(self, resolution: int, reduce: str = "mean") -> int:
        return sum(p.node_count(resolution, reduce) for p in self.parts)

    def pieces(self) -> tuple[Piece, ...]:
        return tuple(piece for part in self.parts for piece in part.pieces())

    def quadrature(self, functions: Functions, design: Array, resolution: int, reduce: str = "mean"):
        rules = [p.quadrature(functions, design, resolution, reduce) for p in self.parts]
        if _numeric(design):
            return np.concatenate([r[0] for r in rules]), np.concatenate([r[1] for r in rules])
        return ca.horzcat(*(r[0] for r in rules)), ca.horzcat(*(r[1] for r in rules))

    def sample(
        self, functions: Functions, design: Array, resolution: int, reduce: str = "mean"
    ) -> tuple[np.ndarray, np.ndarray]:
        """Every part's samples, with the cell measure of each point."""
        samples = [p.sample(functions, design, resolution, reduce) for p in self.parts]
        points = np.concatenate([s[0] for s in samples])
        cells = np.concatenate([np.broadcast_to(np.asarray(s[1], dtype=float), (len(s[0]),)) for s in samples])
        return points, cells


@dataclass(frozen=True)
class Poses:
    """Given poses (a path's samples, a cloud of task points), fixed in SI and each of the same weight
    1 / count: a mean over them is their average, an extreme their least or largest value; nothing lies
    between them, so extremes are not refined (``refinable``: the piece needs no ``project``) and every
    resolution gives the same nodes. Its reference coordinates are the pose's own."""

    name: str
    doc: str
    poses: tuple[tuple[float, ...], ...]
    guard: str | None = None

    refinable = False

    @property
    def dimension(self) -> int:
        return len(self.poses[0])

    def node_count(self, resolution: int, reduce: str = "mean") -> int:  # noqa: ARG002
        return len(self.poses)

    def pieces(self) -> tuple[Piece, ...]:
        return (self,)

    def reference(self, resolution: int, reduce: str) -> tuple[np.ndarray, np.ndarray]:  # noqa: ARG002
        points = np.array(self.poses, dtype=float)
        return points, np.full(len(points), 1.0 / len(points))

    def to_pose(self, functions: Functions, design: Array, u: Array) -> Array:  # noqa: ARG002
        return u

    def element(self, functions: Functions, design: Array, u: Array) -> Array:  # noqa: ARG002
        return ca.SX(1.0) if isinstance(design, ca.SX) else ca.DM(1.0)

    def quadrature(self, functions: Functions, design: Array, resolution: int, reduce: str = "mean"):  # noqa: ARG002
        points, weights = self.reference(resolution, reduce)
        if _numeric(design):
            return points, weights
        return ca.DM(points.T), ca.DM(weights).T

    def sample(self, functions: Functions, design: Array, resolution: int, reduce: str = "mean"  # noqa: ARG002
               ) -> tuple[np.ndarray, float]:
        points, weights = self.reference(resolution, reduce)
        return points, float(weights[0])
