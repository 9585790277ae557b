"""The spatial 2-UPS-PU platform of Zhao, Tang and Zhao 2008: one translation l0 along the central PU
leg and two rotations theta1 (about the base X axis) and theta2 (about the moving y_p axis).

See ``symbolic/mechanisms/ups_pu.py`` for the equations and docs/papers/zhao2008.md for the mapping to
the paper. The forward kinematics is the degree-8 polynomial in tan(theta2 / 2) of the symbolic module:
assembly mode ``root<k>`` is its k-th real root in ascending order.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any, ClassVar

import casadi as ca
import numpy as np

from pkm.batch import REACH_TOLERANCE, evaluate_finite
from pkm.design import Condition, Parameter
from pkm.design_space import DesignSpace, parameter_plane
from pkm.errors import PoseError
from pkm.kinematics import (
    Branch,
    DesignLike,
    FunctionTable,
    PolynomialRoots,
    as_batch,
    as_real,
    nan_unless,
    require_finite,
    unbatch,
    within_limits,
)
from pkm.mechanism import Mechanism
from pkm.models.ups_pu import workspace
from pkm.models.ups_pu.structure import structure
from pkm.regions import Cylinder, Mapped

DEG = math.pi / 180
INF = math.inf
MAX_ASSEMBLIES = 8
WRENCH = ("F_x", "F_y", "F_z", "M_x", "M_y", "M_z")


def _length(name: str, default: float, doc: str) -> Parameter:
    return Parameter(name, default, 0.0, INF, "m", doc)


def _angle(name: str, default: float, lower: float, upper: float, doc: str) -> Parameter:
    return Parameter(name, default, lower, upper, "rad", doc)


PARAMETERS = (
    _length("r", 0.124, "radius of the platform's spherical joints S1, S2 about U0 (Zhao Table 1: 124 mm)"),
    _length("R", 0.186, "radius of the base universal joints U1, U2 about O (Table 1: 186 mm)"),
    _angle("alpha", 90 * DEG, -math.pi - 1e-12, math.pi, "angular position of U1 and S1 (Zhao section 6: 90 deg)"),
    _angle("beta", 27 * DEG, -math.pi - 1e-12, math.pi, "angular position of U2 and S2 (Table 1: 27 deg)"),
    _length("l_min", 0.396, "shortest length of the UPS legs (Table 1: 396 mm)"),
    _length("l_max", 0.712, "longest length of the UPS legs (Table 1: 712 mm)"),
    _length("l0_min", 0.450, "lowest position l0 of U0 (Table 1: 450 mm)"),
    _length("l0_max", 0.650, "highest position l0 of U0 (Table 1: 650 mm)"),
    _angle("theta_u_max", 90 * DEG, 0.0, math.pi, "largest misalignment of a universal joint (section 5.3: 90 deg)"),
    _angle("theta_s_max", 60 * DEG, 0.0, math.pi, "largest misalignment of a spherical joint (section 5.3: 60 deg)"),
    Parameter("D", 0.005, 0.0, INF, "m", "diameter of the legs, the least distance between two legs "
              "(section 5.3: 5 mm)", closed_lower=True),
    Parameter("payload", 50.0, 0.0, INF, "kg", "mass carried by the platform (pkm's choice: Zhao states no load)",
              closed_lower=True, required=False),
    Parameter("payload_height", 0.2, -INF, INF, "m", "height of the payload's centre of mass above U0 along the "
              "platform normal (pkm's choice)", required=False),
    Parameter("g", 9.81, 0.0, INF, "m/s^2", "gravitational acceleration along -Z", closed_lower=True, required=False),
    Parameter("task_tilt", 30 * DEG, 0.0, math.pi / 2, "rad", "radius of the prescribed task cylinder: the largest "
              "tilt of the platform normal (section 6.2's gamma_u = 60 deg read as the cone's apex angle)",
              required=False),
    Parameter("task_height", 0.1, 0.0, INF, "m", "height h of the task cylinder in l0, from l0_min (section 6.2: "
              "100 mm)", required=False),
)

CONDITIONS = (
    Condition("l_min < l_max (the UPS legs have a stroke)", lambda d: d["l_max"] - d["l_min"]),
    Condition("l0_min < l0_max (the PU leg has a stroke)", lambda d: d["l0_max"] - d["l0_min"]),
    Condition(
        "sin(beta - alpha) != 0 (the UPS legs neither coincide nor stand opposite: det J = 0 everywhere)",
        lambda d: abs(math.sin(d["beta"] - d["alpha"])) - 1e-9,
    ),
)


SINGULAR_CONDITION = 1e12  # the Frobenius condition number of the wrench matrix from which a pose is singular


def _regular_solve(matrix: ca.SX, rhs: ca.SX) -> tuple[ca.SX, ca.SX]:
    """``matrix^-1 rhs`` and whether ``matrix`` is regular: its Frobenius condition number ||W||_F ||W^-1||_F
    below SINGULAR_CONDITION (kappa_2 <= kappa_F <= 6 kappa_2 for a 6 x 6 matrix)."""
    condition = ca.norm_fro(matrix) * ca.norm_fro(ca.solve(matrix, ca.SX.eye(matrix.size1())))
    return ca.solve(matrix, rhs), condition < SINGULAR_CONDITION


def actuator_forces(statics: ca.Function) -> ca.Function:
    """``actuator_forces(q, x, design) -> f_a``: the forces (f1, f2, f0) that hold the payload, whose
    resultant with the constraint forces cancels the payload's wrench: W f = -w_load; infinite where the
    wrench matrix is singular (its Frobenius condition number at least SINGULAR_CONDITION), so that the
    largest force over a region touching a singularity is its limit, not a finite number of 1e13 N."""
    q, x, d = (ca.SX.sym(statics.name_in(i), statics.size_in(i)) for i in range(3))
    W, _, w_load = statics(q, x, d)
    forces, regular = _regular_solve(W, -w_load)
    finite = ca.if_else(regular, forces[:3], ca.DM.inf(3))
    return ca.Function("actuator_forces", [q, x, d], [finite], ["q", "x", "design"], ["f_a"])



def statics_pipeline(functions: FunctionTable, printed: bool) -> ca.Function:
    """``(x, wrench, mode, design) -> (f)``: the inverse kinematics, the wrench matrix W of eq. 8 (as
    printed with ``printed``) and f = W^-1 wrench in one SX graph; f (6 x 1) is NaN where the pose is out
    of reach or W is singular (:func:`_regular_solve`)."""
    ik, statics = functions["inverse_kinematics"], functions["statics"]
    x = ca.SX.sym("x", ik.numel_in(0))
    wrench = ca.SX.sym("wrench", 6)
    mode = ca.SX.sym("mode", ik.numel_in(1))
    design = ca.SX.sym("design", ik.numel_in(2))
    q, reach = ik(x, mode, design)
    W, W_printed, _ = statics(q, x, design)
    forces, regular = _regular_solve(W_printed if printed else W, wrench)
    forces = nan_unless(ca.logic_and(ca.mmin(reach) >= -REACH_TOLERANCE, regular), forces)
    name = "statics_printed_pipeline" if printed else "statics_pipeline"
    return ca.Function(name, [x, wrench, mode, design], [forces], ["x", "wrench", "mode", "design"], ["f"])


def composed(generated: Mapping[str, ca.Function], names: tuple[str, ...]) -> dict[str, ca.Function]:
    """The functions composed from the generated ones: the workspace margins of section 5, the inverse
    kinematics within them (:func:`pkm.kinematics.within_limits`), the actuator forces and the statics."""
    functions = {**generated, **workspace.functions(generated, names)}
    functions.update(within_limits(functions, "workspace_margins"))
    functions["actuator_forces"] = actuator_forces(generated["statics"])
    functions["statics_pipeline"] = statics_pipeline(functions, printed=False)
    functions["statics_printed_pipeline"] = statics_pipeline(functions, printed=True)
    return {name: fn for name, fn in functions.items() if generated.get(name) is not fn}


@dataclass(frozen=True)
class Statics:
    """Forces that balance a wrench at U0 (Zhao eq. 8), over a batch of poses.

    Attributes
    ----------
    actuators : numpy.ndarray, shape (N, 3)
        f1, f2 along the UPS legs from U_i to S_i and f0 along Z [N].
    constraint : numpy.ndarray, shape (N, 3)
        The PU leg's constraint forces f_x, f_y along X, Y [N] and torque m_c [N m].
    """

    actuators: np.ndarray
    constraint: np.ndarray


class UpsPu(Mechanism):
    name = "ups_pu"
    doc = "spatial 2-UPS-PU platform of Zhao 2008: pose (l0, theta1, theta2), actuated l1, l2 and l0"
    parameters = PARAMETERS
    conditions = CONDITIONS
    working_modes = (Branch("legs", (1.0,), "the leg lengths of eq. 4 (one solution per pose)"),)
    assembly_modes = tuple(
        Branch(f"root{k}", (float(k),), f"the {k + 1}-th real root of the forward polynomial in tan(theta2/2)")
        for k in range(MAX_ASSEMBLIES)
    )
    limits = "workspace_margins"
    limit_names = workspace.MARGINS
    pose_names = ("l0", "theta1", "theta2")
    pose_units = ("m", "rad", "rad")
    actuator_names = ("l1", "l2", "l0_leg")
    actuator_units = ("m", "m", "m")
    forward = PolynomialRoots()
    design_spaces: ClassVar[dict[str, DesignSpace]] = {
        "radius_beta": parameter_plane(PARAMETERS, (("R", 0.08, 0.30), ("beta", 10 * DEG, 80 * DEG)),
                                       name="radius_beta"),
    }
    regions: ClassVar[dict[str, Any]] = {
        "task": Mapped(
            "task",
            "the prescribed cylinder of Zhao section 6: tilt gamma <= task_tilt at every l0 in [l0_min, l0_min + "
            "task_height], drawn in (l0, gamma cos phi, gamma sin phi) and mapped to the pose by eq. 15",
            Cylinder("task_tilt_cylinder", "the task cylinder in tilt coordinates", function="task_cylinder"),
            "tilt_to_pose",
        )
    }
    structure = staticmethod(structure)

    def composed(self, generated: Mapping[str, ca.Function]) -> dict[str, ca.Function]:
        """The workspace margins, the limited inverse kinematics, the actuator forces and the statics, composed
        from the generated functions (:func:`composed`)."""
        return composed(generated, self.parameter_names())

    def workspace_margins(self, pose: Any, design: DesignLike = None) -> dict[str, np.ndarray]:
        """The margins of the four constraints of Zhao section 5 and of the angles' range by name (see
        :mod:`pkm.models.ups_pu.workspace`), each (N,) or a float; >= 0 where the constraint holds
        (:meth:`limit_margins`)."""
        return self.limit_margins(pose, design)

    @staticmethod
    def characteristic_length(design: Mapping[str, Any]) -> Any:
        """The platform radius r: an angle of the platform times r is the displacement of S_i."""
        return design["r"]

    def workspace_box(self, design: np.ndarray) -> np.ndarray:
        """l0 over its stroke and both angles within +-90 deg (the range of eq. 6)."""
        d = self.design_dict(design)
        return np.array([[d["l0_min"], d["l0_max"]], [-math.pi / 2, math.pi / 2], [-math.pi / 2, math.pi / 2]])

    def statics(
        self, pose: Any, wrench: Any, design: DesignLike = None, *, mode: str | None = None, printed: bool = False
    ) -> Statics:
        """Actuator and constraint forces whose resultant at U0 is the wrench (F, M) (Zhao eq. 8: W f =
        wrench); pass the negative of an external load for the forces that hold it.

        ``printed`` uses eq. 8 as printed (unit moment axes, the constraint torque about Z) instead of
        the physical wrench matrix; see docs/papers/zhao2008.md. A wrench (6,) is shared by the poses.
        Rows out of reach and rows where the wrench matrix is singular (its Frobenius condition number
        at least 1e12) are NaN. IK, W, its conditioning and the solve are one compiled pass
        (:func:`statics_pipeline`).
        """
        x, single = as_batch(pose, self.n_out, "pose", finite=False)
        w = as_real(wrench, "wrench", "(6,) or (N, 6)")
        shape = f"(6,) or (N, 6) ({', '.join(WRENCH)})"
        if w.shape[-1:] != (6,) or w.ndim > 2:
            raise PoseError(f"wrench must have shape {shape}; got {w.shape}")
        if w.ndim == 2 and len(w) != len(x):
            raise PoseError(f"wrench has {len(w)} rows; the poses have {len(x)}")
        fused = self.functions["statics_printed_pipeline" if printed else "statics_pipeline"]
        (forces,), finite = evaluate_finite(fused, x, w, np.array(self.working_mode(mode).signs),
                                            self.design_vector(design))
        if not finite:
            require_finite(x, "pose")
            require_finite(w, "wrench")
        forces = forces[:, :, 0]
        return Statics(unbatch(forces[:, :3], single), unbatch(forces[:, 3:], single))
