"""Certified regions (issue 41): a property proved over the whole of a task region, refuted by a pose inside it,
or left undecided in boxes of a stated size, by branch and prune on rigorous enclosures (:mod:`pkm.intervals`).

A property is a local index at least a threshold: ``singularity``, the least of the type I and type II singularity
margins (:data:`pkm.indices.local.SINGULARITY`) at least ``threshold`` (1e-6, pkm's singular pose, by default);
``limits``, the least workspace margin (the legs' reach and every stated limit, signed) at least 0; ``collisions``,
the collision margin (the least distance between two legs' capsules less their radii, :mod:`pkm.spec.collisions`) at
least 0. The region (a disc, rectangle, box or cylinder, placed or mapped into the pose) is certified in its
reference coordinates u in [-1, 1]^d, the pose x(u) its placement at the design, the index g(x(u)) one SX graph at
the working mode and the design. Each box B of u:

- outside the region (a disc's or a cylinder's round part entirely beyond its rim): dropped;
- proved where the enclosure of g over B, the tighter of the natural one and the mean-value form
  g(m) + grad g(B) (B - m) (m the box's centre), lies at or above the threshold;
- refuted where g at a point of B inside the region, enclosed at that point, lies below it: the point is the
  witness, and the region's verdict is refuted;
- else halved across its widest side, down to ``depth`` halvings; a box left at that depth is undecided.

The verdict: ``proved`` (every box proved), ``refuted`` (a witness), else ``undecided`` with the volume of the
undecided boxes as a fraction of the region's reference box. Boxes, time and the largest depth reached are
reported. A sampled check (pkm's region extremes) is never called certified, nor the reverse."""

from __future__ import annotations

import functools
import heapq
import itertools
import math
import time
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import casadi as ca
import numpy as np

from pkm import regions
from pkm.errors import PkmError
from pkm.indices.local import SINGULAR, WORKSPACE_MARGIN
from pkm.intervals import ball, enclosure, span

PROPERTIES = {"singularity": (("singularity_margin_type1", "singularity_margin_type2"), SINGULAR),
              "limits": (("workspace_margin",), 0.0),
              "collisions": (("collision_margin",), 0.0)}  # each property's indices and its default threshold
DEPTH = 14  # halvings of a box at most (a side of 2^-(14/d) of the region's per coordinate)
MAX_BOXES = 20000  # boxes examined at most
SECONDS = 60.0  # time at most


@dataclass
class Certificate:
    """The verdict on each property over the region: ``proved``, ``refuted`` (with ``witnesses``: poses inside
    the region, each with the property's value there) or ``undecided`` (``undecided`` the fraction of the
    region's reference box left undecided); ``boxes`` examined, ``depth`` reached and ``seconds`` taken."""

    mechanism: str
    region: str
    mode: str
    design: dict[str, float]
    properties: dict[str, float]  # the thresholds
    verdict: str
    witnesses: list[dict[str, Any]] = field(default_factory=list)
    undecided: float = 0.0
    boxes: int = 0
    depth: int = 0
    seconds: float = 0.0
    stopped: str = ""  # why the search stopped short (the box or time budget), "" where it ran out of boxes
    designs: dict[str, list[float]] = field(default_factory=dict)  # the parameters that span intervals
    cells: dict[str, list[list[list[float]]]] = field(default_factory=dict)  # the boxes proved and those left
    # undecided, each [lower corner, upper corner] in the reference coordinates (:func:`plot_certificate`)

    def as_dict(self) -> dict[str, Any]:
        return {**{k: getattr(self, k) for k in ("mechanism", "region", "mode", "design", "designs", "properties",
                                                 "verdict", "witnesses", "undecided", "boxes", "depth", "seconds",
                                                 "stopped")},
                "cells": {state: len(boxes) for state, boxes in self.cells.items()}}


def _round_axes(shape: Any) -> list[int]:
    """The reference coordinates that a disc (or a cylinder's disc) joins, where the region is round."""
    inner = getattr(shape, "inner", shape)
    if isinstance(inner, regions.Disc):
        return [0, 1]
    if isinstance(inner, regions.Cylinder):
        return [k for k in range(3) if k != inner.axis]
    return []


def _as_casadi(design: Any) -> Any:
    """A design vector as CasADi takes it: symbolic where some of it spans a box (:func:`certify`'s designs)."""
    return design if isinstance(design, ca.SX) else ca.DM(design)


def _margins(mech: Any, x: ca.SX, mode: str, design: Any) -> tuple[dict[str, ca.SX], ca.SX]:
    """The properties' values at the pose x, and the joints there: the type I and type II singularity margins as
    |det A| / prod_j ||a_j|| (the determinants from the first order, A = [H_a H_p] and [H_p H_x] from the closure:
    the same Hadamard ratios as pkm.indices.local's, in a form whose enclosures stay tight), and the least
    workspace margin (signed beyond the reach)."""
    signs, d = ca.DM(mech.working_mode(mode).signs), _as_casadi(design)
    fused = regions.pipeline(mech, (), first_order=True)
    q, _, _, *rest = fused(x, signs, d)
    first = dict(zip(fused.name_out()[3:], rest, strict=True))
    _, H_q, H_x = mech.functions["constraint"](q, x, d)
    columns = (H_q, ca.horzcat(H_q[:, mech.n_act:], H_x))
    out = {}
    for k, A in enumerate(columns, 1):
        norms = ca.SX(1)
        for j in range(A.size2()):
            norms = norms * ca.norm_2(A[:, j])
        out[f"singularity_margin_type{k}"] = ca.fabs(first[f"det_type{k}"]) / norms
    (margin,) = regions.pipeline(mech, (WORKSPACE_MARGIN,))(x, signs, d)[3:]
    out["workspace_margin"] = margin
    return out, q


PIECES = 8  # each capsule's segment cut into this many pieces, their boxes' gaps bounding the distance below


@dataclass(frozen=True)
class _Capsules:
    """The legs' capsules over a box: the drawing's points enclosed, each pair of segments of two legs
    (:func:`pkm.spec.collisions.pairs`) bounded below by the gaps between the boxes of their pieces, and above at
    a point by the distance between two of their points."""

    points: Any  # the enclosure of the drawing's points (n x dim, by columns) over a box of u
    n: int
    dim: int
    pairs: list[tuple[int, int, int, int]]
    first: list[int]
    radii: np.ndarray
    at: ca.Function  # the points at u
    margin: ca.Function  # the collision margin at u, in floats
    plates: list[tuple[int, int, list[int], float]]  # (leg, segment, the plate's vertices' rows in points, its radius)
    plate_margins: Any  # the enclosure of the segments' margins to the plates over a box of u

    def _segments(self, balls: list[Any], i: int, a: int) -> tuple[list[Any], list[Any]]:
        row = self.first[i] + a
        return ([balls[row + self.n * c] for c in range(self.dim)],
                [balls[row + 1 + self.n * c] for c in range(self.dim)])

    def lower(self, lo: np.ndarray, hi: np.ndarray) -> float:
        """The least margin's lower bound over the box."""
        (balls,) = self.points([[ball(a, b) for a, b in zip(lo, hi, strict=True)]])
        boxes: dict[tuple[int, int], list[list[Any]]] = {}

        def pieces(i: int, a: int) -> list[list[Any]]:
            if (i, a) not in boxes:
                boxes[i, a] = _pieces(*self._segments(balls, i, a))
            return boxes[i, a]

        least = math.inf
        for i, a, j, b in self.pairs:
            gap = min(_box_gap(one, two) for one in pieces(i, a) for two in pieces(j, b))
            clear = ball(gap, gap) - ball(self.radii[i], self.radii[i]) - ball(self.radii[j], self.radii[j])
            least = min(least, float(clear.lower()) if clear.is_finite() else -math.inf)
        for i, a, rows, radius in self.plates:
            plate = [functools.reduce(span, (balls[r + self.n * c] for r in rows)) for c in range(self.dim)]
            gap = min(_box_gap(one, plate) for one in pieces(i, a))
            clear = ball(gap, gap) - ball(self.radii[i], self.radii[i]) - ball(radius, radius)
            least = min(least, float(clear.lower()) if clear.is_finite() else -math.inf)
        return least

    def upper(self, u: np.ndarray) -> float:
        """The least margin's upper bound at u: the distance between two points of each pair, enclosed."""
        (balls,) = self.points([[ball(c, c) for c in u]])
        points = np.asarray(self.at(u), dtype=float)
        least = math.inf
        for i, a, j, b in self.pairs:
            s, t = _closest(points[self.first[i] + a], points[self.first[i] + a + 1], points[self.first[j] + b],
                            points[self.first[j] + b + 1])
            (p1, q1), (p2, q2) = self._segments(balls, i, a), self._segments(balls, j, b)
            square = sum(((p + (q - p) * s) - (r + (w - r) * t)) ** 2 for p, q, r, w in zip(p1, q1, p2, q2,
                                                                                          strict=True))
            margin = square.sqrt() - ball(self.radii[i], self.radii[i]) - ball(self.radii[j], self.radii[j])
            least = min(least, float(margin.upper()) if margin.is_finite() else math.inf)
        if self.plates:
            margins = self.plate_margins([[ball(c, c) for c in u]])[0]
            least = min(least, *(float(m.upper()) if m.is_finite() else math.inf for m in margins))
        return least


def _pieces(p: list[Any], q: list[Any]) -> list[list[Any]]:
    """The boxes of the PIECES pieces of the segment p q (its ends enclosed per coordinate): each per coordinate the
    union of its ends' balls."""
    return [[span(p[c] + (q[c] - p[c]) * k / PIECES, p[c] + (q[c] - p[c]) * (k + 1) / PIECES) for c in range(len(p))]
            for k in range(PIECES)]


def _box_gap(one: list[Any], two: list[Any]) -> float:
    """A lower bound of the distance between two boxes (per coordinate a ball): the gap between them, -inf where
    one is not finite."""
    total = ball(0.0, 0.0)
    for a, b in zip(one, two, strict=True):
        if not (a.is_finite() and b.is_finite()):
            return -math.inf
        gap = b.lower() - a.upper() if b > a else (a.lower() - b.upper() if a > b else None)
        if gap is not None:
            total = total + gap**2
    return float(total.sqrt().lower())


def _closest(p1: np.ndarray, q1: np.ndarray, p2: np.ndarray, q2: np.ndarray) -> tuple[float, float]:
    """The parameters of two segments' closest points, in floats (any two points give an upper bound)."""
    best = (math.inf, 0.0, 0.0)
    for s in np.linspace(0, 1, 65):
        a = p1 + s * (q1 - p1)
        d2 = q2 - p2
        t = float(np.clip(np.dot(a - p2, d2) / max(np.dot(d2, d2), 1e-300), 0, 1))
        gap = float(np.linalg.norm(a - p2 - t * d2))
        best = min(best, (gap, float(s), t))
    return best[1], best[2]


@dataclass(frozen=True)
class _Domain:
    """What a search certifies: the properties' values g(u) over reference coordinates u in [-1, 1]^d (each
    property's indices in order, but the collision margin), their gradient, the pose x(u), the round coordinates
    (a unit disc or ball among them), the thresholds per index and, for collisions, the legs' capsules."""

    value: Any
    slope: Any
    g: ca.Function
    pose: ca.Function
    indices: list[str]
    round_axes: list[int]
    limits: np.ndarray
    capsules: _Capsules | None = None
    design: ca.Function | None = None  # the design at u, where designs span a box


def _domain(mech: Any, x: ca.SX, u: ca.SX, round_axes: list[int], *, bounds: dict[str, float], mode: str,
            design: Any) -> _Domain:
    margins, q = _margins(mech, x, mode, design)
    capsules = _capsules(mech, q, x, u, design) if "collisions" in bounds else None
    indices = [i for n in bounds if n != "collisions" for i in PROPERTIES[n][0]]
    limits = [bounds[n] for n in bounds if n != "collisions" for _ in PROPERTIES[n][0]]
    g = ca.Function("certified", [u], [ca.vertcat(*(margins[i] for i in indices))])
    gradient = ca.Function("certified_gradient", [u], [ca.densify(ca.jacobian(g(u), u))])
    spanned = ca.Function("certified_design", [u], [design]) if isinstance(design, ca.SX) else None
    return _Domain(enclosure(g), enclosure(gradient), g, ca.Function("certified_pose", [u], [x]), indices,
                   round_axes, np.array(limits), capsules, spanned)


def _capsules(mech: Any, q: ca.SX, x: ca.SX, u: ca.SX, design: np.ndarray) -> _Capsules:
    """The legs' capsules at the joints q and the pose x(u): the drawing's points, then each plate's vertices
    (:func:`pkm.spec.collisions.plate_polygon`), enclosed together."""
    from pkm.spec.collisions import pairs, plate_pairs, plate_polygon, plate_radii
    from pkm.spec.vocabulary import kind_of

    d = _as_casadi(design)
    description = mech.description
    points = mech.functions["skeleton"](q, x, d)
    counts = [kind_of(leg).points for leg in description.data["legs"]]
    first = [sum(counts[:k]) for k in range(len(counts))]
    plates = plate_radii(description, d)
    polygons = {plate: plate_polygon(description, mech.functions, plate, points=points, x=x, d=d) for plate in plates}
    rows, corners = {}, points.size1()
    for plate, vertices in polygons.items():
        rows[plate], corners = list(range(corners, corners + len(vertices))), corners + len(vertices)
    drawn = ca.vertcat(points, *(v.T for vertices in polygons.values() for v in vertices))
    at = ca.Function("capsule_points", [u], [ca.densify(drawn)])
    margins = mech.functions["collision"](q, x, d)
    margin = ca.Function("capsule_margin", [u], [ca.mmin(margins)])
    plate_margins = ca.Function("plate_margins", [u], [ca.densify(margins[len(pairs(description)):])])
    radii = dict(zip(plates, _radii(ca.vertcat(*plates.values()), u), strict=True)) if plates else {}
    return _Capsules(enclosure(at), drawn.size1(), drawn.size2(), pairs(description), first,
                     _radii(mech.functions["capsules"](d), u), at, margin,
                     [(i, a, rows[plate], radii[plate]) for i, a, plate in plate_pairs(description)],
                     enclosure(plate_margins))


def _radii(radii: Any, u: ca.SX) -> np.ndarray:
    """Capsules' or plates' radii: numbers, or where a radius follows a design parameter that spans a box, its
    largest over the box (a bound that only widens them: a proof stays a proof)."""
    if isinstance(radii, ca.DM):
        return np.asarray(radii, dtype=float).ravel()
    enclosed = enclosure(ca.Function("radii", [u], [ca.densify(radii)]))
    return np.array([float(r.upper()) for r in enclosed([[ball(-1.0, 1.0)] * u.numel()])[0]])


def _bounds(mech: Any, properties: Sequence[str], threshold: float | None) -> dict[str, float]:
    unknown = [p for p in properties if p not in PROPERTIES]
    if unknown or not properties:
        raise PkmError(f"properties violates: some of {', '.join(PROPERTIES)}; got {', '.join(unknown) or 'none'}")
    if "collisions" in properties and ("collision" not in mech.functions or
                                       getattr(mech, "description", None) is None):
        raise PkmError(f"properties violates: collisions of a described machine whose legs state their capsules; "
                       f"{mech.name}'s do not")
    if threshold is not None and not 0 <= threshold < 1:
        raise PkmError(f"threshold violates: a singularity margin in [0, 1); got {threshold!r}")
    return {p: (threshold if p == "singularity" and threshold is not None else PROPERTIES[p][1])
            for p in properties}


def certify(mech: Any, region: Any, design: Any = None, *, properties: Sequence[str] = ("singularity", "limits"),
            mode: str | None = None, threshold: float | None = None, depth: int = DEPTH, max_boxes: int = MAX_BOXES,
            seconds: float = SECONDS, designs: Mapping[str, Sequence[float]] | None = None,
            progress: Callable[[int, int], None] | None = None) -> Certificate:
    """Each property proved, refuted or left undecided over the region (a name or a region of the mechanism)
    at the design in the working mode (module docstring); ``threshold`` the least singularity margin; with
    ``designs`` ({parameter: [lower, upper]}), at every design whose parameters lie in those intervals (the
    others the design's): the box searched spans them too, and a witness names its design; ``progress(boxes,
    max_boxes)`` is called before each box is examined (an exception it raises stops the search). In parallel
    over boxes: :func:`pkm.certify_pieces.certify`."""
    task = checked(mech, region, design, properties=properties, mode=mode, threshold=threshold, designs=designs)
    found = search(mech, prepared(mech, task), depth=depth, max_boxes=max_boxes, seconds=seconds, progress=progress)
    return task.certificate(mech, found)


@dataclass(frozen=True)
class Task:
    """A certification's inputs, checked: the region (as given, and placed), the design vector, the working
    mode, the properties (as given, and their thresholds), the least singularity margin given and the design
    parameters that span intervals."""

    region: Any
    shape: Any
    design: np.ndarray
    mode: str
    properties: tuple[str, ...]
    threshold: float | None
    bounds: dict[str, float]
    spans: dict[str, tuple[float, float]]

    @property
    def dimension(self) -> int:
        """The searched box's: the region's reference coordinates and the spanning parameters'."""
        return self.shape.pieces()[0].dimension + len(self.spans)

    def certificate(self, mech: Any, found: dict[str, Any]) -> Certificate:
        return Certificate(mech.name, regions.region_name(self.shape), self.mode, mech.design_dict(self.design),
                           self.bounds, **found, designs={n: list(interval) for n, interval in self.spans.items()})


def checked(mech: Any, region: Any, design: Any = None, *, properties: Sequence[str] = ("singularity", "limits"),
            mode: str | None = None, threshold: float | None = None,
            designs: Mapping[str, Sequence[float]] | None = None) -> Task:
    """A certification's inputs checked (:func:`certify`'s)."""
    bounds = _bounds(mech, properties, threshold)
    shape = mech.region(region)
    d = mech.design_vector(design)
    pieces = shape.pieces()
    inner = getattr(shape, "inner", shape)
    if len(pieces) != 1 or not isinstance(inner, regions.Disc | regions.Rectangle | regions.Box | regions.Cylinder):
        raise PkmError(f"region {regions.region_name(shape)} violates: one disc, rectangle, box or cylinder (placed, "
                       "or mapped into the pose) to certify over, its reference coordinates in [-1, 1]")
    return Task(region, shape, d, mech.working_mode(mode).name, tuple(properties), threshold, bounds,
                _spans(mech, designs))


def placed(mech: Any, task: Task) -> tuple[ca.SX, Any, ca.SX]:
    """A certification's reference coordinates u (the region's, then the spanning design parameters'), the design
    at u and the pose x(u)."""
    piece = task.shape.pieces()[0]
    u = ca.SX.sym("u", task.dimension)
    at = _spanned(mech, task.design, task.spans, u[piece.dimension:]) if task.spans else ca.DM(task.design)
    return u, at, piece.to_pose(mech.functions, at, u[: piece.dimension])


def prepared(mech: Any, task: Task) -> _Domain:
    """The domain of a certification: the region's reference coordinates and the spanning design parameters'."""
    u, at, x = placed(mech, task)
    return _domain(mech, x, u, _round_axes(task.shape), bounds=task.bounds, mode=task.mode, design=at)


def _spans(mech: Any, designs: Mapping[str, Sequence[float]] | None) -> dict[str, tuple[float, float]]:
    """The design parameters that span intervals, checked: each a parameter of the mechanism, lower < upper,
    finite and within its bounds."""
    if designs is None:
        return {}
    if not isinstance(designs, Mapping):
        raise PkmError(f"designs violates: a table {{parameter: [lower, upper]}}; got {type(designs).__name__}")
    spans = {}
    for name, given in designs.items():
        parameter = next((p for p in mech.parameters if p.name == name), None)
        if parameter is None:
            raise PkmError(f"designs violates: parameters of {mech.name} ({', '.join(mech.parameter_names())}); got "
                           f"{name!r}")
        try:
            lower, upper = (float(v) for v in given)
        except (TypeError, ValueError):
            raise PkmError(f"designs.{name} violates: [lower, upper], two numbers; got {given!r}") from None
        if not (np.isfinite(lower) and np.isfinite(upper) and parameter.lower <= lower < upper <= parameter.upper):
            raise PkmError(f"designs.{name} violates: finite, lower < upper, within [{parameter.lower:g}, "
                           f"{parameter.upper:g}]; got [{lower:g}, {upper:g}]")
        spans[name] = (lower, upper)
    return spans


def _spanned(mech: Any, design: np.ndarray, spans: dict[str, tuple[float, float]], v: ca.SX) -> ca.SX:
    """The design vector with each spanning parameter at the middle of its interval plus half its width times
    its reference coordinate in [-1, 1]."""
    names = list(mech.parameter_names())
    entries = [ca.SX(float(value)) for value in design]
    for k, (name, (lower, upper)) in enumerate(spans.items()):
        entries[names.index(name)] = (lower + upper) / 2 + (upper - lower) / 2 * v[k]
    return ca.vertcat(*entries)


def halves(lo: np.ndarray, hi: np.ndarray) -> tuple[tuple[np.ndarray, np.ndarray], tuple[np.ndarray, np.ndarray]]:
    """A box's two halves across its widest side, the lower first: how the search cuts a box."""
    k = int(np.argmax(hi - lo))
    middle = (lo[k] + hi[k]) / 2
    upper_lo, lower_hi = lo.copy(), hi.copy()
    upper_lo[k], lower_hi[k] = middle, middle
    return (lo, lower_hi), (upper_lo, hi)


def search(mech: Any, domain: _Domain, *, depth: int, max_boxes: int, seconds: float,
            start: tuple[np.ndarray, np.ndarray, int] | None = None,
            progress: Callable[[int, int], None] | None = None) -> dict[str, Any]:
    """Branch and prune over [-1, 1]^d (or the box ``start``: its corners and its level), the largest box first
    (module docstring); ``progress(boxes, max_boxes)`` before each box."""
    dim = domain.g.numel_in(0)
    lo, hi, level = start if start is not None else (np.full(dim, -1.0), np.full(dim, 1.0), 0)
    began = time.perf_counter()
    order = itertools.count()  # the heap's tie-break: first pushed, first taken
    queue = [(-float(np.prod(hi - lo)), next(order), lo, hi, level)]
    undecided, boxes, reached, stopped, witnesses = 0.0, 0, 0, "", []
    cells: dict[str, list[list[list[float]]]] = {"proved": [], "undecided": []}
    while queue:
        if boxes >= max_boxes or time.perf_counter() - began > seconds:
            stopped = f"the budget of {max_boxes} boxes or {seconds:g} s"
            undecided += sum(float(np.prod((hi - lo) / 2)) for _, _, lo, hi, _ in queue)
            cells["undecided"] += [[lo.tolist(), hi.tolist()] for _, _, lo, hi, _ in queue]
            break
        if progress is not None:
            progress(boxes, max_boxes)
        _, _, lo, hi, level = heapq.heappop(queue)
        boxes += 1
        reached = max(reached, level)
        if _outside(lo, hi, domain.round_axes):
            continue
        if _proved(domain, lo, hi):
            cells["proved"].append([lo.tolist(), hi.tolist()])
            continue
        centre = (lo + hi) / 2
        if _inside(centre, domain.round_axes) and _refuted(domain, centre):
            witnesses.append(_witness(mech, domain, centre))
            break
        if level >= depth:
            undecided += float(np.prod((hi - lo) / 2))
            cells["undecided"].append([lo.tolist(), hi.tolist()])
            continue
        for part in halves(lo, hi):
            heapq.heappush(queue, (-float(np.prod(part[1] - part[0])), next(order), *part, level + 1))
    verdict = "refuted" if witnesses else ("proved" if undecided == 0.0 else "undecided")
    return {"verdict": verdict, "witnesses": witnesses, "undecided": undecided, "boxes": boxes, "depth": reached,
            "seconds": time.perf_counter() - began, "stopped": stopped, "cells": cells}


WORKSPACE_RESOLUTION = 121  # nodes a side of the workspace drawn under a certification's boxes


def _task_of(mech: Any, region: Any, certificate: Certificate, design: Any = None) -> Task:
    """The task a certificate answered, at ``design`` (the certificate's by default)."""
    return checked(mech, region, design if design is not None else certificate.design,
                   properties=tuple(certificate.properties), mode=certificate.mode,
                   threshold=certificate.properties.get("singularity"), designs=certificate.designs or None)


def certificate_drawing(mech: Any, region: Any, certificate: Certificate, design: Any = None) -> Any:
    """Each box's corners in its first two reference coordinates (the others at its middle) mapped to the pose's first
    two coordinates (a region of more coordinates, or spanning designs, as its projection), the region's reference
    square or disc edge mapped, and the witnesses' poses (:class:`pkm.workspace_map.CellsDrawing`)."""
    return _drawing(mech, _task_of(mech, region, certificate, design), certificate)


def _drawing(mech: Any, task: Task, certificate: Certificate) -> Any:
    from pkm.workspace_map import CellsDrawing

    u, _, x = placed(mech, task)
    pose = ca.Function("certified_pose", [u], [x])

    def mapped(points: np.ndarray) -> np.ndarray:
        return np.asarray(pose.map(len(points))(points.T), dtype=float).T[:, :2]

    cells = {}
    for state in ("proved", "undecided"):
        boxes = np.asarray(certificate.cells.get(state, []), dtype=float).reshape(-1, 2, task.dimension)
        corners = np.repeat(((boxes[:, 0] + boxes[:, 1]) / 2)[:, None], 4, axis=1)
        for k, (i, j) in enumerate(((0, 0), (1, 0), (1, 1), (0, 1))):
            corners[:, k, 0], corners[:, k, 1] = boxes[:, i, 0], boxes[:, j, 1]
        cells[state] = mapped(corners.reshape(-1, task.dimension)).reshape(-1, 4, 2) if len(boxes) else \
            np.zeros((0, 4, 2))
    angle = np.linspace(0, 2 * np.pi, 181)
    edge = (np.column_stack([np.cos(angle), np.sin(angle)]) if _round_axes(task.shape)[:2] == [0, 1]
            else np.array([[-1, -1], [1, -1], [1, 1], [-1, 1], [-1, -1]], dtype=float))
    outline = np.zeros((len(edge), task.dimension))
    outline[:, :2] = edge
    witnesses = np.array([[w["pose"][n] for n in mech.pose_names[:2]] for w in certificate.witnesses]).reshape(-1, 2)
    return CellsDrawing(cells, mapped(outline), witnesses)


def plot_certificate(mech: Any, region: Any, certificate: Certificate, path: Any, design: Any = None) -> Any:
    """The certification's boxes (:func:`certificate_drawing`) over the workspace (the mode's reach, grey, in the
    plane of the pose's first two coordinates, the others at the region's centre): the proved ones green, those
    left undecided orange, each witness a red cross, the region's outline; a PNG or SVG by the path's suffix
    (:func:`pkm.figures.save`)."""
    from matplotlib.patches import Patch
    from matplotlib.ticker import MaxNLocator

    from pkm import figures
    from pkm.workspace_map import draw_cells, workspace_slice

    task = _task_of(mech, region, certificate, design)
    drawing = _drawing(mech, task, certificate)
    fig = figures.figure(6.4, 6.4)
    ax = fig.subplots()
    u, _, x = placed(mech, task)
    centre = np.asarray(ca.Function("centre", [u], [x])(np.zeros(task.dimension)), dtype=float).ravel()
    held = {n: float(v) for n, v in zip(mech.pose_names[2:], centre[2:], strict=True)}
    reach = workspace_slice(mech, mech.design_dict(task.design), index=mech.local_indices()[0], mode=task.mode,
                            axes=tuple(mech.pose_names[:2]), held=held, resolution=WORKSPACE_RESOLUTION)
    ax.contourf(reach.u, reach.v, np.isfinite(reach.values).T.astype(float), levels=[0.5, 1.5], colors=["0.88"])
    workspace = Patch(facecolor="0.88", label=f"the workspace (mode {task.mode}"
                                               + "".join(f", {n} = {v:.3g}" for n, v in held.items()) + ")")
    draw_cells(ax, drawing)
    names = dict(zip(mech.pose_names, mech.pose_units, strict=True))
    ax.set_xlabel(f"{mech.pose_names[0]} [{names[mech.pose_names[0]]}]")
    ax.set_ylabel(f"{mech.pose_names[1]} [{names[mech.pose_names[1]]}]")
    ax.set_aspect("equal")
    ax.autoscale_view()
    ax.xaxis.set_major_locator(MaxNLocator(5))
    ax.yaxis.set_major_locator(MaxNLocator(6))
    ax.legend(handles=[workspace, *ax.get_legend_handles_labels()[0]], fontsize=8, loc="upper center",
              bbox_to_anchor=(0.5, -0.12), ncol=2, frameon=False)
    properties = ", ".join(f"{p} >= {v:g}" for p, v in certificate.properties.items())
    ax.set_title(f"{mech.name}: {properties} over {certificate.region}, mode {certificate.mode}: "
                 f"{certificate.verdict}", fontsize=9, wrap=True)
    return figures.save(fig, path, dpi=120)


@dataclass
class LargestRegion:
    """The largest disc (a planar pose's position) or ball (a spatial one's) about a pose at its orientation
    where the properties hold: ``proved`` the radius certified, ``beyond`` the least radius above it found not
    proved, ``witness`` the nearest pose found where a property fails (its ``distance`` from the centre: the rims
    from ``beyond`` outwards searched, by steps doubling from the tolerance, then by halving the gap to the
    nearest rim found clear), each certification's verdict by radius in ``steps``."""

    mechanism: str
    centre: dict[str, float]
    properties: dict[str, float]
    proved: float
    beyond: float
    witness: dict[str, Any] | None
    steps: list[dict[str, Any]]
    seconds: float

    def as_dict(self) -> dict[str, Any]:
        return {k: getattr(self, k) for k in ("mechanism", "centre", "properties", "proved", "beyond", "witness",
                                              "steps", "seconds")}


def largest_region(mech: Any, pose: Any, design: Any = None, *, radius: float,
                   properties: Sequence[str] = ("singularity", "limits"), mode: str | None = None,
                   threshold: float | None = None, tolerance: float = 1e-3, depth: int = DEPTH,
                   max_boxes: int = MAX_BOXES, seconds: float = SECONDS,
                   designs: Mapping[str, Sequence[float]] | None = None) -> LargestRegion:
    """The largest disc or ball of the pose's position (its coordinates in m; the others held) about ``pose``
    where the properties hold, certified from both sides: bisection on the radius from ``radius`` (the
    largest tried) until the proved radius and the one beyond it differ by ``tolerance`` (relative); a
    refuted radius is replaced by its witness's distance (a pose where a property fails), an undecided one
    counts as not proved. With ``designs`` ({parameter: [lower, upper]}, as :func:`certify` takes them), for
    every design within the intervals: a witness names its design."""
    bounds = _bounds(mech, properties, threshold)
    d = mech.design_vector(design)
    spans = _spans(mech, designs)
    mode = mech.working_mode(mode).name
    centre = np.asarray(pose, dtype=float).ravel()
    moved = [k for k, unit in enumerate(mech.pose_units) if unit == "m"]
    if len(centre) != mech.n_out or not np.all(np.isfinite(centre)):
        raise PkmError(f"pose violates: {mech.n_out} finite numbers ({', '.join(mech.pose_names)})")
    if not (isinstance(radius, int | float) and math.isfinite(radius) and radius > 0):
        raise PkmError(f"radius violates: a finite positive length; got {radius!r}")
    if not (isinstance(tolerance, int | float) and 0 < tolerance < 1):
        raise PkmError(f"tolerance violates: a relative gap in (0, 1); got {tolerance!r}")
    u = ca.SX.sym("u", len(moved) + len(spans))
    r = ca.SX.sym("r")
    x = ca.SX(ca.DM(centre))
    for j, k in enumerate(moved):
        x[k] = centre[k] + r * u[j]
    at = _spanned(mech, d, spans, u[len(moved):]) if spans else d

    def domain_at(trial: float) -> _Domain:
        return _domain(mech, ca.substitute(x, r, trial), u, list(range(len(moved))), bounds=bounds, mode=mode,
                       design=at)

    start = time.perf_counter()
    low, high, witness, steps = 0.0, radius, None, []
    while high - low > tolerance * high:
        trial = high if not steps else (low + high) / 2
        found = search(mech, domain_at(trial), depth=depth, max_boxes=max_boxes, seconds=seconds)
        steps.append({"radius": trial, **{k: found[k] for k in ("verdict", "boxes", "undecided", "seconds")}})
        if found["verdict"] == "proved":
            low = trial
            if trial == high:
                break
        elif found["verdict"] == "refuted":
            witness = found["witnesses"][0]
            high = witness["distance"] = trial * float(np.linalg.norm(witness["u"][: len(moved)]))
        else:
            high = trial
    clear, probe, step = high, high, tolerance * high
    while witness is None or witness["distance"] > probe:
        rim = _beyond(mech, domain_at(probe), len(moved), len(spans))
        if rim is not None:
            witness = {**rim, "distance": probe}
            break
        if witness is None and probe >= radius:
            break
        clear, probe, step = probe, probe + step, 2 * step
    while witness is not None and witness["distance"] - clear > tolerance * clear:
        probe = (clear + witness["distance"]) / 2
        rim = _beyond(mech, domain_at(probe), len(moved), len(spans))
        if rim is None:
            clear = probe
        else:
            witness = {**rim, "distance": probe}
    return LargestRegion(mech.name, dict(zip(mech.pose_names, centre.tolist(), strict=True)), bounds, low, high,
                         witness, steps, time.perf_counter() - start)


def _proved(domain: _Domain, lo: np.ndarray, hi: np.ndarray) -> bool:
    held = not domain.indices or bool(np.all(_lower(domain.value, domain.slope, lo, hi) >= domain.limits))
    return held and (domain.capsules is None or domain.capsules.lower(lo, hi) >= 0)


def _refuted(domain: _Domain, u: np.ndarray) -> bool:
    """Whether a property fails at u, its value enclosed there below its threshold."""
    if domain.indices:
        at = np.array([v.upper() for v in domain.value([[ball(c, c) for c in u]])[0]], dtype=float)
        if np.any(at < domain.limits):
            return True
    return domain.capsules is not None and domain.capsules.upper(u) < 0


def _witness(mech: Any, domain: _Domain, u: np.ndarray) -> dict[str, Any]:
    x = np.asarray(domain.pose(u), dtype=float).ravel()
    out = {"pose": dict(zip(mech.pose_names, x.tolist(), strict=True)), "u": u.tolist(),
           **({"design": mech.design_dict(np.asarray(domain.design(u), dtype=float).ravel())}
              if domain.design is not None else {}),
           **{i: float(v) for i, v in zip(domain.indices, np.asarray(domain.g(u)).ravel(), strict=True)}}
    if domain.capsules is not None:
        out["collision_margin"] = domain.capsules.upper(u)
    return out


BEYOND_SAMPLES = 4096  # directions on the sphere searched for a witness at the radius beyond the proved one


def _beyond(mech: Any, domain: _Domain, dim: int, spanned: int = 0) -> dict[str, Any] | None:
    """A pose on the rim (|u| = 1 in its ``dim`` position coordinates) where a property fails, its value enclosed
    at that point below the threshold, at designs of the box of the ``spanned`` parameters (half the samples at
    its corners, where a property is likeliest to fail first, half within it): the witness just beyond a proved
    radius; None where the sampled directions find none."""
    rng = np.random.default_rng(0)
    directions = rng.normal(size=(BEYOND_SAMPLES, dim))
    directions /= np.linalg.norm(directions, axis=1, keepdims=True)
    corners = rng.choice([-1.0, 1.0], size=(BEYOND_SAMPLES // 2, spanned))
    designs = np.concatenate([corners, rng.uniform(-1, 1, (BEYOND_SAMPLES - len(corners), spanned))])
    directions = np.concatenate([directions, designs], axis=1)
    short = np.full(BEYOND_SAMPLES, np.inf)
    if domain.indices:
        values = np.asarray(domain.g.map(BEYOND_SAMPLES)(directions.T), dtype=float).T
        short = np.min(values - domain.limits, axis=1)
    if domain.capsules is not None:
        short = np.fmin(short, np.asarray(domain.capsules.margin.map(BEYOND_SAMPLES)(directions.T)).ravel())
    for k in np.argsort(short)[: int(np.sum(short < 0))]:
        if _refuted(domain, directions[k]):
            return _witness(mech, domain, directions[k])
    return None


def _lower(value: Any, slope: Any, lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
    """The least value of each property's enclosure over the box: the greater of the natural enclosure's and
    the mean-value form's lower ends (-inf where neither is finite)."""
    box = [ball(a, b) for a, b in zip(lo, hi, strict=True)]
    natural = value([box])[0]
    centre = (lo + hi) / 2
    at = value([[ball(c, c) for c in centre]])[0]
    grad = slope([box])[0]
    n = len(at)
    out = np.full(n, -math.inf)
    for i in range(n):
        form = at[i]
        for j in range(len(lo)):
            form = form + grad[j * n + i] * ball(lo[j] - centre[j], hi[j] - centre[j])
        ends = [float(e.lower()) for e in (natural[i], form) if e.is_finite()]
        out[i] = max(ends) if ends else -math.inf
    return out


def _outside(lo: np.ndarray, hi: np.ndarray, axes: list[int]) -> bool:
    """Whether the box lies entirely beyond the unit disc of the round coordinates."""
    if not axes:
        return False
    nearest = sum(max(0.0, lo[k], -hi[k]) ** 2 for k in axes)
    return nearest > 1.0


def _inside(u: np.ndarray, axes: list[int]) -> bool:
    return sum(u[k] ** 2 for k in axes) <= 1.0
