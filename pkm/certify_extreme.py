"""A local index's largest (or least) value over a region, certified from both sides (:mod:`pkm.certify`): a pose of
the region where the index takes ``found`` (so the extreme is at least that), and a bound ``proved`` that branch and
prune proves the index never passes anywhere in the region, within a stated relative gap of ``found``.

The index is sampled at points of the region's reference box (inside its round part), its largest value ``found``;
then the region is certified for index <= found (1 + gap) (for the least value, >= found (1 - gap)): proved, the
bound is ``proved``; refuted, the witness is a pose where the index passes that bound, which becomes ``found``, and
the next bound is tried; undecided (boxes left at the depth or the budget spent), nothing is proved, and the
extreme's certificate says so. The index is any local index of the machine (a name, or an index object such as an
error model's pose error, :meth:`pkm.accuracy.ErrorModel.index`) whose graph the enclosures can walk."""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field
from typing import Any

import casadi as ca
import numpy as np

from pkm import regions
from pkm.certify import DEPTH, MAX_BOXES, SECONDS, _Domain, _inside, _round_axes, checked, placed, search
from pkm.errors import PkmError
from pkm.intervals import enclosure

SAMPLES = 4096  # points of the reference box the index is sampled at first
STEPS = 12  # certifications at most, each after a witness beyond the last bound


@dataclass
class CertifiedExtreme:
    """``found``: the index's value at ``pose`` in the region; ``proved``: a bound the index is proved not to pass
    in the region (None where no certification proved one); ``steps``: each bound tried with its verdict, boxes
    and time."""

    mechanism: str
    region: str
    mode: str
    design: dict[str, float]
    index: str
    unit: str
    sense: str
    found: float
    pose: dict[str, float]
    proved: float | None
    gap: float
    steps: list[dict[str, Any]] = field(default_factory=list)
    seconds: float = 0.0

    def as_dict(self) -> dict[str, Any]:
        return {k: getattr(self, k) for k in ("mechanism", "region", "mode", "design", "index", "unit", "sense",
                                              "found", "pose", "proved", "gap", "steps", "seconds")}


def certified_extreme(mech: Any, index: Any, region: Any, design: Any = None, *, sense: str = "max",
                      mode: str | None = None, gap: float = 0.05, depth: int = DEPTH, max_boxes: int = MAX_BOXES,
                      seconds: float = SECONDS) -> CertifiedExtreme:
    """The largest (``sense`` "max") or least ("min") value of the local index over the region at the design in the
    working mode, certified from both sides within the relative ``gap`` (module docstring); ``depth``,
    ``max_boxes`` and ``seconds`` each certification's budget."""
    if sense not in ("max", "min"):
        raise PkmError(f"sense violates: max or min; got {sense!r}")
    if not (isinstance(gap, int | float) and 0 < gap < 1):
        raise PkmError(f"gap violates: a relative gap in (0, 1); got {gap!r}")
    spec = mech.local_spec(index)
    task = checked(mech, region, design, properties=("limits",), mode=mode)
    u, d, x = placed(mech, task)
    (value,) = regions.pipeline(mech, (spec,))(x, ca.DM(mech.working_mode(task.mode).signs), d)[3:]
    sign = 1.0 if sense == "min" else -1.0  # the certified graph: at least its limit where the bound holds
    g = ca.Function("certified", [u], [sign * value])
    slope = enclosure(ca.Function("certified_gradient", [u], [ca.densify(ca.jacobian(g(u), u))]))
    pose, round_axes = ca.Function("certified_pose", [u], [x]), _round_axes(task.shape)
    started = time.perf_counter()
    at, least = _sampled(g, task.dimension, round_axes)
    found = sign * least
    steps: list[dict[str, Any]] = []
    proved = None
    for _ in range(STEPS):
        if found == 0.0:
            raise PkmError(f"index violates: a nonzero {sense} for a relative gap; {spec.name} is 0 at "
                           f"{np.asarray(pose(at), dtype=float).ravel().tolist()}")
        bound = found - sign * gap * abs(found)
        domain = _Domain(enclosure(g), slope, g, pose, [spec.name], round_axes, np.array([sign * bound]))
        result = search(mech, domain, depth=depth, max_boxes=max_boxes, seconds=seconds)
        steps.append({"bound": bound, **{k: result[k] for k in ("verdict", "boxes", "undecided", "seconds")}})
        if result["verdict"] == "proved":
            proved = bound
            break
        if result["verdict"] != "refuted":
            break
        at = np.asarray(result["witnesses"][0]["u"], dtype=float)
        found = sign * float(np.asarray(g(at)).ravel()[0])
    x_at = dict(zip(mech.pose_names, np.asarray(pose(at), dtype=float).ravel().tolist(), strict=True))
    return CertifiedExtreme(mech.name, regions.region_name(task.shape), task.mode, mech.design_dict(task.design),
                            spec.name, mech.index_unit(spec), sense, found, x_at, proved, gap, steps,
                            time.perf_counter() - started)


def _sampled(g: ca.Function, dim: int, round_axes: list[int]) -> tuple[np.ndarray, float]:
    """The point of SAMPLES in the reference box (within its round part, and its centre) where g is least, and g
    there."""
    points = np.random.default_rng(0).uniform(-1.0, 1.0, (SAMPLES, dim))
    points = np.vstack([np.zeros(dim), points[[_inside(p, round_axes) for p in points]]])
    values = np.asarray(g.map(len(points))(points.T), dtype=float).ravel()
    if not np.isfinite(values).any():
        raise PkmError("region violates: a point where the index has a value, among the points sampled")
    k = int(np.argmin(np.where(np.isfinite(values), values, math.inf)))
    return points[k], float(values[k])
