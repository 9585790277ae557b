"""The planar 2-DOF manipulator with two revolute-actuated RRR legs and a passive RP constraining leg
of Nam and Park 2006: the platform's centre C = (x_c, y_c) moves in the plane and its angle follows,
x_c cos(theta) + y_c sin(theta) = 0 (eq. 1).

See ``symbolic/mechanisms/passive_leg.py`` for the equations and docs/papers/nam2006.md for the mapping
to the paper. Working modes are the signs of eq. 6 for the two legs; the forward kinematics is the
degree-6 polynomial in the passive leg's length l_c (eq. 11 as derived): assembly mode ``root<k>`` is
its k-th real root in ascending order.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any, ClassVar

import casadi as ca
import numpy as np

from pkm.batch import evaluate
from pkm.design import Condition, Parameter
from pkm.design_space import DesignSpace
from pkm.errors import PoseError
from pkm.kinematics import (
    Branch,
    DesignLike,
    FunctionTable,
    PolynomialRoots,
    as_batch,
    as_real,
    unbatch,
)
from pkm.mechanism import Mechanism
from pkm.models.passive_leg.spaces import NAM2006
from pkm.models.passive_leg.structure import structure
from pkm.regions import Mapped, MappedSquare, Union

DEG = math.pi / 180
INF = math.inf
MAX_ASSEMBLIES = 6
MARGINS = ("angle_b1", "angle_b2", "type2")
CLOSURE_TOLERANCE = 1e-9  # the loop residual forward_refined accepts, relative to (l_a + l_b)^2

PARAMETERS = (
    Parameter("R", 1.0, 0.0, INF, "m", "half-distance between the base revolutes B1, B2 (Nam section 6.2: R = 1)"),
    Parameter("r", 1.2, 0.0, INF, "m", "half-width of the platform, |C b_i| (Fig. 8c: r = 1.2)"),
    Parameter("l_a", 1.4, 0.0, INF, "m", "lower (actuated) links |B_i d_i| (l_b - l_a = R - r: 1.4)"),
    Parameter("l_b", 1.2, 0.0, INF, "m", "upper links |d_i b_i| (Fig. 8c: l_b = 1.2)"),
    Parameter("theta_max", 85 * DEG, 0.0, math.pi / 2 + 1e-12, "rad",
              "largest platform angle |theta| of the workspace region, the phi of eq. 28 'in the vicinity of "
              "pi/2' (pkm's choice: 85 deg; up to pi/2 inclusive)", required=False),
)

CONDITIONS = (
    Condition("l_a + l_b > max(r, R - r) (eq. 14: the outer boundary l_CM is real at every theta)",
              lambda d: d["l_a"] + d["l_b"] - max(d["r"], d["R"] - d["r"])),
)

WORKING_MODES = (
    Branch("out_out", (1.0, -1.0), "both elbows outward: d1 right of the line B1 b1, d2 left of B2 b2 (Fig. 1: "
           "eq. 6 with + for leg 1 and - for leg 2; the branch of eq. 25 and of section 4's joint ranges)",
           aliases=("fig1",)),
    Branch("out_in", (1.0, 1.0), "elbow d1 outward, d2 inward (eq. 6 with + for both legs)"),
    Branch("in_out", (-1.0, -1.0), "elbow d1 inward, d2 outward (eq. 6 with - for both legs)"),
    Branch("in_in", (-1.0, 1.0), "both elbows inward (eq. 6 with - for leg 1 and + for leg 2)"),
)


def region_margins(generated: FunctionTable) -> ca.Function:
    """``region_margins(q, x, design) -> margins``: the sines of section 4's joint angles b_i (>= 0
    inside [0, pi]) and -2 l_c det J_x / (l_a + l_b)^3 (> 0 away from the type-2 singularity on Fig. 1's
    branch). The angles d_i keep their sign on a working mode: they leave (0, pi) only where a leg is
    stretched or folded, where the inverse kinematics ends (its reach)."""
    angles, jac = generated["joint_angles"], generated["paper_first_order"]
    q, x, d = (ca.SX.sym(angles.name_in(i), angles.size_in(i)) for i in range(3))
    sines, _ = angles(q, x, d)
    _, _, det_jx, _, _ = jac(q, x, d)
    margins = ca.vertcat(sines[2:], det_jx / (d[2] + d[3]) ** 3)
    return ca.Function("region_margins", [q, x, d], [margins], ["q", "x", "design"], ["margins"])


NEWTON_STEPS = 2
NEWTON_LIMIT = 1e-4  # a Newton step longer than this in l_c / (l_a + l_b) or theta [rad] is not taken


def leg_reach(generated: FunctionTable) -> ca.Function:
    """``leg_reach(design) -> l_a + l_b``: the size of the passive leg's length, the forward
    polynomial's variable."""
    d = ca.SX.sym("design", generated["forward_polynomial"].size_in(1))
    return ca.Function("leg_reach", [d], [d[2] + d[3]], ["design"], ["l"])


def forward_refined(generated: FunctionTable) -> ca.Function:
    """``forward_refined(root, q_a, design) -> (x, q, reach)``: the pose and joints of a root l_c of the
    forward polynomial, theta by the legs one at a time and Newton steps on eqs. 2-3 in (l_c, theta).

    At a root each leg's equation reads a_i + b_i cos(theta) + c_i sin(theta) = 0 (eq. 8) with two
    solutions; of the four, the one that best closes the other leg is kept. (The linear pair of eq. 8
    divides by B2 C1 - B1 C2, which is small where two assemblies nearly meet, and loses digits there.)
    A Newton step that is long or not finite (at a double root) is not taken."""
    back, paper = generated["forward_from_root"], generated["paper_forward"]
    root, qa, d = (ca.SX.sym(back.name_in(i), back.size_in(i)) for i in range(3))

    def legs(theta):
        return paper(ca.vertcat(qa, theta, 0, 0, root), d)[0]

    at_0, at_half, at_pi = legs(0), legs(math.pi / 2), legs(math.pi)
    candidates = []
    for i in range(2):
        a = (at_0[i] + at_pi[i]) / 2
        b, c = (at_0[i] - at_pi[i]) / 2, at_half[i] - a
        turn = ca.acos(ca.fmin(1, ca.fmax(-1, -a / ca.sqrt(b**2 + c**2))))
        candidates += [ca.atan2(c, b) + turn, ca.atan2(c, b) - turn]
    best, best_error = candidates[0], ca.mmax(ca.fabs(legs(candidates[0])))
    for theta in candidates[1:]:
        error = ca.mmax(ca.fabs(legs(theta)))
        best, best_error = ca.if_else(error < best_error, theta, best), ca.fmin(error, best_error)
    best = ca.atan2(ca.sin(best), ca.cos(best))
    z = ca.SX.sym("z", 2)
    residual = paper(ca.vertcat(qa, z[1], 0, 0, z[0]), d)[0]
    moved = z - ca.solve(ca.jacobian(residual, z), residual)
    step = moved - z
    small = ca.logic_and(ca.fabs(step[0]) <= NEWTON_LIMIT * (d[2] + d[3]), ca.fabs(step[1]) <= NEWTON_LIMIT)
    newton = ca.Function("newton", [z, qa, d], [ca.if_else(small, moved, z)])
    step = ca.vertcat(root, best)
    for _ in range(NEWTON_STEPS):
        step = newton(step, qa, d)
    l_c, theta = step[0], step[1]
    centre = l_c * ca.vertcat(-ca.sin(theta), ca.cos(theta))
    u = ca.vertcat(ca.cos(theta), ca.sin(theta))
    psi = []
    for k, side in enumerate((1, -1)):
        elbow = ca.vertcat(side * d[0], 0) + d[2] * ca.vertcat(ca.cos(qa[k]), ca.sin(qa[k]))
        upper = centre + side * d[1] * u - elbow
        psi.append(ca.atan2(upper[1], upper[0]))
    q = ca.vertcat(qa, theta, psi[0], psi[1], l_c)
    closure = paper(q, d)[0]
    reach = CLOSURE_TOLERANCE * (d[2] + d[3]) ** 2 - ca.fabs(closure)
    return ca.Function("forward_refined", [root, qa, d], [centre, q, reach], ["root", "q_a", "design"],
                       ["x", "q", "reach"])


@dataclass(frozen=True)
class ForwardSolutions:
    """Every real solution of the forward kinematics of a batch of actuator angles.

    Attributes
    ----------
    l_c : numpy.ndarray, shape (N, 6)
        Real roots of the polynomial of eq. 11 (as derived), ascending, NaN-padded, each refined on the
        loop equations [m]. A root with y_c < 0 (|theta| > pi/2) is an assembly outside the paper's
        domain (section 4).
    pose : numpy.ndarray, shape (N, 6, 2)
        (x_c, y_c) of each root [m].
    theta : numpy.ndarray, shape (N, 6)
        Platform angle of each root [rad].
    modes : numpy.ndarray of str, shape (N, 6)
        The working mode of each configuration ('' where there is no root).
    count : numpy.ndarray of int, shape (N,)
        Number of real solutions.
    residual : numpy.ndarray, shape (N, 6)
        Largest residual of eqs. 2-3 at each solution [m^2]: near a double root (a forward singularity)
        a root is accurate to about the square root of the rounding only.
    """

    l_c: np.ndarray
    pose: np.ndarray
    theta: np.ndarray
    modes: np.ndarray
    count: np.ndarray
    residual: np.ndarray


POLAR = Union(
    "polar",
    "theta in the workspace range, l_c between the boundaries, in two halves split at the kink theta = 0, the "
    "nodes graded towards l_CM (where a leg stretches and the indices behave like a square root)",
    tuple(MappedSquare(f"polar_{side}", f"theta {sign} 0", f"workspace_range_{side}", "workspace_curves",
                       grading=2)
          for side, sign in (("negative", "<="), ("positive", ">="))),
)


class PassiveLeg(Mechanism):
    name = "passive_leg"
    doc = "planar 2-DOF manipulator with revolute actuators and a passive constraining leg (Nam 2006): pose (x_c, y_c)"
    parameters = PARAMETERS
    conditions = CONDITIONS
    working_modes = WORKING_MODES
    assembly_modes = tuple(
        Branch(f"root{k}", (float(k),), f"the {k + 1}-th real root l_c of the forward polynomial (eq. 11)")
        for k in range(MAX_ASSEMBLIES)
    )
    pose_names = ("x_c", "y_c")
    pose_units = ("m", "m")
    actuator_names = ("phi1", "phi2")
    actuator_units = ("rad", "rad")
    forward = PolynomialRoots(back="forward_refined", scale="leg_reach")
    design_spaces: ClassVar[dict[str, DesignSpace]] = {"nam2006": NAM2006}
    structure = staticmethod(structure)
    regions: ClassVar[dict[str, Any]] = {
        "workspace": Mapped(
            "workspace",
            "the workspace of section 4 in (theta, l_c): |theta| <= theta_max, l_c from the inner boundary "
            "(the x axis where l_cm is not real) to l_CM(theta) (eqs. 12-13 as derived), measured in the plane "
            "of (x_c, y_c) (dW = l_c dtheta dl_c); indices are undefined where the reach, a joint range of "
            "section 4 or the sign of det J_x fails at a node",
            POLAR,
            "polar_to_pose",
            element="polar_area",
            guard="region_margins",
            modes=("out_out",),
        ),
        "workspace_eq28": Mapped(
            "workspace_eq28",
            "the same region measured as eq. 28 prints it, dW = dtheta dl_c (W = integral of l_CM dtheta)",
            POLAR,
            "polar_to_pose",
            guard="region_margins",
            modes=("out_out",),
        ),
    }

    def composed(self, generated: Mapping[str, ca.Function]) -> dict[str, ca.Function]:
        """The workspace margins, the refined forward kinematics and the legs' reach, composed from the generated
        functions."""
        return {
            "region_margins": region_margins(generated),
            "forward_refined": forward_refined(generated),
            "leg_reach": leg_reach(generated),
        }

    def workspace_box(self, design: np.ndarray) -> np.ndarray:
        """x_c within +-(l_a + l_b), y_c from 0 to l_a + l_b: the passive leg is never longer than l_CM(theta)
        <= l_a + l_b."""
        d = self.design_dict(design)
        reach = d["l_a"] + d["l_b"]
        return np.array([[-reach, reach], [0.0, reach]])

    def region_margins(self, pose: Any, design: DesignLike = None, *, mode: str | None = None
                          ) -> dict[str, np.ndarray]:
        """Margins by name (:data:`MARGINS`), each (N,) or a float, >= 0 inside the workspace of section 4:
        the sines of the joint angles b_i = d_i b_i C (in [0, pi) on Fig. 1's branch) and the type-2
        measure -2 l_c det J_x / (l_a + l_b)^3."""
        x, single = as_batch(pose, self.n_out, "pose")
        d = self.design_vector(design)
        q = self.inverse_kinematics(x, d, mode=mode, passive=True)
        (margins,) = evaluate(self.functions["region_margins"], q, x, d)
        return {name: unbatch(margins[:, k, 0], single) for k, name in enumerate(MARGINS)}

    def singularity_measures(self, pose: Any, design: DesignLike = None, *, mode: str | None = None
                             ) -> dict[str, np.ndarray]:
        """det J_q (eq. 19: zero on type-1, inverse singularities) and det J_x (eq. 20: zero on type-2,
        forward singularities) at poses, each (N,) or a float; both zero on architecture singularities."""
        x, single = as_batch(pose, self.n_out, "pose")
        d = self.design_vector(design)
        q = self.inverse_kinematics(x, d, mode=mode, passive=True)
        J_q, J_x, _, _, _ = evaluate(self.functions["paper_first_order"], q, x, d)
        reached = np.all(np.isfinite(q), axis=1)
        dets = {"det_J_q": np.full(len(x), np.nan), "det_J_x": np.full(len(x), np.nan)}
        dets["det_J_q"][reached] = np.linalg.det(J_q[reached])
        dets["det_J_x"][reached] = np.linalg.det(J_x[reached])
        return {k: unbatch(v, single) for k, v in dets.items()}

    def workspace_boundary(self, theta: Any, design: DesignLike = None) -> dict[str, np.ndarray]:
        """l_CM(theta), l_cm(theta) of eqs. 12-13 (as derived and as printed) and the radicands of eqs.
        14-15, by name, each (N,) or a float; NaN where a boundary is not real."""
        t = as_real(theta, "theta", "a number or (N,)")
        if t.ndim > 1 or not np.all(np.isfinite(t)) or np.any(np.abs(t) >= math.pi / 2):
            raise PoseError("theta must be a number or (N,), finite and within (-pi/2, pi/2) (section 4)")
        d = self.design_vector(design)
        fn = self.functions["workspace_boundary"]
        values = {fn.name_out(k): v[:, 0, 0] for k, v in enumerate(evaluate(fn, np.atleast_1d(t)[:, None], d))}
        for key, radicand in (("l_CM", "eq14"), ("l_cm", "eq15")):
            for name in (key, f"{key}_printed"):
                values[name] = np.where(values[radicand] >= 0, values[name], np.nan)
        return {k: unbatch(v, t.ndim == 0) for k, v in values.items()}

    def forward_solutions(self, q: Any, design: DesignLike = None) -> ForwardSolutions:
        """Every real root l_c of eq. 11 for actuator angles (N, 2) or (2,), with its pose, working mode
        and loop residual; the leading axis is dropped for a single configuration."""
        qa, single = as_batch(q, self.n_act, "actuated joints")
        d = self.design_vector(design)
        roots = self.forward.compute(self.functions, qa, d)
        n, k = roots.shape
        found = np.isfinite(roots.ravel())
        x, q_all, reach = evaluate(self.functions["forward_refined"], np.nan_to_num(roots.reshape(-1, 1)),
                                   np.repeat(qa, k, axis=0), d)
        _, signs = evaluate(self.functions["joint_angles"], q_all[:, :, 0], x[:, :, 0], d)
        by_signs = {tuple(b.signs): b.name for b in self.working_modes}
        modes = np.array([by_signs.get(tuple(s), "") if ok else "" for s, ok in zip(signs[:, :, 0], found,
                                                                                      strict=True)])
        tolerance = CLOSURE_TOLERANCE * (d[2] + d[3]) ** 2
        residual = np.where(found, np.max(tolerance - reach[:, :, 0], axis=1), np.nan)
        pose = np.where(found[:, None], x[:, :, 0], np.nan)
        q_all = np.where(found[:, None], q_all[:, :, 0], np.nan)
        out = ForwardSolutions(q_all[:, 5].reshape(n, k), pose.reshape(n, k, 2), q_all[:, 2].reshape(n, k),
                               modes.reshape(n, k), found.reshape(n, k).sum(axis=1), residual.reshape(n, k))
        if not single:
            return out
        return ForwardSolutions(*(getattr(out, f)[0] for f in ("l_c", "pose", "theta", "modes", "count",
                                                                 "residual")))
