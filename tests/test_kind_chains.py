"""Each named leg kind is the chain of joints its documentation states (pkm.spec.vocabulary.KINDS, each kind's
``chain``): the schema expands every leg of a kind into its chain's joints and checks them as a chain's, and the
chain closes wherever the kind's closed form reaches, with the kind's actuated joint. The chain is walked here in
numpy, joint by joint as docs/mechanisms.md states a chain's joints, apart from pkm's derivation."""

from __future__ import annotations

import math
import tomllib

import numpy as np
import pytest
from helpers import PRR3, RPR3
from scipy.optimize import least_squares

import pkm
from pkm import expressions
from pkm.models.described import DESCRIPTIONS
from pkm.spec.schema import describe
from pkm.spec.vocabulary import KINDS

# each kind's chain as its doc states it in words: the joints' types from the base, the actuated one starred
STATED = {
    "RR": ("R*", "R"),
    "RPR": ("R", "P*"),
    "PRR": ("P*", "R"),
    "R_parallelogram": ("R*", "parallelogram"),
    "UPS": ("U", "P*"),
}
WORDS = {"R": "revolute", "P": "prismatic", "U": "universal", "parallelogram": "parallelogram"}
MACHINES = {"RR": DESCRIPTIONS["rrr3"], "RPR": RPR3, "PRR": PRR3, "R_parallelogram": DESCRIPTIONS["delta"],
            "UPS": DESCRIPTIONS["stewart"]}


HELD_OFF = 2  # poses at which each leg's chain is also held 5% off its actuated joint (every start tried there)


def _raw(source):
    return tomllib.loads(source.read_text()) if hasattr(source, "read_text") else source


def test_every_kind_has_its_stated_chain():
    assert set(STATED) == set(KINDS)
    for kind, joints in STATED.items():
        words = [WORDS[j.rstrip("*")] for j in joints]
        doc = KINDS[kind].doc
        positions = [doc.find(w) for w in words]
        assert -1 not in positions, (kind, doc)
        assert positions == sorted(positions), (kind, doc)


@pytest.mark.parametrize("kind", sorted(STATED))
def test_the_schema_expands_each_kind_into_its_stated_chain(kind):
    description = describe(_raw(MACHINES[kind]))
    for leg in description.data["legs"]:
        assert leg["kind"] == kind
        assert tuple(j["type"] + "*" * j["actuated"] for j in leg["joints"]) == STATED[kind]


def _generators(axis: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The cross-product matrix K of the unit vector along ``axis`` and K @ K: a turn by an angle about the axis
    is I + sin(angle) K + (1 - cos(angle)) K @ K (Rodrigues' formula)."""
    u = axis / np.linalg.norm(axis)
    cross = np.array([[0.0, -u[2], u[1]], [u[2], 0.0, -u[0]], [-u[1], u[0], 0.0]])
    return cross, cross @ cross


def _turn(generators: tuple[np.ndarray, np.ndarray], angle: float) -> np.ndarray:
    cross, square = generators
    return np.eye(3) + math.sin(angle) * cross + (1 - math.cos(angle)) * square


def _rotation(axis: np.ndarray, angle: float) -> np.ndarray:
    return _turn(_generators(axis), angle)


Joint = tuple[str, list, np.ndarray]


def _numeric(joints: list[dict], design: dict, planar: bool) -> list[Joint]:
    """A chain's joints as (type, axes, link) in numbers at the design, evaluated once per leg rather than at
    each step of the least squares: a P's one axis (a unit vector), an R's or U's axes (a planar R's the z axis)
    by their :func:`_generators`, a link."""

    def vec(trees: list) -> np.ndarray:
        return np.array([float(expressions.evaluate(t, design)) for t in trees] + [0.0] * planar)

    def axes(joint: dict) -> list:
        if joint["type"] == "P":
            axis = vec(joint["axis"])
            return [axis / np.linalg.norm(axis)]
        return [_generators(np.array([0.0, 0.0, 1.0]) if planar else vec(axis)) for axis in joint["axes"]]

    return [(joint["type"], axes(joint), vec(joint["link"])) for joint in joints]


def _end(joints: list[Joint], a: np.ndarray, values: np.ndarray) -> np.ndarray:
    """The end of a chain (its joints by :func:`_numeric`) from a (the base's frame, turn 0): a P slides along
    its axis, an R (U) turns about its axis (axes, the second in the frame the first turns), a parallelogram
    turns its link like a U and keeps the frame before it; each link in the frame of the joint it follows."""
    planar = a.size == 2
    point, rotation, values = np.append(a, 0.0) if planar else a.copy(), np.eye(3), iter(values)
    for kind, axes, link in joints:
        turned = rotation
        if kind == "P":
            point = point + rotation @ axes[0] * next(values)
        else:
            for generators in axes:
                turned = turned @ _turn(generators, next(values))
        point = point + turned @ link
        if kind != "parallelogram":
            rotation = turned
    return point[:2] if planar else point


def _platform_point(frame: str, x: np.ndarray, c: np.ndarray) -> np.ndarray:
    if frame == "planar":
        return x[:2] + np.array([[math.cos(x[2]), -math.sin(x[2])], [math.sin(x[2]), math.cos(x[2])]]) @ c
    if frame == "spatial":
        roll, pitch, yaw = x[3:]
        rotation = (_rotation(np.array([0.0, 0, 1]), yaw) @ _rotation(np.array([0.0, 1, 0]), pitch)
                    @ _rotation(np.array([1.0, 0, 0]), roll))
        return x[:3] + rotation @ c
    return x[: c.size] + c


@pytest.mark.parametrize("kind", sorted(STATED))
def test_each_kinds_chain_closes_where_the_kind_reaches_with_its_actuated_joint(kind):
    """At poses the kind's closed form reaches, its actuated joint held, the chain's passive joints close it
    (least squares from a few starts) to 1e-9 m; and held 5% off at the first HELD_OFF of them, they do not: the
    chain is the kind's. A chain that closes held off has more freedom than its kind, which its joints' types and
    axes give it at every pose near home alike, so that the other poses check the closing alone."""
    m = pkm.load(_raw(MACHINES[kind]))
    data = m.description.data
    design = {name: m.design()[name] for name in m.parameter_names()}
    home = np.asarray(m.functions["home"](m.design().vector()), dtype=float).ravel()
    rng = np.random.default_rng(3)
    scale = np.where(np.array(data["pose"]["units"]) == "rad", 0.1, 0.05 * max(design.values()))
    x = home + rng.uniform(-1, 1, size=(12, home.size)) * scale
    q = m.inverse_kinematics(x)
    reached = np.isfinite(q).all(axis=1)
    assert reached.sum() >= 6
    for n, (pose, joints) in enumerate(zip(x[reached][:6], q[reached][:6], strict=True)):
        for k, leg in enumerate(data["legs"]):
            a = np.array([float(expressions.evaluate(t, design)) for t in leg["base"]])
            c = _platform_point(data["pose"]["frame"], pose,
                                np.array([float(expressions.evaluate(t, design)) for t in leg["platform"]]))
            sizes = [1 if j["type"] in ("R", "P") else 2 for j in leg["joints"]]
            at = sum(sizes[: next(i for i, j in enumerate(leg["joints"]) if j["actuated"])])
            count = sum(sizes)
            chain = _numeric(leg["joints"], design, a.size == 2)
            for actuated, closes in ((joints[k], True), (joints[k] * 1.05, False))[: 2 if n < HELD_OFF else 1]:

                def residual(passive, actuated=actuated, at=at, chain=chain, a=a, c=c):
                    return _end(chain, a, np.concatenate((passive[:at], [actuated], passive[at:]))) - c

                # the first start that closes the chain ends the search; held off, every start is tried
                for start in rng.uniform(-math.pi, math.pi, size=(8, count - 1)):
                    best = least_squares(residual, start, xtol=1e-15, ftol=1e-15, gtol=1e-15)
                    if np.abs(best.fun).max() < 1e-9:
                        break
                assert (np.abs(best.fun).max() < 1e-9) == closes, (kind, k, actuated, best.fun)

