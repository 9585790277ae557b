"""The collision margins of a described machine whose legs state their capsules (:data:`pkm.spec.vocabulary`'s
``capsule``): each leg's links as capsules, the segments of its drawing from joint to joint with the leg's radius,
and for every pair of segments of two legs the distance between them less their two radii (negative where they
overlap), composed in CasADi from the derived drawing (``skeleton``) and radii (``capsules``). Two segments
that meet at a joint the legs share by their description (one base attachment, one platform attachment) are
not a pair."""

from __future__ import annotations

from collections.abc import Mapping

import casadi as ca

from pkm.spec.schema import Description
from pkm.spec.vocabulary import kind_of

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
    """The pairs of segments (leg i, segment a, leg j, segment b), i < j, that may collide."""
    legs = description.data["legs"]
    counts = [kind_of(leg).points - 1 for leg in legs]
    out = []
    for i in range(len(legs)):
        for j in range(i + 1, len(legs)):
            for a in range(counts[i]):
                for b in range(counts[j]):
                    shared_base = a == 0 and b == 0 and legs[i]["base"] == legs[j]["base"]
                    shared_end = (a == counts[i] - 1 and b == counts[j] - 1
                                  and legs[i]["platform"] == legs[j]["platform"])
                    if not (shared_base or shared_end):
                        out.append((i, a, j, b))
    return out


def composed_collisions(description: Description, functions: Mapping[str, ca.Function]) -> ca.Function:
    """``collision(q, x, design) -> margins``: each pair's distance less its radii [m] (:func:`pairs`)."""
    skeleton, capsules = functions["skeleton"], functions["capsules"]
    q, x, d = (ca.SX.sym(skeleton.name_in(i), skeleton.size_in(i)) for i in range(3))
    points = skeleton(q, x, d)
    radii = capsules(d)
    counts = [kind_of(leg).points for leg in description.data["legs"]]
    first = [sum(counts[:k]) for k in range(len(counts))]
    margins = [segment_distance(points[first[i] + a, :].T, points[first[i] + a + 1, :].T,
                                points[first[j] + b, :].T, points[first[j] + b + 1, :].T) - radii[i] - radii[j]
               for i, a, j, b in pairs(description)]
    return ca.Function("collision", [q, x, d], [ca.vertcat(*margins) if margins else ca.SX(0, 1)],
                       ["q", "x", "design"], ["margins"])
