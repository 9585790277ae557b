"""Certified regions (issue 41): ball-arithmetic enclosures of pkm's graphs hold every value they enclose; a
region is proved where no sampled pose of it violates the property, refuted by a witness that violates it (by
pkm's own local indices, apart from the certification), and the largest certified disc or ball lies below a
witness just beyond it."""

from __future__ import annotations

import json
import re
import tomllib
import warnings
from pathlib import Path
from typing import Any

import casadi as ca
import numpy as np
import pytest
from helpers import FIVE_BAR_OF_RR_LEGS, rpr3_text

import pkm
from pkm import regions
from pkm.cli import main
from pkm.errors import PkmError, SingularityWarning
from pkm.intervals import ball, enclosure
from pkm.models.described import DESCRIPTIONS
from pkm.spec.schema import DescriptionError


def test_the_enclosure_of_a_graph_holds_its_values_over_the_box():
    """A graph of every kind of operation the kinematics use (atan2, acos, sqrt, a choice, a minimum): at 10,000
    random points of each of three random boxes each value lies within its enclosure."""
    x = ca.SX.sym("x", 2)
    f = ca.Function("f", [x], [ca.vertcat(
        ca.sin(x[0]) * x[1] + ca.sqrt(x[0]) + ca.atan2(x[1], x[0]) + ca.if_else(x[0] < 0.5, x[1] ** 2, -x[1]),
        ca.acos(x[0] / 2) + ca.fmin(x[0], x[1]) - ca.fabs(x[1]) ** 3 / (1 + x[0] ** 2))])
    enclose = enclosure(f)
    rng = np.random.default_rng(1)
    for _ in range(3):
        lo = rng.uniform(0.1, 0.8, 2)
        hi = lo + rng.uniform(0.01, 0.5, 2)
        (out,) = enclose([[ball(a, b) for a, b in zip(lo, hi, strict=True)]])
        points = rng.uniform(lo, hi, (10_000, 2))
        values = np.asarray(f.map(len(points))(points.T)).T
        for k, v in enumerate(out):
            assert float(v.lower()) <= values[:, k].min()
            assert values[:, k].max() <= float(v.upper())


def test_the_enclosure_of_a_mechanisms_inverse_kinematics_holds_its_values():
    """The 3-RRR's inverse kinematics over a box of poses: at 10,000 random points of it each joint lies within its
    enclosure."""
    m = pkm.load("rrr3")
    x = ca.SX.sym("x", 3)
    q, _ = m.functions["inverse_kinematics"](x, ca.DM(m.working_mode(None).signs), ca.DM(m.design_vector(None)))
    f = ca.Function("ik", [x], [q])
    lo, hi = np.array([0.02, -0.03, 0.1]), np.array([0.05, 0.0, 0.12])
    (out,) = enclosure(f)([[ball(a, b) for a, b in zip(lo, hi, strict=True)]])
    points = np.random.default_rng(2).uniform(lo, hi, (10_000, 3))
    values = np.asarray(f.map(len(points))(points.T)).T
    for k, v in enumerate(out):
        assert float(v.lower()) <= values[:, k].min() <= values[:, k].max() <= float(v.upper())


def _disc(centre, radius):
    return regions.Disc("probe", "a disc", fixed=(tuple(centre), (radius,)))


def test_the_deltas_task_is_proved_within_its_limits_and_a_sampled_check_agrees():
    delta = pkm.load("delta")
    proved = delta.certify("task", properties=("limits",))
    assert (proved.verdict, proved.undecided, proved.witnesses) == ("proved", 0.0, [])
    assert proved.boxes >= 1
    rng = np.random.default_rng(3)
    radius, angle = 0.15 * np.sqrt(rng.uniform(size=2000)), rng.uniform(0, 2 * np.pi, 2000)
    poses = np.column_stack([radius * np.cos(angle), radius * np.sin(angle), rng.uniform(-0.55, -0.45, 2000)])
    assert delta.local_index("workspace_margin", poses).min() >= 0


def test_a_disc_of_the_five_bar_away_from_its_singularities_is_proved_and_one_across_its_rim_refuted():
    five_bar = pkm.load("five_bar")
    inside = five_bar.certify(_disc((0.0, 1.6), 0.1), properties=("singularity", "limits"))
    assert inside.verdict == "proved"
    across = five_bar.certify(_disc((0.0, 1.6), 0.8), properties=("limits",))
    assert across.verdict == "refuted"
    (witness,) = across.witnesses
    pose = np.array(list(witness["pose"].values()))
    assert np.hypot(pose[0], pose[1] - 1.6) <= 0.8
    assert five_bar.local_index("workspace_margin", pose) < 0


@pytest.fixture(scope="module")
def in_line(tmp_path_factory):
    path = tmp_path_factory.mktemp("rpr3") / "rpr3.toml"
    path.write_text(rpr3_text("rpr3_in_line", R=1.0, r=0.4, stroke=(0.3, 1.5)))  # test_singularities' machine
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", SingularityWarning)
        return pkm.load(str(path))


def test_a_singular_plane_is_refuted_with_a_witness_on_it(in_line):
    """The in-line 3-RPR is type-II singular over phi = 0: a cylinder of platform angles across it is refuted,
    its witness singular by pkm's own margins."""
    region = regions.Cylinder("across", "across phi = 0", fixed=((0.0, 0.0, 0.0), (0.05, 0.2)), axis=2)
    found = in_line.certify(region, properties=("singularity",), threshold=1e-3)
    assert found.verdict == "refuted"
    pose = np.array(list(found.witnesses[0]["pose"].values()))
    assert in_line.local_index("singularity_margin", pose) < 1e-3


def test_the_largest_certified_ball_of_the_delta_lies_below_a_witness_beyond_it():
    delta = pkm.load("delta")
    found = delta.largest_region([0, 0, -0.5], radius=0.4, properties=("limits",), tolerance=3e-2, depth=10)
    assert 0 < found.proved <= found.beyond <= found.witness["distance"] <= 0.4
    witness = np.array(list(found.witness["pose"].values()))
    assert np.linalg.norm(witness - [0, 0, -0.5]) == pytest.approx(found.witness["distance"], rel=1e-9)
    assert delta.local_index("workspace_margin", witness) < 0
    rng = np.random.default_rng(5)
    directions = rng.normal(size=(3000, 3))
    directions /= np.linalg.norm(directions, axis=1, keepdims=True)
    inside = [0, 0, -0.5] + found.proved * rng.uniform(size=(3000, 1)) ** (1 / 3) * directions
    assert delta.local_index("workspace_margin", inside).min() >= 0


def test_pkm_certify_prints_the_verdict_and_refuses_bad_input(capsys):
    assert main(["certify", "delta", "--properties", "limits", "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert (data["verdict"], data["region"], data["properties"]) == ("proved", "task", {"limits": 0.0})
    assert main(["certify", "delta", "--properties", "colour"]) == 2
    assert "properties violates: some of singularity, limits, collisions; got colour" in capsys.readouterr().err
    assert main(["certify", "delta", "--threshold", "2"]) == 2
    assert "threshold violates" in capsys.readouterr().err
    assert main(["certify", "delta", "--properties", "limits", "--designs", "L_b=0.58:0.62"]) == 0
    assert "over task, L_b in [0.58, 0.62] in mode elbow_out: PROVED" in capsys.readouterr().out
    assert main(["certify", "delta", "--designs", "L_b=0.58"]) == 2
    assert "--designs violates: comma-separated name=lower:upper" in capsys.readouterr().err
    with pytest.raises(PkmError, match="radius violates"):
        pkm.load("delta").largest_region([0, 0, -0.5], radius=0)


def _segment_gap(p1, q1, p2, q2, samples=401):
    """The least distance between two segments by dense sampling of both."""
    s = np.linspace(0, 1, samples)[:, None]
    a, b = p1 + s * (q1 - p1), p2 + s * (q2 - p2)
    gaps = a[:, None] - b[None]
    return float(np.sqrt(np.min(np.einsum("ijk,ijk->ij", gaps, gaps))))


def test_the_segment_distance_is_the_least_over_both_segments():
    from pkm.spec.collisions import segment_distance

    p1, q1, p2, q2 = (ca.SX.sym(n, 3) for n in ("p1", "q1", "p2", "q2"))
    f = ca.Function("d", [p1, q1, p2, q2], [segment_distance(p1, q1, p2, q2)])
    rng = np.random.default_rng(6)
    for _ in range(40):
        ends = rng.normal(size=(4, 3))
        if rng.uniform() < 0.3:
            ends[3] = ends[2] + 0.3 * (ends[1] - ends[0])  # parallel
        distance, gap = float(f(*ends)), _segment_gap(*ends)
        assert distance == pytest.approx(gap, abs=2e-3)
        assert distance <= gap + 1e-12


@pytest.fixture(scope="module")
def capsules():
    from helpers import FIVE_BAR_ELASTIC

    return pkm.load(FIVE_BAR_ELASTIC)


def test_the_collision_margin_is_the_least_gap_between_two_legs_links_less_their_radii(capsules):
    """From the drawn linkage: the proximal links against each other and each against the other leg's distal
    one (the distal links share the platform joint: not a pair), less twice the radius; negative in the mode
    whose elbows cross."""
    rng = np.random.default_rng(7)
    poses = np.column_stack([rng.uniform(-0.4, 0.4, 10), rng.uniform(0.6, 1.9, 10)])
    checked = 0
    for mode in capsules.modes:
        for pose in poses:
            legs = capsules.linkage(pose, mode=mode)
            if not legs or not np.all(np.isfinite(legs[0])):
                continue
            (a0, a1, a2), (b0, b1, b2) = legs
            gap = min(_segment_gap(a0, a1, b0, b1), _segment_gap(a0, a1, b1, b2), _segment_gap(a1, a2, b0, b1))
            assert capsules.local_index("collision_margin", pose, mode=mode) == pytest.approx(gap - 0.1, abs=5e-3)
            checked += 1
    assert checked >= 20
    assert capsules.global_index("collision_margin_min", None, region=_disc((0.0, 1.6), 0.2), mode="out_out") > 0


def test_collisions_are_certified_absent_in_one_mode_and_refuted_in_the_crossed_one(capsules):
    region = _disc((0.0, 1.6), 0.2)
    assert capsules.certify(region, properties=("collisions",), mode="out_out").verdict == "proved"
    crossed = capsules.certify(region, properties=("collisions",), mode="in_in")
    assert crossed.verdict == "refuted"
    pose = np.array(list(crossed.witnesses[0]["pose"].values()))
    assert capsules.local_index("collision_margin", pose, mode="in_in") < 0
    with pytest.raises(PkmError, match="collisions of a described machine whose legs state their capsules"):
        pkm.load("five_bar").certify("miw", properties=("collisions",))


def test_a_synthesis_ends_with_its_optimum_certified_when_asked(capsys):
    """pkm design --certify: the deflection-constrained Delta's optimum proved over its task free of a
    singularity margin below the problem's and within its limits, in the text and the JSON."""
    task = Path(__file__).resolve().parents[1] / "docs" / "tasks" / "delta_stiff.toml"
    assert main(["design", str(task), "--resolution", "4", "--starts", "1", "--certify", "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    certified = data["certified"]
    assert (certified["verdict"], certified["region"], certified["properties"]) == (
        "proved", "task", {"singularity": 0.01, "limits": 0.0})
    assert certified["design"]["L_a"] == pytest.approx(data["optimum"]["design"]["L_a"])


def test_signs_truths_and_copysigns_over_a_box_are_every_value_they_take():
    """Over [-1, 1] the derivative of |x| (CasADi's sign) takes -1 and 1, a choice on a nonzero value and a logic
    of values other than 0 and 1 are CasADi's, and copysign takes both signs."""
    x = ca.SX.sym("x", 2)
    box, point = [ball(-1.0, 1.0), ball(5.0, 5.0)], [ball(-1.0, -1.0), ball(5.0, 5.0)]
    for expression, at_point in ((ca.densify(ca.jacobian(ca.fabs(x[0]), x))[0], -1.0),
                                 (ca.if_else(x[0], x[1], 0), 5.0),
                                 (ca.if_else(ca.logic_and(x[0], 1), x[1], 7), 5.0),
                                 (ca.copysign(3, x[0]), -3.0)):
        f = ca.Function("f", [x], [expression])
        (over,) = enclosure(f)([box])[0]
        (here,) = enclosure(f)([point])[0]
        assert float(here.lower()) <= at_point <= float(here.upper())
        values = [float(f([u, 5.0])) for u in np.linspace(-1, 1, 101)]
        assert float(over.lower()) <= min(values)
        assert max(values) <= float(over.upper())


def test_a_property_that_fails_inside_a_box_is_never_proved_by_its_mean_value_form():
    """g(u) = |u0 - 0.1| (1 + u1^2) >= 1e-6 fails at u0 = 0.1: the search must not prove it (the derivative of
    |.| enclosed as 0 across the kink once did)."""
    from pkm.certify import _Domain, search

    u = ca.SX.sym("u", 2)
    g = ca.Function("g", [u], [ca.fabs(u[0] - 0.1) * (1 + u[1] ** 2)])
    gradient = ca.Function("dg", [u], [ca.densify(ca.jacobian(g(u), u))])
    domain = _Domain(enclosure(g), enclosure(gradient), g, ca.Function("x", [u], [u]), ["g"], [],
                     np.array([1e-6]))
    found = search(pkm.load("five_bar"), domain, depth=12, max_boxes=3000, seconds=20)
    assert found["verdict"] != "proved"


def test_a_disc_is_proved_for_every_design_of_a_box_and_refuted_with_the_design_that_fails():
    """The five-bar's disc of radius 0.1 about (0, 1.6) for every r2 within 2 % and r3 within 5 % of the defaults:
    proved, and 20 designs drawn in the box agree at 200 poses of the disc; the disc of radius 0.4, proved at the
    default design, refuted for r2 in [0.9, 1.0] with a witness whose design lies in that interval and whose
    workspace margin at that design is negative."""
    five_bar = pkm.load("five_bar")
    spans = {"r2": (0.98, 1.02), "r3": (0.76, 0.84)}
    proved = five_bar.certify(_disc((0.0, 1.6), 0.1), properties=("singularity", "limits"), designs=spans)
    assert proved.verdict == "proved"
    assert proved.designs == {name: list(span) for name, span in spans.items()}
    rng = np.random.default_rng(6)
    radius, angle = 0.1 * np.sqrt(rng.uniform(size=200)), rng.uniform(0, 2 * np.pi, 200)
    poses = np.column_stack([radius * np.cos(angle), 1.6 + radius * np.sin(angle)])
    for _ in range(20):
        design = {**dict(five_bar.design()), **{name: rng.uniform(*span) for name, span in spans.items()}}
        assert np.all(five_bar.local_index("workspace_margin", poses, design) >= 0)
        assert np.all(five_bar.local_index("singularity_margin", poses, design) >= 1e-6)
    assert five_bar.certify(_disc((0.0, 1.6), 0.4), properties=("limits",)).verdict == "proved"
    refuted = five_bar.certify(_disc((0.0, 1.6), 0.4), properties=("limits",), designs={"r2": (0.9, 1.0)})
    assert refuted.verdict == "refuted"
    (witness,) = refuted.witnesses
    assert 0.9 <= witness["design"]["r2"] <= 1.0
    pose = np.array(list(witness["pose"].values()))
    assert five_bar.local_index("workspace_margin", pose, witness["design"]) < 0


@pytest.mark.parametrize(("designs", "condition"), [
    ({"l9": (0.9, 1.0)}, "designs violates: parameters of five_bar"),
    ({"r2": (1.0, 0.9)}, "designs.r2 violates: finite, lower < upper"),
    ({"r2": "wide"}, "designs.r2 violates: [lower, upper], two numbers"),
])
def test_a_bad_design_box_is_refused_naming_it(designs, condition):
    with pytest.raises(PkmError, match=re.escape(condition)):
        pkm.load("five_bar").certify(_disc((0.0, 1.6), 0.1), designs=designs)


def _capsule(p: np.ndarray, q: np.ndarray, radius: float):
    """coal's capsule about the segment p q: its axis z turned onto q - p, its centre the segment's middle."""
    import coal

    d = q - p
    length = float(np.linalg.norm(d))
    z = d / length
    axis = np.cross([0.0, 0.0, 1.0], z)
    s, c = float(np.linalg.norm(axis)), float(z[2])
    if s < 1e-12:
        rotation = np.eye(3) if c > 0 else np.diag([1.0, -1.0, -1.0])
    else:
        k = axis / s
        cross = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
        rotation = np.eye(3) + s * cross + (1 - c) * cross @ cross
    return coal.Capsule(radius, length), coal.Transform3s(rotation, (p + q) / 2)


def test_the_deltas_capsules_are_coals_and_its_tasks_rim_is_certified_free_of_collisions():
    """The Delta with 15 mm capsules about its arms and rods: every pair's margin (the arms and the rods of two legs
    against each other) equals coal's capsule distance at 30 poses across and beyond its task, to 1e-12; a
    cylinder at the task's rim is proved free of collisions."""
    import coal

    from pkm.batch import evaluate
    from pkm.spec.collisions import pairs

    raw = tomllib.loads(DESCRIPTIONS["delta"].read_text())
    m = pkm.load({**raw, "name": "delta_capsules", "legs": {**raw["legs"], "capsule": "0.015"}})
    d = m.design_vector(None)
    radii = np.asarray(m.functions["capsules"](d)).ravel()
    rng = np.random.default_rng(3)
    radius, angle = 0.25 * np.sqrt(rng.uniform(size=30)), rng.uniform(0, 2 * np.pi, 30)
    checked = 0
    for x in np.column_stack([radius * np.cos(angle), radius * np.sin(angle), rng.uniform(-0.6, -0.4, 30)]):
        legs = m.linkage(x)
        if not legs or not all(np.all(np.isfinite(leg)) for leg in legs):
            continue
        (margins,) = evaluate(m.functions["collision"], m.inverse_kinematics(x, passive=True), x, d)
        for margin, (i, a, j, b) in zip(np.ravel(margins), pairs(m.description), strict=True):
            distance = coal.distance(*_capsule(legs[i][a], legs[i][a + 1], radii[i]),
                                     *_capsule(legs[j][b], legs[j][b + 1], radii[j]),
                                     coal.DistanceRequest(), coal.DistanceResult())
            assert margin == pytest.approx(distance, abs=1e-12)
            checked += 1
    assert checked >= 20 * 12
    rim = regions.Cylinder("rim", "the task's rim", fixed=((0.15, 0.0, -0.5), (0.03, 0.05)), axis=2)
    assert m.certify(rim, properties=("collisions",)).verdict == "proved"


def _plate(points: list[np.ndarray], radius: float) -> tuple[Any, Any]:
    """coal's convex plate of the polygon ``points`` (in order, in space), rounded by ``radius``."""
    import coal

    vertices, triangles = coal.StdVec_Vec3s(), coal.StdVec_Triangle()
    for p in points:
        vertices.append(np.asarray(p, dtype=float))
    for k in range(1, len(points) - 1):
        triangles.append(coal.Triangle(0, k, k + 1))
    plate = coal.Convex(vertices, triangles)
    plate.setSweptSphereRadius(radius)
    return plate, coal.Transform3s()


def _plate_margins_are_coals(m: pkm.Mechanism, poses: np.ndarray, radii: dict[str, float],
                             own: dict[str, Any] | None = None) -> int:
    """Each segment-plate pair's margin equals coal's distance between the segment's capsule and the plate (the
    legs' joints at it, or ``own[name](x)``, its own corners at the pose; in space: z = 0 in the plane), to 1e-9; the
    number of pairs checked."""
    import coal

    from pkm.batch import evaluate
    from pkm.spec.collisions import pairs, plate_pairs, plate_vertices

    d = m.design_vector(None)
    capsule = float(np.asarray(m.functions["capsules"](d)).ravel()[0])
    checked = 0
    for x in poses:
        legs = [np.pad(leg, ((0, 0), (0, 3 - leg.shape[1]))) for leg in m.linkage(x)]
        if not legs or not all(np.all(np.isfinite(leg)) for leg in legs):
            continue
        (margins,) = evaluate(m.functions["collision"], m.inverse_kinematics(x, passive=True), x, d)
        for margin, (i, a, name) in zip(np.ravel(margins)[len(pairs(m.description)):], plate_pairs(m.description),
                                        strict=True):
            corners = [np.pad(c, (0, 3 - len(c))) for c in own[name](x)] if own and name in own else \
                [legs[k][-1 if name == "platform" else 0] for k in plate_vertices(m.description, name)]
            distance = coal.distance(*_capsule(legs[i][a], legs[i][a + 1], capsule), *_plate(corners, radii[name]),
                                     coal.DistanceRequest(), coal.DistanceResult())
            assert margin == pytest.approx(distance, abs=1e-9)
            checked += 1
    return checked


def _delta_plates_are_coals_and_certified(m: pkm.Mechanism, rng: np.random.Generator, radii: dict[str, float],
                                          own: dict[str, Any] | None = None) -> None:
    """The Delta's plates against coal at 30 poses up to the top of its workspace; a cylinder in the middle of its
    task proved free of collisions, one near its top, where the rods reach the base plate, refuted with a witness
    whose margin is negative."""
    radius, angle = 0.15 * np.sqrt(rng.uniform(size=30)), rng.uniform(0, 2 * np.pi, 30)
    poses = np.column_stack([radius * np.cos(angle), radius * np.sin(angle), rng.uniform(-0.6, -0.32, 30)])
    assert _plate_margins_are_coals(m, poses, radii, own) >= 20 * 6
    middle = regions.Cylinder("middle", "the task's middle", fixed=((0.0, 0.0, -0.45), (0.03, 0.03)), axis=2)
    assert m.certify(middle, properties=("collisions",)).verdict == "proved"
    top = m.certify(regions.Cylinder("top", "near the top", fixed=((0.0, 0.0, -0.325), (0.005, 0.005)), axis=2),
                    properties=("collisions",))
    assert top.verdict == "refuted"
    assert top.witnesses[0]["collision_margin"] < 0


def test_the_platform_and_the_base_are_coals_convex_plates_and_certified_free_of_them_or_not():
    """The Delta with 15 mm capsules and plates (the platform's joints' triangle rounded by 0.1 m, the base's by
    0.05 m): each arm's margin to the platform and each rod's to the base equal coal's capsule-to-convex distances
    at 30 poses up to the top of the workspace, to 1e-9; a cylinder in the middle of the task is proved free of
    collisions, one near the top, where the rods reach the base plate, refuted with a witness whose margin is
    negative. The 3-RRR's proximal links against its platform's triangle: coal's distances in the plane."""
    raw = tomllib.loads(DESCRIPTIONS["delta"].read_text())
    radii = {"platform": 0.1, "base": 0.05}
    m = pkm.load({**raw, "name": "delta_plates", "legs": {**raw["legs"], "capsule": "0.015"},
                  "plates": {k: str(v) for k, v in radii.items()}})
    rng = np.random.default_rng(7)
    _delta_plates_are_coals_and_certified(m, rng, radii)
    for plates, field in (({"platform": "0"}, "plates.platform violates: a positive radius"),
                          ({"table": "0.1"}, "plates violates: a table of platform and/or base plates")):
        with pytest.raises(DescriptionError, match=re.escape(field)):
            pkm.load({**raw, "name": "delta_bad_plates", "legs": {**raw["legs"], "capsule": "0.015"}, "plates": plates})
    with pytest.raises(DescriptionError, match="plates violates: the legs' capsules"):
        pkm.load({**raw, "name": "delta_bad_plates", "plates": {"base": "0.1"}})
    stewart = tomllib.loads(DESCRIPTIONS["stewart"].read_text())
    corners = [[float(np.cos(a)), float(np.sin(a)), 0.05 if k == 5 else 0.0]
               for k, a in enumerate(np.linspace(0, 2 * np.pi, 6, endpoint=False))]
    tilted = {**stewart["legs"], "capsule": "0.015", "base": corners}
    with pytest.raises(DescriptionError, match=re.escape("plates.base violates: the legs' base attachments in one "
                                                         "plane")):
        pkm.load({**stewart, "name": "stewart_bad_plates", "legs": tilted, "plates": {"base": "0.1"}})
    planar = tomllib.loads(DESCRIPTIONS["rrr3"].read_text())
    rrr3 = pkm.load({**planar, "name": "rrr3_plate", "legs": {**planar["legs"], "capsule": "0.02"},
                     "plates": {"platform": "0.01"}})
    poses = np.column_stack([rng.uniform(-0.15, 0.15, (30, 2)), rng.uniform(-0.3, 0.3, 30)])
    assert _plate_margins_are_coals(rrr3, poses, {"platform": 0.01}) >= 20 * 3


def test_a_plate_of_its_own_points_is_coals_convex_plate_and_certified():
    """Plates of their own shape: the 3-RRR's platform a square of 0.08 m turned with the platform (its corners
    given crosswise) and its base a disc of 0.05 m about (0, -0.3) (one point rounded), the Delta's platform a
    hexagon of 0.06 m rounded by 0.01 m and its base one of 0.2 m rounded by 0.05 m: each segment's margin to them
    equals coal's capsule-to-convex distance at 30 poses, to 1e-9, the plate's corners placed here from the pose;
    the Delta's plates certified free of its legs in the middle of its task and refuted, with a witness, near its
    top, where the rods reach the base's hexagon. A polygon that is not convex, points out of one plane and an empty
    list are refused, naming the plate; points on one line are a bar, the polygon's straight corners dropped."""
    rng = np.random.default_rng(11)
    planar = tomllib.loads(DESCRIPTIONS["rrr3"].read_text())
    square = [[0.04, 0.04], [-0.04, 0.04], [-0.04, -0.04], [0.04, -0.04]]
    crosswise = [square[k] for k in (0, 2, 1, 3)]  # pkm takes the points in their angular order
    rrr3 = pkm.load({**planar, "name": "rrr3_own_plates", "legs": {**planar["legs"], "capsule": "0.02"},
                     "plates": {"platform": {"radius": "0.005", "points": crosswise},
                                "base": {"radius": "0.05", "points": [[0, -0.3]]}}})

    def turned(x: np.ndarray) -> list[np.ndarray]:
        c, s = np.cos(x[2]), np.sin(x[2])
        return [x[:2] + np.array([[c, -s], [s, c]]) @ p for p in np.array(square)]

    poses = np.column_stack([rng.uniform(-0.15, 0.15, (30, 2)), rng.uniform(-0.3, 0.3, 30)])
    assert _plate_margins_are_coals(rrr3, poses, {"platform": 0.005, "base": 0.05},
                                    {"platform": turned, "base": lambda _: [np.array([0.0, -0.3])]}) >= 20 * 5
    raw = tomllib.loads(DESCRIPTIONS["delta"].read_text())
    hexagon = np.array([[np.cos(a), np.sin(a), 0] for a in np.linspace(0, 2 * np.pi, 6, endpoint=False)])
    plates = {"platform": {"radius": "0.01", "points": (0.06 * hexagon).tolist()},
              "base": {"radius": "0.05", "points": (0.2 * hexagon).tolist()}}
    m = pkm.load({**raw, "name": "delta_hexagons", "legs": {**raw["legs"], "capsule": "0.015"}, "plates": plates})
    own = {"platform": lambda x: list(x + 0.06 * hexagon), "base": lambda _: list(0.2 * hexagon)}
    _delta_plates_are_coals_and_certified(m, rng, {"platform": 0.01, "base": 0.05}, own)
    legs = {**planar["legs"], "capsule": "0.02"}
    for points, condition in (([[0.04, 0.04], [0, 0.01], [-0.04, 0.04], [0, -0.04]], "a convex polygon"),
                              ([], "a list of 1 to 64 points"), ([[0.04, 0.04, 0]], "a vector of 2 expressions")):
        with pytest.raises(DescriptionError, match=re.escape("plates.platform") + ".*" + re.escape(condition)):
            pkm.load({**planar, "name": "rrr3_bad_plate", "legs": legs,
                      "plates": {"platform": {"radius": "0.01", "points": points}}})
    with pytest.raises(DescriptionError, match=re.escape("plates.platform violates: the plate's points in one plane")):
        pkm.load({**raw, "name": "delta_bad_plate", "legs": {**raw["legs"], "capsule": "0.015"},
                  "plates": {"platform": {"radius": "0.01", "points": [[0.1, 0, 0], [0, 0.1, 0], [-0.1, 0, 0.02]]}}})
    from pkm.spec.checks import plate_order
    from pkm.spec.collisions import polygon_distance

    line = np.array([[0.0, 0.0], [1.0, 0.0], [2.0, 0.0], [1.5, 0.0]])
    bar = [ca.DM(line[k]) for k in plate_order(line)]
    assert len(bar) == 2
    assert float(polygon_distance(ca.DM([5.0, 0.0]), ca.DM([6.0, 0.0]), bar)) == pytest.approx(3.0)
    assert float(polygon_distance(ca.DM([1.0, -1.0]), ca.DM([1.0, 1.0]), bar)) == 0.0
    with pytest.raises(DescriptionError, match=re.escape("plates.platform.shape violates: a known field of a plate")):
        pkm.load({**planar, "name": "rrr3_bad_plate", "legs": legs, "plates": {"platform": {"radius": 1, "shape": 2}}})


def test_links_in_other_layers_pass_over_each_other():
    """The five-bar of RR legs with 3 cm capsules, each leg's proximal link in layer 0 and its distal link in layer
    1 (built one above the other): the proximal links are the one pair left, their margin the unlayered machine's;
    about a pose of the out_out mode where a distal link crosses the other leg's proximal link and the proximal links
    are 0.3 m apart, a disc is refuted with the links in one layer and proved with them in two. Layers are refused
    without a capsule and of the wrong length."""
    from pkm.batch import evaluate
    from pkm.spec.collisions import pairs

    flat = {**FIVE_BAR_OF_RR_LEGS, "name": "five_bar_capsules", "legs": {**FIVE_BAR_OF_RR_LEGS["legs"],
                                                                         "capsule": "0.03"}}
    one, two = pkm.load(flat), pkm.load({**flat, "name": "five_bar_layers", "legs": {**flat["legs"],
                                                                                       "layers": [0, 1]}})
    assert pairs(one.description) == [(0, 0, 1, 0), (0, 0, 1, 1), (0, 1, 1, 0)]
    assert pairs(two.description) == [(0, 0, 1, 0)]
    rng = np.random.default_rng(4)
    x = np.column_stack([rng.uniform(-1.5, 1.5, 40), rng.uniform(-0.3, 2.0, 40)])
    q = one.inverse_kinematics(x, mode="out_out", passive=True)
    x, q = x[np.all(np.isfinite(q), axis=1)], q[np.all(np.isfinite(q), axis=1)]
    d = one.design_vector(None)
    (flat_margins,), (layered,) = (evaluate(m.functions["collision"], q, x, d) for m in (one, two))
    np.testing.assert_allclose(np.reshape(layered, (len(x), -1))[:, 0], np.reshape(flat_margins, (len(x), -1))[:, 0],
                               rtol=0, atol=1e-15)
    crossing = _disc((1.014, -0.292), 0.01)
    refuted = one.certify(crossing, mode="out_out", properties=("collisions",))
    assert refuted.verdict == "refuted"
    assert refuted.witnesses[0]["collision_margin"] < 0
    assert two.certify(crossing, mode="out_out", properties=("collisions",)).verdict == "proved"
    for legs, condition in (({**FIVE_BAR_OF_RR_LEGS["legs"], "layers": [0, 1]}, "given with the leg's capsule"),
                            ({**flat["legs"], "layers": [0, 1, 1]}, "a list of 2 integers from 0 to 15"),
                            ({**flat["legs"], "layers": [0, True]}, "a list of 2 integers from 0 to 15")):
        with pytest.raises(DescriptionError, match=re.escape(f"legs.layers violates: {condition}")):
            pkm.load({**flat, "name": "five_bar_bad_layers", "legs": legs})


def test_the_2_ups_pus_legs_are_coals_capsules_and_their_margin_an_index_but_not_certified():
    """The hand-derived 2-UPS-PU's legs as capsules of its leg diameter D: its collision margins (the legs U1S1,
    U2S2 and OU0 pairwise) equal coal's capsule distances at 30 poses across its task, to 1e-12, and the collision
    margin is their least, a local index like any other; certifying collisions asks for a described machine."""
    import coal

    from pkm.batch import evaluate

    m = pkm.load("ups_pu")
    d = m.design_vector(None)
    radius = m.design(None)["D"] / 2
    rng = np.random.default_rng(6)
    poses = np.column_stack([rng.uniform(0.45, 0.6, 30), rng.uniform(-0.4, 0.4, 30), rng.uniform(-0.4, 0.4, 30)])
    (margins,) = evaluate(m.functions["collision"], m.inverse_kinematics(poses, limits=False), poses, d)
    (u0, s1, s2, u1, u2, _) = (p[..., 0] for p in evaluate(m.functions["joint_positions"], poses, d))
    legs = [(u1, s1), (u2, s2), (np.zeros_like(u0), u0)]
    for k in range(len(poses)):
        for margin, (i, j) in zip(margins[k, :, 0], ((0, 1), (0, 2), (1, 2)), strict=True):
            distance = coal.distance(*_capsule(legs[i][0][k], legs[i][1][k], radius),
                                     *_capsule(legs[j][0][k], legs[j][1][k], radius),
                                     coal.DistanceRequest(), coal.DistanceResult())
            assert margin == pytest.approx(distance, abs=1e-12)
    np.testing.assert_allclose(m.local_index("collision_margin", poses[:5]), margins[:5, :, 0].min(axis=1))
    with pytest.raises(PkmError, match="collisions of a described machine"):
        m.certify("task", properties=("collisions",))
    assert main(["certify", "ups_pu", "--region", "task", "--boxes", "20"]) == 0  # without collisions by default


def test_a_certification_in_parallel_pieces_is_the_one_search(capsys):
    """The box cut into pkm.certify_pieces.PIECES pieces by the search's own halvings, each in a local process:
    the same verdict and undecided volume as one search (the five-bar's MIW, which touches its workspace's rim, and
    a disc refuted for a box of designs, its witnesses' designs in the box); the pieces tile the box; the command
    takes --executor processes."""
    from pkm import certify_pieces

    five_bar = pkm.load("five_bar")
    one = five_bar.certify("miw", properties=("limits",))
    pieces = certify_pieces.certify(five_bar, "miw", properties=("limits",), executor="processes")
    assert (pieces.verdict, pieces.undecided) == (one.verdict, one.undecided) == ("undecided", pieces.undecided)
    assert pieces.undecided > 0
    refuted = certify_pieces.certify(five_bar, _disc((0.0, 1.6), 0.4), properties=("limits",),
                                     designs={"r2": (0.9, 1.0)}, executor="processes")
    assert refuted.verdict == "refuted"
    assert all(0.9 <= w["design"]["r2"] <= 1.0 for w in refuted.witnesses)
    boxes = certify_pieces.cut(3)
    assert len(boxes) == certify_pieces.PIECES
    assert sum(np.prod(np.subtract(hi, lo)) for lo, hi, _ in boxes) == pytest.approx(8.0)
    assert main(["certify", "delta", "--properties", "limits", "--executor", "processes", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["verdict"] == "proved"


def test_the_largest_disc_over_a_set_of_designs_lies_within_each_designs_and_below_its_witness(tmp_path, capsys):
    """The five-bar's largest disc about (0, 1.6) free of limits for every r2 in [0.95, 1.0], by pkm certify
    --around --designs (its text names the witness's design, its certify.json the result): proved no larger than
    at the default design (r2 = 1.0, in the interval), and its witness lies beyond it at a design in the interval
    whose workspace margin there is negative."""
    five_bar = pkm.load("five_bar")
    alone = five_bar.largest_region([0.0, 1.6], radius=1.0, properties=("limits",), tolerance=2e-2, depth=10)
    assert main(["certify", "five_bar", "--around", "0,1.6", "--radius", "1", "--properties", "limits", "--depth",
                 "10", "--designs", "r2=0.95:1.0", "--out", str(tmp_path / "spanned")]) == 0
    assert ", r2 = 0.95" in capsys.readouterr().out
    spanned = json.loads((tmp_path / "spanned" / "certify.json").read_text())
    assert 0 < spanned["proved"] <= alone.proved * (1 + 2e-2)
    witness = spanned["witness"]
    assert spanned["proved"] <= witness["distance"]
    assert 0.95 <= witness["design"]["r2"] <= 1.0
    pose = np.array(list(witness["pose"].values()))
    assert np.hypot(pose[0], pose[1] - 1.6) == pytest.approx(witness["distance"], rel=1e-9)
    assert five_bar.local_index("workspace_margin", pose, witness["design"]) < 0
