"""The collision margins of a described machine whose legs state their capsules (:data:`pkm.spec.vocabulary`'s
``capsule``): each leg's links as capsules, the segments of its drawing from joint to joint with the leg's radius,
and for every pair of segments of two legs the distance between them less their two radii (negative where they
overlap), composed in CasADi from the derived drawing (``skeleton``) and radii (``capsules``). Two segments
that meet at a joint the legs share by their description (one base attachment, one platform attachment), or that
the legs build in different layers (their ``layers``: a planar machine's links one above another), are not a
pair.

Where the description states ``plates``, the platform and the base are plates too: a convex polygon, the plate's
own points placed by the pose or else the legs' attachments to it (their joints in the drawing), in the angular
order of the points about their centre at the default design (one vertex per distinct point), rounded by the
plate's radius. Each segment
of a leg but the one at the plate's own joint (a leg's last at the platform, its first at the base) is a pair
with it: the least distance between the segment and the polygon (0 where they meet: an end inside it in the
plane, the segment through it in space; else the least over the polygon's edges and, in space, over the
segment's ends above it) less the two radii."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import casadi as ca
import numpy as np

from pkm import expressions
from pkm.spec.checks import plate_corners, plate_order
from pkm.spec.schema import Description
from pkm.spec.vocabulary import PLATES, kind_of

DEGENERATE = 1e-18  # [m^2] a segment this short is a point


def segment_distance(p1: ca.SX, q1: ca.SX, p2: ca.SX, q2: ca.SX) -> ca.SX:
    """The least distance between the segments p1 q1 and p2 q2 (Ericson, Real-Time Collision Detection, 5.1.9:
    the closest points' parameters clamped to the segments, a point-like segment its point)."""
    d1, d2, r = q1 - p1, q2 - p2, p1 - p2
    a, e, f = ca.dot(d1, d1), ca.dot(d2, d2), ca.dot(d2, r)
    c, b = ca.dot(d1, r), ca.dot(d1, d2)
    denominator = a * e - b * b

    def clamp(v: ca.SX) -> ca.SX:
        return ca.fmin(ca.fmax(v, 0), 1)

    s = ca.if_else(denominator > DEGENERATE * (a * e + DEGENERATE), clamp((b * f - c * e) / denominator),
                   ca.if_else(e > DEGENERATE, 0, ca.if_else(a > DEGENERATE, clamp(-c / a), 0)))
    t = ca.if_else(e > DEGENERATE, (b * s + f) / e, 0)
    s = ca.if_else(t < 0, ca.if_else(a > DEGENERATE, clamp(-c / a), 0),
                   ca.if_else(t > 1, ca.if_else(a > DEGENERATE, clamp((b - c) / a), 0), s))
    t = clamp(t)
    return ca.norm_2(p1 + d1 * s - p2 - d2 * t)


def pairs(description: Description) -> list[tuple[int, int, int, int]]:
    """The pairs of segments (leg i, segment a, leg j, segment b), i < j, that may collide: in one layer (the legs'
    ``layers``, all 0 by default), not meeting at a joint the two legs share."""
    legs = description.data["legs"]
    counts = [kind_of(leg).points - 1 for leg in legs]
    layers = [leg.get("layers", [0] * n) for leg, n in zip(legs, counts, strict=True)]
    out = []
    for i in range(len(legs)):
        for j in range(i + 1, len(legs)):
            for a in range(counts[i]):
                for b in range(counts[j]):
                    shared_base = a == 0 and b == 0 and legs[i]["base"] == legs[j]["base"]
                    shared_end = (a == counts[i] - 1 and b == counts[j] - 1
                                  and legs[i]["platform"] == legs[j]["platform"])
                    if not (shared_base or shared_end) and layers[i][a] == layers[j][b]:
                        out.append((i, a, j, b))
    return out


def plate_pairs(description: Description) -> list[tuple[int, int, str]]:
    """The pairs (leg i, segment a, plate) of a leg's segment and a plate that may collide: every segment but the
    one at the plate's own joint."""
    legs, plates = description.data["legs"], description.data.get("plates", {})
    counts = [kind_of(leg).points - 1 for leg in legs]
    return [(i, a, plate) for plate in PLATES if plate in plates for i in range(len(legs)) for a in range(counts[i])
            if a != (counts[i] - 1 if plate == "platform" else 0)]


def plate_vertices(description: Description, plate: str) -> list[int]:
    """The plate's vertices in order (:func:`pkm.spec.checks.plate_order` at the default design): indices of its own
    points where it states them, else of the legs whose attachments are its vertices."""
    design = {p["name"]: p["default"] for p in description.data["parameters"]}
    return plate_order(np.array([[float(expressions.evaluate(t, design)) for t in point[:2]]
                                 for point in plate_corners(description.data, plate)]))


def plate_polygon(description: Description, functions: Mapping[str, ca.Function], plate: str, *, points: ca.SX,
                  x: ca.SX, d: Any) -> list[ca.SX]:
    """The plate's vertices in order (:func:`plate_vertices`), each a column in the base frame: its own points
    placed by the pose (the derived ``plate_<name>(x, design)``), or the legs' joints at it in the drawing
    (``points``, the skeleton's rows: each leg's last joint for the platform, its first for the base)."""
    order = plate_vertices(description, plate)
    if "points" in description.data["plates"][plate]:
        placed = functions[f"plate_{plate}"](x, d)
        return [placed[k, :].T for k in order]
    counts = [kind_of(leg).points for leg in description.data["legs"]]
    return [points[sum(counts[:i]) + (counts[i] - 1 if plate == "platform" else 0), :].T for i in order]


def plate_radii(description: Description, d: Any) -> dict[str, Any]:
    """Each stated plate's radius, an expression of the design vector ``d`` (symbols or numbers)."""
    symbols = {p["name"]: d[k] for k, p in enumerate(description.data["parameters"])}
    return {plate: expressions.evaluate(table["radius"], symbols, expressions.CASADI)
            for plate, table in description.data.get("plates", {}).items()}


def _cross2(u: ca.SX, v: ca.SX) -> ca.SX:
    return u[0] * v[1] - u[1] * v[0]


def polygon_distance(p: ca.SX, q: ca.SX, vertices: list[ca.SX]) -> ca.SX:
    """The least distance between the segment p q and the convex polygon of ``vertices`` (in order; a segment for
    two, a point for one), in the plane or in space (module docstring); NaN where a point is not finite (a leg
    that does not reach), as a pair of segments' distance is."""
    return ca.if_else(ca.sumsqr(ca.vertcat(p, q, *vertices)) < np.inf, _polygon_distance(p, q, vertices), np.nan)


def _polygon_distance(p: ca.SX, q: ca.SX, vertices: list[ca.SX]) -> ca.SX:
    m = len(vertices)
    edges = [segment_distance(p, q, vertices[k], vertices[(k + 1) % m]) for k in range(m if m > 2 else 1)]
    best = ca.mmin(ca.vertcat(*edges))
    if m < 3:
        return best
    if p.numel() == 2:  # the vertices turn anticlockwise (:func:`plate_vertices`; a rigid motion keeps that)

        def inside(e: ca.SX) -> ca.SX:
            return ca.mmin(ca.vertcat(*[_cross2(vertices[(k + 1) % m] - vertices[k], e - vertices[k])
                                        for k in range(m)])) >= 0

        return ca.if_else(ca.logic_or(inside(p), inside(q)), 0, best)
    normal = sum((ca.cross(vertices[k], vertices[(k + 1) % m]) for k in range(1, m)),
                 ca.cross(vertices[0], vertices[1 % m]))  # Newell's normal
    n = normal / ca.norm_2(normal)

    def above(e: ca.SX) -> ca.SX:
        return ca.mmin(ca.vertcat(*[ca.dot(ca.cross(vertices[(k + 1) % m] - vertices[k], e - vertices[k]), n)
                                    for k in range(m)])) >= 0

    sp, sq = ca.dot(n, p - vertices[0]), ca.dot(n, q - vertices[0])
    through = p + (q - p) * sp / ca.if_else(sp == sq, 1, sp - sq)
    faces = [ca.if_else(above(p), ca.fabs(sp), best), ca.if_else(above(q), ca.fabs(sq), best),
             ca.if_else(ca.logic_and(sp * sq <= 0, above(through)), 0, best)]
    return ca.mmin(ca.vertcat(best, *faces))


def composed_collisions(description: Description, functions: Mapping[str, ca.Function]) -> ca.Function:
    """``collision(q, x, design) -> margins``: each pair's distance less its radii [m] (:func:`pairs`), then each
    pair of a segment and a plate (:func:`plate_pairs`)."""
    skeleton, capsules = functions["skeleton"], functions["capsules"]
    q, x, d = (ca.SX.sym(skeleton.name_in(i), skeleton.size_in(i)) for i in range(3))
    points = skeleton(q, x, d)
    radii = capsules(d)
    counts = [kind_of(leg).points for leg in description.data["legs"]]
    first = [sum(counts[:k]) for k in range(len(counts))]
    margins = [segment_distance(points[first[i] + a, :].T, points[first[i] + a + 1, :].T,
                                points[first[j] + b, :].T, points[first[j] + b + 1, :].T) - radii[i] - radii[j]
               for i, a, j, b in pairs(description)]
    plates = plate_radii(description, d)
    polygons = {plate: plate_polygon(description, functions, plate, points=points, x=x, d=d) for plate in plates}
    margins += [polygon_distance(points[first[i] + a, :].T, points[first[i] + a + 1, :].T, polygons[plate])
                - radii[i] - plates[plate] for i, a, plate in plate_pairs(description)]
    return ca.Function("collision", [q, x, d], [ca.vertcat(*margins) if margins else ca.SX(0, 1)],
                       ["q", "x", "design"], ["margins"])
