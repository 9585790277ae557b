"""Quantities along a trajectory: global indices over a :class:`pkm.regions.TrajectoryRegion`, usable wherever a
global index is (objectives, constraints, checks), smooth in the design and refined between the nodes in time.

With tau the actuator efforts of the rigid inverse dynamics at the pose's motion (N for a prismatic
actuator, N m for a revolute one), q_dot = J x_dot the actuator rates and P = sum_i tau_i q_dot_i the
mechanical power the actuators deliver (negative where they brake):

==========================  ===========================================================  ==========
``effort_peak``             max_t max_i |tau_i|: a region maximum, in epigraph form       N or N m
                            (t >= +-tau_i at every node), refined between the nodes
``effort_rms``              sqrt(1/T int sum_i tau_i^2 / n dt): the efforts' RMS over      N or N m
                            time and actuators
``energy``                  int P dt: with regeneration (braking returns energy)          J
``energy_no_regeneration``  int sum_i max(tau_i q_dot_i, 0) dt: no drive returns or       J
                            passes on energy. The optimiser integrates the smooth
                            (p + sqrt(p^2 + s^2)) / 2 instead of max(p, 0), s =
                            ``smoothing`` [W] (at most s/2 more per actuator and second);
                            every reported and verified value is exact
``power_peak``              max_t |P|                                                    W
``actuator_speed_peak``     max_t max_i |q_dot_i|                                        actuator/s
``positioning_error``       max_t max_j sum_i |J_f[j, i]| delta_i: the worst error of a  pose
                            pose coordinate from the encoders' resolutions delta_i
                            (epigraph: every sign pattern of the sum, smooth)
``velocity_amplification``  max_t sigma_max(J_f): the largest end-effector speed per unit  pose/act.
                            actuator rates along the path
``joint_range_<actuator>``  max_t q_i - min_t q_i, two region extremes (:func:`joint_extremes`)
==========================  ===========================================================  ==========

The first five need a dynamic model (a virtual-work ``inverse_dynamics`` or a Lagrange chain model); the
others are kinematic and every mechanism has them.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Sequence
from dataclasses import replace
from typing import Any

import casadi as ca
import numpy as np

from pkm.batch import evaluate
from pkm.errors import PkmError, PoseError, UnknownNameError
from pkm.indices import GlobalIndex, LocalIndex
from pkm.indices.local import VELOCITY_MAX
from pkm.regions.pipeline import MOTION, first_order_outputs
from pkm.regions.trajectory import TrajectoryRegion, trajectory_region

EFFORT_UNITS = {"rad": "N m", "m": "N"}
ENCODER_RESOLUTION = {"rad": 2 * math.pi / 2**17, "m": 1e-6}  # a 17-bit rotary encoder, a 1 um linear scale
SMOOTHING = 1e-3  # [W] of the positive part of a power that the optimiser integrates
DYNAMICS = ("inverse_dynamics", "inverse_dynamics_from_pose", "elastic_dynamics")
DYNAMIC = ("effort_peak", "effort_rms", "energy", "energy_no_regeneration", "power_peak")
KINEMATIC = ("actuator_speed_peak", "positioning_error", "velocity_amplification")
SHOWN_POSES = 5  # poses out of reach that an error names


def has_dynamics(mech: Any) -> bool:
    """Whether the mechanism has a rigid dynamic model (its efforts along a motion are defined)."""
    return any(name in mech.functions for name in DYNAMICS)


def effort_unit(mech: Any) -> str:
    """The unit of the mechanism's actuator efforts (N for a prismatic actuator, N m for a revolute one)."""
    return " or ".join(sorted({EFFORT_UNITS.get(u, f"N m/{u}") for u in mech.actuator_units}))


def encoder_resolution(mech: Any, encoder: Sequence[float] | None) -> np.ndarray:
    """The encoders' resolutions (n_act,) in the actuators' SI units: given, or ENCODER_RESOLUTION by unit."""
    if encoder is None:
        return np.array([ENCODER_RESOLUTION.get(u, 1e-6) for u in mech.actuator_units])
    values = np.asarray(encoder, dtype=float).ravel()
    if values.shape != (mech.n_act,) or not np.all(np.isfinite(values) & (values > 0)):
        raise PkmError(f"encoder = {list(np.ravel(encoder))} violates: {mech.n_act} finite resolutions > 0, one per "
                       f"actuator ({', '.join(mech.actuator_names)}), in SI")
    return values


def _positive_part(p: ca.SX, width: float) -> ca.SX:
    return (p + ca.sqrt(p * p + width * width)) / 2


def _positioning_epigraph(steps: np.ndarray) -> Any:
    """t - sum_i s_i J_f[j, i] delta_i >= 0 for every sign pattern s and pose coordinate j: smooth, and all
    hold exactly where t >= max_j sum_i |J_f[j, i]| delta_i."""
    signs = np.array(list(itertools.product((-1.0, 1.0), repeat=len(steps))))
    patterns = ca.DM((signs * steps).T)
    return lambda J_f, t: ca.vec(t - J_f @ patterns)


def trajectory_indices(mech: Any, *, encoder: Sequence[float] | None = None,
                       smoothing: float = SMOOTHING) -> dict[str, GlobalIndex]:
    """The trajectory quantities the mechanism offers (module docstring), by name; ``encoder`` the actuators'
    resolutions for ``positioning_error`` (ENCODER_RESOLUTION by default)."""
    n = mech.n_act
    unit = effort_unit(mech)
    pose_unit = " or ".join(sorted(set(mech.pose_units)))
    rate_unit = " or ".join(sorted({f"{u}/s" for u in mech.actuator_units}))
    steps = encoder_resolution(mech, encoder)
    out: dict[str, GlobalIndex] = {}

    def motion(name: str, doc: str, unit: str, formula: Any, arguments: tuple[str, ...], **options: Any) -> LocalIndex:
        return LocalIndex(name, doc, unit, -np.inf, np.inf, np.nan, formula, MOTION, arguments, dimension=None,
                          raw=True, **options)

    if has_dynamics(mech):
        effort = motion("effort", "largest actuator effort |tau_i| of the rigid inverse dynamics at the motion",
                        unit, lambda tau: ca.mmax(ca.fabs(tau)), ("tau",),
                        epigraph_upper=lambda tau, t: ca.vertcat(t - tau, t + tau))
        square = motion("effort_square", "mean square of the actuator efforts sum_i tau_i^2 / n", f"({unit})^2",
                        lambda tau: ca.sumsqr(tau) / n, ("tau",))
        power = motion("power", "mechanical power the actuators deliver, sum_i tau_i q_dot_i", "W",
                       ca.dot, ("tau", "q_dot"),
                       epigraph_upper=lambda tau, q_dot, t: ca.vertcat(t - ca.dot(tau, q_dot), t + ca.dot(tau, q_dot)))
        positive = motion("positive_power", "power each actuator delivers, summed where positive: sum_i max(tau_i "
                          "q_dot_i, 0)", "W", lambda tau, q_dot: ca.sum1(ca.fmax(tau * q_dot, 0)), ("tau", "q_dot"),
                          smooth=lambda tau, q_dot: ca.sum1(_positive_part(tau * q_dot, smoothing)))
        out["effort_peak"] = GlobalIndex("effort_peak", effort, "largest actuator effort along the trajectory",
                                         "max", "min")
        out["effort_rms"] = GlobalIndex("effort_rms", square, "RMS of the actuator efforts over time and actuators",
                                        "rms", "min")
        out["energy"] = GlobalIndex("energy", power, "mechanical energy the actuators deliver along the trajectory, "
                                    "braking returned (with regeneration)", "integral", "min")
        out["energy_no_regeneration"] = GlobalIndex(
            "energy_no_regeneration", positive, "mechanical energy the actuators deliver along the trajectory, none "
            "returned (without regeneration)", "integral", "min")
        magnitude = replace(power, name="power_magnitude", formula=lambda tau, q_dot: ca.fabs(ca.dot(tau, q_dot)))
        out["power_peak"] = GlobalIndex("power_peak", magnitude, "largest magnitude of the actuators' total power "
                                        "along the trajectory", "max", "min")
    speed = motion("actuator_speed", "largest actuator rate |q_dot_i| at the motion", rate_unit,
                   lambda q_dot: ca.mmax(ca.fabs(q_dot)), ("q_dot",),
                   epigraph_upper=lambda q_dot, t: ca.vertcat(t - q_dot, t + q_dot))
    error = LocalIndex(
        "positioning_error", f"largest error of a pose coordinate from encoder resolutions {steps.tolist()}: max_j "
        "sum_i |J_f[j, i]| delta_i", pose_unit, 0.0, np.inf, np.inf,
        lambda J_f: ca.mmax(ca.fabs(J_f) @ ca.DM(steps)), "first_order", ("J_f",),
        epigraph_upper=_positioning_epigraph(steps), dimension=None, raw=True)
    out["actuator_speed_peak"] = GlobalIndex("actuator_speed_peak", speed, "largest actuator rate along the "
                                             "trajectory", "max", "min")
    out["positioning_error"] = GlobalIndex("positioning_error", error, "worst positioning error from the encoders' "
                                           "resolution along the trajectory", "max", "min")
    out["velocity_amplification"] = GlobalIndex("velocity_amplification", VELOCITY_MAX, "largest end-effector speed "
                                                "per unit actuator rates along the trajectory", "max", "min")
    return out


def joint_index(mech: Any, name: str) -> LocalIndex:
    """An actuated joint's value as a local index (SI, as the inverse kinematics gives it)."""
    if name not in mech.actuator_names:
        raise UnknownNameError(f"actuated joint of the {mech.name}", name, list(mech.actuator_names))
    k = mech.actuator_names.index(name)
    unit = mech.actuator_units[k]
    return LocalIndex(name, f"actuated joint {name} [{unit}] as the inverse kinematics gives it", unit, -np.inf,
                      np.inf, np.nan, lambda q: q[k], "inverse_kinematics", ("q",), dimension=None, raw=True)


def joint_extremes(mech: Any, name: str, where: str = "the task") -> tuple[GlobalIndex, GlobalIndex]:
    """The least and the largest value of an actuated joint over a region, two region extremes: its range is
    their difference."""
    local = joint_index(mech, name)
    return (GlobalIndex(f"{name}_least", local, f"the least {name} over {where}", "min", "max"),
            GlobalIndex(f"{name}_largest", local, f"the largest {name} over {where}", "max", "min"))


def require_reached(mech: Any, region: TrajectoryRegion, design: np.ndarray, *, mode: str | None = None,
                    resolution: int) -> None:
    """:class:`PoseError` naming the times and poses of the trajectory's nodes that the design does not reach
    in the working mode (assembled, as the quantities take them)."""
    times, poses, _ = region.nodes(resolution, "max")
    branch = mech.working_mode(mode)
    valid, _ = evaluate(first_order_outputs(mech, ("q",)), poses, np.array(branch.signs, dtype=float),
                        np.asarray(design, dtype=float))
    reached = valid[:, 0, 0] > 0
    if reached.all():
        return
    out = np.flatnonzero(~reached)
    shown = "; ".join(f"t = {times[k]:.4g} s at {np.round(poses[k], 6).tolist()}" for k in out[:SHOWN_POSES])
    more = f" and {len(out) - SHOWN_POSES} more" if len(out) > SHOWN_POSES else ""
    raise PoseError(f"the trajectory {region.name} leaves the workspace of the {mech.name} (working mode "
                    f"{branch.name}) at {len(out)} of its {len(poses)} nodes: {shown}{more}")


def trajectory_values(
    mech: Any, moves: Any, design: Any = None, *, mode: str | None = None, names: Sequence[str] | None = None,
    resolution: int = 8, gradient: bool = False, encoder: Sequence[float] | None = None,
) -> dict[str, Any]:
    """The trajectory quantities of a design along a move (or moves one after another, or a
    :class:`TrajectoryRegion`): by name, each a :class:`pkm.regions.GlobalValue` (extremes refined between the
    nodes), with ``gradient`` a pair (value, gradient in the design vector); ``joint_range_<actuator>`` for
    every actuator. :class:`PoseError` where the trajectory leaves the workspace."""
    from pkm.regions.quadrature import global_value

    region = moves if isinstance(moves, TrajectoryRegion) else trajectory_region(moves)
    vector = mech.design_vector(design)
    require_reached(mech, region, vector, mode=mode, resolution=resolution)
    indices = trajectory_indices(mech, encoder=encoder)
    ranges = {f"joint_range_{a}": joint_extremes(mech, a, region.name) for a in mech.actuator_names}
    wanted = list(indices) + list(ranges) if names is None else list(names)
    branch = mech.working_mode(mode)
    out = {}
    for name in wanted:
        if name not in indices and name not in ranges:
            raise UnknownNameError(f"trajectory quantity of the {mech.name}", name, [*indices, *ranges])
        parts = ranges.get(name, (indices.get(name),))
        values = [global_value(mech, spec, region, vector, branch=branch, resolution=resolution, gradient=gradient)
                  for spec in parts]
        if len(values) == 2:
            (least, d_least), (largest, d_largest) = values
            value = type(least)(float(largest) - float(least), points=least.points, region=region.name,
                                resolution=resolution, accuracy=least.accuracy + largest.accuracy)
            values = [(value, None if d_least is None else d_largest - d_least)]
        value, grad = values[0]
        out[name] = (value, grad) if gradient else value
    return out
