"""The elastic elements of a described machine's legs (:data:`pkm.spec.vocabulary.ELASTIC_FIELDS`): each beam's
compliance at its end, clamped at its start (Euler-Bernoulli), and each drive's compliance, as expressions of the
design; the runtime composes them into the Cartesian stiffness (:mod:`pkm.spec.stiffness`)."""

from __future__ import annotations

from typing import Any

import sympy as sp

BEAM_TERMS = ("axial", "bending_uu", "bending_uphi", "bending_phiphi", "torsion")


def section_properties(section: dict[str, Any], scalar: Any) -> tuple[sp.Expr, sp.Expr, sp.Expr, sp.Expr]:
    """A section's area A and second moments I_y, I_z (about its y and z axes) and torsion constant J: a solid round
    of diameter d; a round tube of outer diameter d and wall t; a rectangular tube of width b (along y), height h
    (along z) and wall t (thin-walled: J = 4 A_m^2 t / p_m, A_m and p_m the area and perimeter within the wall's
    middle); or given."""
    shape = section["shape"]
    if shape == "given":
        return tuple(scalar(section[k]) for k in ("A", "I_y", "I_z", "J"))  # type: ignore[return-value]
    if shape == "round":
        d = scalar(section["d"])
        return sp.pi * d**2 / 4, sp.pi * d**4 / 64, sp.pi * d**4 / 64, sp.pi * d**4 / 32
    if shape == "tube":
        d, t = scalar(section["d"]), scalar(section["t"])
        inner = d - 2 * t
        moment = sp.pi * (d**4 - inner**4) / 64
        return sp.pi * (d**2 - inner**2) / 4, moment, moment, 2 * moment
    b, h, t = (scalar(section[k]) for k in ("b", "h", "t"))
    bi, hi = b - 2 * t, h - 2 * t
    middle = (b - t) * (h - t)
    return (b * h - bi * hi, (b * h**3 - bi * hi**3) / 12, (h * b**3 - hi * bi**3) / 12,
            4 * middle**2 * t / (2 * (b - t) + 2 * (h - t)))


def beam_terms(beam: dict[str, Any], length: sp.Expr, scalar: Any, *, planar: bool, count: int) -> list[sp.Expr]:
    """A beam's compliance terms at its end, clamped at its start, for end loads in its frame (x along it), of
    ``count`` equal beams side by side (a parallelogram's rods): L / (E A) axially; L^3 / (3 E I), L^2 / (2 E I)
    and L / (E I) in bending (I_z in the plane, I_y = I_z in space); L / (G J) in torsion (0 in the plane)."""
    area, _, i_z, torsion = section_properties(beam["section"], scalar)
    young, shear = scalar(beam["material"]["E"]), scalar(beam["material"]["G"])
    bend = young * i_z * count
    return [length / (young * area * count), length**3 / (3 * bend), length**2 / (2 * bend), length / bend,
            sp.Integer(0) if planar else length / (shear * torsion * count)]


def add_hand_derived(spec: Any, *, joints: Any, pose: Any, design: Any, points: list[sp.Matrix],
                     drives: list[sp.Expr], passive: int, terms: list[list[sp.Expr]], what: str) -> None:
    """A hand-derived machine's ``skeleton`` (its legs' joints, ``points`` leg by leg), ``elastic`` (its drives'
    compliances, ``passive`` free passive joints, its beams' compliance terms, rigid bearings) and ``leg_ends``
    (each leg's closure's derivative in its platform joint, I: its closure is that joint less the chain's end), in
    the conventions of a described machine of the same legs, whose stiffness composition reads them
    (:func:`pkm.spec.stiffness.elastic_functions`); ``what`` names the beams in their outputs' docs."""
    from symbolic.codegen import Output

    dim = points[0].rows
    spec.add("skeleton", (joints, pose, design),
             (Output("points", sp.Matrix.hstack(*points).T, "each leg's joints, one row each [m]"),),
             "The points of the joints, leg by leg, for drawing the linkage and for its elastic elements.")
    spec.add("elastic", (design,),
             (Output("drives", sp.Matrix(drives), "each leg's drive compliance [rad/(N m), m/N]"),
              Output("passive", sp.zeros(passive, 1), "each passive joint's compliance, 0: free [rad/(N m)]"),
              Output("beams", sp.Matrix(terms), f"{what}: each beam's compliance terms at its end, clamped at its "
                     f"start: {', '.join(BEAM_TERMS)} [SI]"),
              Output("bearings", sp.zeros(len(drives), 1), "the joints' bearings' compliance: rigid [m/N]")),
             "The compliance of each leg's drive and of each of its beams.")
    spec.add("leg_ends", (joints, pose, design),
             (Output("H_c", sp.Matrix.vstack(*[sp.eye(dim)] * len(drives)), "each leg's closure's derivative in "
                     "its platform joint [-]"),),
             "The derivative of each leg's closure in its platform joint's point.")
