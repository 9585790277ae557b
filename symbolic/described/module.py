"""A normalised description's module (:func:`module`) and the derivation's command (:func:`main`)."""

from __future__ import annotations

import json
import sys
from dataclasses import replace
from pathlib import Path
from typing import Any

import sympy as sp

from pkm.spec.vocabulary import beams, kind_of, passive_stiffness, rods
from symbolic import codegen
from symbolic.codegen import ModuleSpec, Output, Port
from symbolic.described.bodies import Kinetic, chain_bodies, leg_bodies, mass_matrix, platform_bodies
from symbolic.described.elastic import BEAM_TERMS, beam_terms
from symbolic.described.legs import FRAMES, Leg, UndefinedError, derive_leg, expression, platform_rotation
from symbolic.kinematics import InverseKinematics, add_kinematics
from symbolic.loops import LoopClosure


def _add_chain(spec: ModuleSpec, k: int, leg: Leg, ends: tuple[sp.Matrix, sp.Matrix], *, pose: Port, design: Port
               ) -> None:
    """``chain<k>(q_leg, c, design) -> (h, H)``: a chain leg's closure at a platform attachment c and its Jacobian
    in the leg's joints (actuated first), and ``chain<k>_ends(x, design) -> (a, c)``: its base and platform
    attachments at a pose, between which the runtime continues it."""
    a, c = ends
    target = sp.Matrix([sp.Symbol(f"c{j + 1}", real=True) for j in range(a.rows)])
    joints = (leg.actuated, *leg.passive)
    h = leg.end - target
    spec.add(f"chain{k + 1}", (Port("q_leg", joints, "the leg's joints, actuated first"),
                               Port("c", tuple(target), "the platform attachment [m]"), design),
             (Output("h", h, "the chain's end less c [m]"), Output("H", h.jacobian(joints), "dh/dq_leg")),
             f"The closure of chain leg {k + 1} at a platform attachment, and its Jacobian in the leg's joints.")
    spec.add(f"chain{k + 1}_ends", (pose, design),
             (Output("a", a, "the base attachment [m]"), Output("c", c, "the platform attachment [m]")),
             f"The attachments of chain leg {k + 1} at a pose.")


def _add_circles(spec: ModuleSpec, legs: list[Leg], platform: list[sp.Matrix], *, actuated: Port, design: Port
                 ) -> None:
    """``platform_circles(q_a, design) -> (centres, radii)``: the sphere (in space) on which each leg's platform
    joint lies, its actuated joint given, and ``platform_points(design) -> points``:
    each leg's platform joint in the platform frame; the complete forward kinematics of a machine whose every
    leg has one (:mod:`pkm.assemblies`)."""
    centres = sp.Matrix.vstack(*(leg.circle[0].T for leg in legs))
    spec.add("platform_circles", (actuated, design),
             (Output("centres", centres, "each leg's sphere's centre, one row each, in the base frame [m]"),
              Output("radii", sp.Matrix([leg.circle[1] for leg in legs]), "each leg's sphere's radius [m]")),
             "The sphere on which each leg's platform joint lies, its actuated joint given.")
    _add_points(spec, platform, design)


def _add_points(spec: ModuleSpec, platform: list[sp.Matrix], design: Port) -> None:
    spec.add("platform_points", (design,),
             (Output("points", sp.Matrix.vstack(*(c.T for c in platform)), "each leg's platform joint in the "
                     "platform frame, one row each [m]"),),
             "Each leg's platform joint in the platform frame.")


def _add_loci(spec: ModuleSpec, legs: list[Leg], platform: list[sp.Matrix], *, actuated: Port, design: Port) -> None:
    """``platform_loci(q_a, design) -> (alpha, beta, gamma)``: the curve on which each leg's platform joint P_i
    lies in the plane, its actuated joint given, as alpha |P_i|^2 + beta . P_i + gamma = 0: a circle (B, r) with
    alpha 1, beta -2 B, gamma |B|^2 - r^2; a line through p along v with alpha 0, beta its unit normal, gamma
    -beta . p; and ``platform_points(design)`` (:func:`_add_circles`): a planar machine's complete forward
    kinematics (:mod:`pkm.assemblies`)."""
    alpha, beta, gamma = [], [], []
    for leg in legs:
        if leg.circle is not None:
            centre, radius = leg.circle
            alpha.append(sp.Integer(1))
            beta.append((-2 * centre).T)
            gamma.append(centre.dot(centre) - radius**2)
        else:
            point, along = leg.line
            normal = sp.Matrix([-along[1], along[0]]) / sp.sqrt(along.dot(along))
            alpha.append(sp.Integer(0))
            beta.append(normal.T)
            gamma.append(-normal.dot(point))
    spec.add("platform_loci", (actuated, design),
             (Output("alpha", sp.Matrix(alpha), "1 for a circle, 0 for a line, one row per leg"),
              Output("beta", sp.Matrix.vstack(*beta), "the linear coefficients, one row per leg [m]"),
              Output("gamma", sp.Matrix(gamma), "the constants, one row per leg [m^2 for a circle, m for a line]")),
             "The circle or line on which each leg's platform joint P lies, its actuated joint given: "
             "alpha |P|^2 + beta . P + gamma = 0.")
    _add_points(spec, platform, design)


def _add_elastic(spec: ModuleSpec, described: list[dict[str, Any]], legs: list[Leg], *, joints: Port, pose: Port,
                 design: Port, vector: Any, scalar: Any) -> None:
    """``elastic(design) -> (drives, passive, beams, bearings)``: each leg's drive compliance (0 where rigid), its
    passive joints' (0 where free), each beam's compliance terms (:data:`symbolic.described.elastic.BEAM_TERMS`, legs
    in order, each leg's beams from the base) and each leg's bearings' translational compliances summed (a
    translation at any joint moves the chain beyond it, and its end, by as much); and ``leg_ends(q, x, design) ->
    H_c``: each leg's closure's derivative in its platform joint's point, the legs' rows stacked."""
    dim = vector(described[0]["base"]).rows
    drives, terms, passive, bearings = [], [], [], []
    for leg in described:
        elastic = leg["elastic"]
        drives.append(sp.Integer(0) if elastic["drive"] is None else 1 / scalar(elastic["drive"]))
        bearings.append(sum((1 / scalar(k) for k in elastic.get("bearings", [])), sp.Integer(0)))
        passive += [sp.Integer(0) if k is None else 1 / scalar(k) for k in passive_stiffness(leg)]
        for b, j in enumerate(beams(leg)):
            link = vector(leg["joints"][j]["link"])
            terms.append(beam_terms(elastic["beams"][b], sp.sqrt(link.dot(link)), scalar, planar=dim == 2,
                                    count=rods(leg, j)))
    spec.add("elastic", (design,),
             (Output("drives", sp.Matrix(drives), "each leg's drive compliance, 0 where rigid [rad/(N m), m/N]"),
              Output("passive", sp.Matrix(passive) if passive else sp.zeros(0, 1), "each leg's passive joints' "
                     "compliance in order, 0 where free [rad/(N m), m/N]"),
              Output("beams", sp.Matrix(terms) if terms else sp.zeros(0, len(BEAM_TERMS)),
                     f"each beam's compliance terms at its end, clamped at its start: {', '.join(BEAM_TERMS)} [SI]"),
              Output("bearings", sp.Matrix(bearings), "each leg's joints' bearings' translational compliances "
                     "summed, 0 where rigid [m/N]")),
             "The compliance of each leg's drive, passive joints, beams and bearings.")
    if any("tilts" in leg["elastic"] for leg in described):
        _add_tilts(spec, described, legs, joints=joints, pose=pose, design=design, vector=vector, scalar=scalar)
    blocks = [-sp.eye(dim) if leg.h_c is None else leg.h_c for leg in legs]
    spec.add("leg_ends", (joints, pose, design),
             (Output("H_c", sp.Matrix.vstack(*blocks), "each leg's closure's derivative in its platform joint's "
                     "point, the legs' rows stacked [-]"),),
             "The derivative of each leg's closure in its platform joint's point.")


def _add_tilts(spec: ModuleSpec, described: list[dict[str, Any]], legs: list[Leg], *, joints: Port, pose: Port,
               design: Port, vector: Any, scalar: Any) -> None:
    """``bearing_tilts(q, x, design) -> (axes, compliances)``: each joint a leg draws, its revolute's axis in the base
    frame at the configuration and its bearing's tilt compliance (a chain's revolutes; a kind's first joint where it
    is one, its axis given in the base frame), a zero axis and compliance where it has none."""
    axes, compliances = [], []
    for leg, derived in zip(described, legs, strict=True):
        for j, stiffness in enumerate(leg["elastic"].get("tilts", [0] * kind_of(leg).points)):
            joint = leg["joints"][j] if j < len(leg["joints"]) else None
            revolute = joint is not None and joint["type"] == "R" and (bool(derived.frames) or j == 0)
            if not revolute or (isinstance(stiffness, int | float) and stiffness == 0):
                axes.append(sp.zeros(1, 3))
                compliances.append(sp.Integer(0))
                continue
            local = vector(joint["axes"][0])
            turned = derived.frames[j][1] if derived.frames else sp.eye(3)
            axes.append((turned * local / sp.sqrt(local.dot(local))).T)
            compliances.append(1 / scalar(stiffness))
    spec.add("bearing_tilts", (joints, pose, design),
             (Output("axes", sp.Matrix.vstack(*axes), "each drawn joint's revolute axis in the base frame, zero where "
                     "it has no tilt spring [-]"),
              Output("compliances", sp.Matrix(compliances), "each drawn joint's bearing tilt compliance, 0 where "
                     "rigid [rad/(N m)]")),
             "The revolutes' axes and their bearings' tilt compliances, joint by joint as the legs draw them.")


def _add_region(spec: ModuleSpec, region: dict[str, Any], design_port: Port, home: sp.Matrix, vector: Any) -> None:
    """``region_<name>(design) -> (centre, size)`` and, where the region spans other coordinates than the
    pose's own in order, ``region_<name>_pose(y, design) -> x`` (the others at the home pose's values)."""
    name = region["name"]
    spec.add(f"region_{name}", (design_port,),
             (Output("centre", vector(region["centre"]), "[pose units]"),
              Output("size", vector(region["size"]), "[pose units]")),
             f"Placement of the region {name}: {region['doc']}.")
    if region["coordinates"] != list(range(len(home))):
        y = tuple(sp.Symbol(f"y{k + 1}", real=True) for k in range(len(region["coordinates"])))
        x = list(home)
        for k, index in enumerate(region["coordinates"]):
            x[index] = y[k]
        spec.add(f"region_{name}_pose", (Port("y", y, "the region's coordinates"), design_port),
                 (Output("x", sp.Matrix(x), "[pose units]"),),
                 f"The pose at a point of the region {name}.")


def module(description: dict[str, Any]) -> ModuleSpec:
    """The ModuleSpec of a normalised description (:mod:`pkm.spec`)."""
    name = description["name"]
    frame = description["pose"]["frame"]
    parameters = [p["name"] for p in description["parameters"]]
    design = tuple(sp.Symbol(f"design.{p}", real=True) for p in parameters)
    pose = tuple(sp.Symbol(p, real=True) for p in FRAMES[frame])
    env = dict(zip(parameters, design, strict=True))

    def vector(trees: list[Any]) -> sp.Matrix:
        return sp.Matrix([expression(t, env) for t in trees])

    def scalar(tree: Any) -> sp.Expr:
        return expression(tree, env)

    rotation = platform_rotation(frame, pose)
    dim = rotation.rows
    defaults = {s: p["default"] for s, p in zip(design, description["parameters"], strict=True)}
    start = {**defaults, **{s: float(v.subs(defaults)) for s, v in zip(pose, vector(description["home"]), strict=True)}}
    origin = sp.Matrix(pose[:dim])
    legs = []
    kinetic: list[Kinetic] = []
    skeleton: list[sp.Matrix] = []
    ends: list[tuple[sp.Matrix, sp.Matrix]] = []
    limits: list[str] = []
    for k, leg in enumerate(description["legs"]):
        a, c = vector(leg["base"]), origin + rotation * vector(leg["platform"])
        legs.append(derive_leg(k, a, c, leg, rotation, vector=vector, scalar=scalar, start=start))
        last = legs[-1]
        names = last.reach_names or (("reach",) if len(last.reach) == 1 else
                                     tuple(f"reach {i + 1}" for i in range(len(last.reach))))
        margins = (*last.reach, *(m for _, m in last.stated))
        names += tuple(n for n, _ in last.stated)
        if "range" in leg:
            lo, hi = (scalar(t) for t in leg["range"])
            margins += (last.actuated - lo, hi - last.actuated)
            names += ("range lower", "range upper")
        legs[-1] = replace(last, margins=margins)
        limits += [f"leg {k + 1} {name}" for name in names]
        ends.append((a, c))
        skeleton += [a, *legs[-1].joints, c]
        if leg["kind"] == "chain":
            kinetic += chain_bodies(leg, legs[-1], scalar=scalar, vector=vector)
        elif "bodies" in leg:
            kinetic += leg_bodies(leg, legs[-1], a, c, scalar)
    q_a = tuple(leg.actuated for leg in legs)
    q_p = tuple(s for leg in legs for s in leg.passive)
    signs = tuple(leg.sign for leg in legs if leg.sign is not None) or (sp.Symbol("branch", real=True),)
    loop = LoopClosure.of([h for leg in legs for h in leg.h], q_a, q_p, pose)
    solution = {s: e for leg in legs for s, e in leg.ik.items()}
    q = sp.Matrix([solution[s] for s in (*q_a, *q_p)])
    spec = ModuleSpec(name, "symbolic/described", description.get("doc", name), limits=tuple(limits))
    design_port = Port("design", design, "; ".join(f"{p['name']} [{p['unit']}]" for p in description["parameters"]))
    pose_port = Port("x", pose, ", ".join(f"{n} [{u}]" for n, u in zip(FRAMES[frame], description["pose"]["units"],
                                                                       strict=True)))
    joints = Port("q", (*q_a, *q_p), "actuated joints, then the passive joints leg by leg")
    actuated = Port("q_a", q_a, "actuated joints")
    mode = Port("mode", signs, "branch sign of each leg with two (+1 or -1)")
    chains = any(leg.end is not None for leg in legs)
    inverse = InverseKinematics(
        q, sp.Matrix([m for leg in legs for m in leg.reach]),
        "Closed-form inverse kinematics, leg by leg, on the branch of the mode's signs"
        + ("; a chain leg's joints are its branch's seed, where the runtime's continuation starts." if chains
           else "."),
        "actuated, then passive joints", "margins of each closed-form leg's reach, >= 0 where it assembles",
    )
    add_kinematics(spec, loop, pose=pose_port, joints=joints, actuated=actuated, design=design_port, mode=mode,
                   inverse=inverse, units=dict.fromkeys(("h", "H_q", "H_x", "J", "J_f", "psi", "det"), "-"),
                   composed=True, inverse_name="continuation_start" if chains else "inverse_kinematics")
    for k, (leg, attachments) in enumerate(zip(legs, ends, strict=True)):
        if leg.end is not None:
            _add_chain(spec, k, leg, attachments, pose=pose_port, design=design_port)
    spec.add("home", (design_port,), (Output("x", vector(description["home"]), "the home pose"),),
             "The home pose: the seed of the forward kinematics.")
    if description.get("platform") is not None or kinetic:
        kinetic += platform_bodies(description.get("platform"), frame, pose, rotation, vector=vector, scalar=scalar)
        z = [*q_a, *q_p, *pose]
        spec.add("mass_matrix", (joints, pose_port, design_port),
                 (Output("M", mass_matrix(kinetic, z), "the kinetic energy's matrix in (q, x): T = z_dot^T M "
                         "z_dot / 2, z = (q, x) [SI]"),),
                 "The mass matrix of the bodies in all the joint and pose coordinates.")
        if description.get("gravity") is not None:
            g = vector(description["gravity"])
            potential = -sum((w * g.dot(p) for w, _, _, p in kinetic if p is not None), sp.Integer(0))
            spec.add("gravity", (joints, pose_port, design_port),
                     (Output("G", sp.Matrix([potential]).jacobian(z).T, "dV/dz [N or N m]"),
                      Output("V", sp.Matrix([potential]), "the bodies' potential energy in the gravity field [J]")),
                     "The gradient of the bodies' potential energy in all the joint and pose coordinates.")
    spec.add("skeleton", (joints, pose_port, design_port),
             (Output("points", sp.Matrix.hstack(*skeleton).T, "each leg's joints from the base's to the platform's, "
                     "one row each [m]"),),
             "The points of the joints, leg by leg, for drawing the linkage.")
    sides = [leg.side for leg in legs if leg.side is not None]
    if sides:
        spec.add("branch_sides", (joints, pose_port, design_port),
                 (Output("sides", sp.Matrix(sides), "one per leg with passive joints and two branches: its sign "
                         "tells the branches apart"),),
                 "The side of each two-branched leg's passive joints at a configuration.")
    for region in description.get("regions", []):
        _add_region(spec, region, design_port, vector(description["home"]), vector)
    platform = [vector(leg["platform"]) for leg in description["legs"]]
    if frame in ("planar", "planar_point") and all(leg.circle is not None or leg.line is not None for leg in legs):
        _add_loci(spec, legs, platform, actuated=actuated, design=design_port)
    elif frame in ("spatial_point", "spatial") and all(leg.circle is not None for leg in legs) and \
            (frame != "spatial" or len(legs) == 6):
        _add_circles(spec, legs, platform, actuated=actuated, design=design_port)
    if all("capsule" in leg for leg in description["legs"]):
        spec.add("capsules", (design_port,),
                 (Output("radii", sp.Matrix([scalar(leg["capsule"]) for leg in description["legs"]]),
                         "the radius of each leg's capsules [m]"),),
                 "The radius of the capsules around each leg's links.")
    for plate, table in description.get("plates", {}).items():
        if "points" in table:
            points = [vector(point) for point in table["points"]]
            placed = [origin + rotation * point for point in points] if plate == "platform" else points
            spec.add(f"plate_{plate}", (pose_port, design_port),
                     (Output("points", sp.Matrix.hstack(*placed).T, f"the {plate} plate's points in the base frame, "
                             "one row each [m]"),),
                     f"The {plate} plate's own points, placed.")
    if all("elastic" in leg for leg in description["legs"]):
        _add_elastic(spec, description["legs"], legs, joints=joints, pose=pose_port, design=design_port,
                     vector=vector, scalar=scalar)
    margins = [m for leg in legs for m in leg.margins]
    spec.add("workspace_margins", (joints, pose_port, design_port),
             (Output("margins", sp.Matrix(margins), "each leg's reach margins and its actuated joint's range, >= 0 "
                     "inside the workspace, named by the module's LIMITS"),),
             "The workspace's margins at a configuration: >= 0 where the legs reach and the actuated joints lie "
             "in their ranges.")
    if description.get("characteristic_length"):
        spec.add("characteristic_length", (design_port,),
                 (Output("L", sp.Matrix([scalar(description["characteristic_length"])]), "[m]"),),
                 "The length that turns the pose's angles into arc lengths.")
    return spec


UNDEFINED = 3  # the exit status of a derivation that meets an expression without a finite value


def main(argv: list[str] | None = None) -> int:
    """Derive the description at the first path into the module at the second; an expression without a
    finite value ends it with one line on standard error and :data:`UNDEFINED`."""
    source, target = (Path(a) for a in (argv if argv is not None else sys.argv[1:]))
    description = json.loads(source.read_text())
    try:
        rendered = codegen.RenderedModule.of(module(description), description["key"], canonical=False)
    except (UndefinedError, codegen.UndefinedError) as exc:
        print(f"undefined: {exc}", file=sys.stderr)
        return UNDEFINED
    target.write_text(rendered.text)
    return 0


