"""Helpers shared by the test files: random valid designs near the defaults, reachable poses of a
working mode, the inputs of the generated functions by port name, and machines described with chain legs.

pytest puts tests/ on ``sys.path`` (``pythonpath`` in pyproject.toml): test files import these with
``from helpers import ...``.
"""

from __future__ import annotations

import copy
import threading
import tomllib
from collections.abc import Callable, Iterable
from pathlib import Path
from typing import Any

import numpy as np

import pkm
from pkm.models.described import DESCRIPTIONS

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"

ATTEMPTS = 1000  # random designs drawn before giving up


def derived_by_hand() -> list[str]:
    """The registered mechanisms with a committed generated module (the others are described as data and
    derived into the cache)."""
    return [name for name in pkm.mechanisms() if not hasattr(pkm.load(name), "description")]


def random_design(
    mech: pkm.Mechanism,
    rng: np.random.Generator,
    *,
    spread: float = 0.2,
    names: Iterable[str] | None = None,
    accept: Callable[[pkm.Design], Any] | None = None,
) -> pkm.Design:
    """A valid design with each parameter (or each of ``names``; the others keep their defaults) drawn
    uniformly within +-``spread`` of its default: one draw per parameter per attempt, in parameter
    order, until the design is valid and ``accept(design)`` raises no :class:`pkm.DesignError`."""
    wanted = None if names is None else set(names)
    chosen = [p for p in mech.parameters if wanted is None or p.name in wanted]
    kept = {p.name: p.default for p in mech.parameters if p.required and p not in chosen}
    for _ in range(ATTEMPTS):
        values = {**kept, **{p.name: p.default * (1 + spread * rng.uniform(-1, 1)) for p in chosen}}
        try:
            design = mech.design(values)
            if accept is not None:
                accept(design)
        except pkm.DesignError:
            continue
        return design
    raise AssertionError(f"no valid {mech.name} design within {spread:.0%} of the defaults in {ATTEMPTS} draws")


def reachable_poses(
    mech: pkm.Mechanism,
    design: Any,
    mode: str,
    rng: np.random.Generator,
    *,
    count: int = 24,
    draws: int = 50,
    where: Callable[[np.ndarray], np.ndarray] | None = None,
) -> np.ndarray:
    """``count`` poses (count, n_out) that the working mode reaches, drawn uniformly in the workspace
    box (``draws`` x ``count`` candidates) and, with ``where``, kept where ``where(poses)`` (a mask)
    holds; fails the test when fewer are found."""
    box = mech.workspace_box(mech.design_vector(design))
    x = rng.uniform(box[:, 0], box[:, 1], size=(draws * count, len(box)))
    x = x[mech.reachable(x, design, mode=mode)]
    if where is not None:
        x = x[where(x)]
    x = x[:count]
    assert len(x) == count, f"{mech.name} {mode}: {len(x)} of {count} poses found in the workspace box"
    return x


def port_inputs(
    mech: pkm.Mechanism, design: Any, x: np.ndarray, mode: str, assembly: np.ndarray
) -> dict[str, np.ndarray]:
    """The inputs of the generated functions by the names of the port convention (pkm.kinematics) at
    poses x (N, n_out) of a working mode, with the assembly signs (N, k) of each pose; ``root`` (the
    variable of a forward-kinematics polynomial) runs over [-0.9, 0.9], ``y`` (the coordinates of a
    mapped region) takes the poses' values, ``a`` (the abscissa of a domain between curves) their
    first coordinate and ``wrench`` (a load on the platform) a fixed wrench per pose."""
    branch = mech.working_mode(mode)
    q = mech.inverse_kinematics(x, design, mode=branch.name, passive=True)
    return {
        "x": x,
        "q": q,
        "q_a": q[:, : mech.n_act],
        "mode": np.array(branch.signs),
        "assembly": np.asarray(assembly, dtype=float),
        "root": np.linspace(-0.9, 0.9, len(x))[:, None],
        "y": x,
        "a": x[:, :1],
        "wrench": np.outer(np.linspace(0.5, 1.5, len(x)), [10.0, -20.0, -500.0, 3.0, -2.0, 1.0]),
        "design": mech.design_vector(design),
    }


def inputs_by_port(mech: pkm.Mechanism, rng: np.random.Generator, n: int) -> dict[str, np.ndarray]:
    """Valid inputs (keys x, q, q_a, mode, assembly, design) of the generated functions at ``n`` poses:
    a random design within 20 % of the defaults, a random working mode, reachable poses in it and a
    random assembly mode per pose."""
    design = random_design(mech, rng, spread=0.2)
    mode = mech.working_modes[rng.integers(len(mech.working_modes))]
    x = reachable_poses(mech, design, mode.name, rng, count=n, draws=40)
    picks = rng.integers(len(mech.assembly_modes), size=len(x))
    assembly = np.array([mech.assembly_modes[k].signs for k in picks])
    return port_inputs(mech, design, x, mode.name, assembly)


DRAWN: dict[str, dict[str, list[str]]] = {}  # by paper, the text problems of each figure its quick run saved


def reproduce_quick(factory, key: str):
    """``pkm reproduce KEY --quick`` into a fresh folder: the report folder and its report.json. The text
    problems of every figure it saves through :func:`pkm.figures.save` (:func:`pkm.figures.text_problems`)
    are kept in DRAWN[key], by file name."""
    import json

    from pkm import figures
    from pkm.cli import main

    out = factory.mktemp("out")
    drawn, save = DRAWN.setdefault(key, {}), figures.save

    def checked(fig, path, *, dpi):
        drawn[Path(path).name] = figures.text_problems(fig)
        return save(fig, path, dpi=dpi)

    figures.save = checked
    try:
        assert main(["reproduce", key, "--out", str(out), "--quick"]) == 0
    finally:
        figures.save = save
    folder = out / key
    return folder, json.loads((folder / "report.json").read_text())


def check_figures_readable(key: str, data: dict) -> None:
    """Every figure of a quick reproduction was saved through pkm.figures.save and can be read: no text
    leaves the canvas or covers another text."""
    drawn = DRAWN[key]
    assert sorted(set(data["figures"]) - set(drawn)) == [], f"{key} saves figures without pkm.figures.save"
    assert {name: problems for name, problems in drawn.items() if problems} == {}


def check_docs_snapshot_paths(key: str, data: dict) -> None:
    """The docs' numbers of ``key`` (tests/test_paper_docs.py) name places that its quick report still
    writes (a list item may be missing: a quick run finds fewer, e.g. of the planes with re-entrant rays)."""
    import json

    from pkm.reproduce import docs

    snapshot = json.loads(docs.paths(key)[1].read_text())
    for path in snapshot["values"]:
        parts = path.split("/")
        lists = [k for k in range(1, len(parts)) if parts[k].isdigit()
                 and isinstance(docs.resolve(data, "/".join(parts[:k])), list)
                 and int(parts[k]) >= len(docs.resolve(data, "/".join(parts[:k])))]
        if lists:
            continue
        value = docs.resolve(data, path)
        assert value is None or isinstance(value, int | float), path


def benchmarks_section(heading: str) -> str:
    """The text of docs/benchmarks.md below ``heading`` up to the next section of its level, stripped."""
    text = (Path(__file__).resolve().parent.parent / "docs" / "benchmarks.md").read_text()
    start = text.index(heading + "\n") + len(heading)
    end = text.find("\n## ", start)
    return text[start : None if end < 0 else end].strip()


def rpr3_text(name: str, *, R: float, r: float, stroke: tuple[float, float],
              alpha: tuple[float, float, float] | None = None) -> str:
    """A planar 3-RPR's description (TOML): base and platform circles R and r, strokes within ``stroke``;
    its platform pattern in line with the base's, or turned by the parameter alpha (default, lower, upper)."""
    turn = "" if alpha is None else (f'  {{name = "alpha", default = {alpha[0]}, lower = {alpha[1]}, upper = '
                                     f'{alpha[2]}, unit = "rad", doc = "the platform pattern turned"}},\n')
    return f"""
name = "{name}"
doc = "planar 3-RPR"
frame = "planar"
home = [0, 0, 0]
characteristic_length = "r"
parameters = [
  {{name = "R", default = {R}, lower = 0.1, upper = 5, unit = "m", doc = "base circle"}},
  {{name = "r", default = {r}, lower = 0.05, upper = 5, unit = "m", doc = "platform circle"}},
{turn}]
[legs]
kind = "RPR"
count = 3
base = {{circle = "R", start = "pi/2"}}
platform = {{circle = "r", start = "pi/2{'' if alpha is None else ' + alpha'}"}}
range = [{stroke[0]}, {stroke[1]}]
"""


# a planar 3-RPR and a 3-PRR with sliders parallel to x, described by their legs' kinds
RPR3 = {
    "name": "rpr3", "doc": "planar 3-RPR", "frame": "planar", "home": [0, 0, 0], "characteristic_length": "r",
    "parameters": [
        {"name": "R", "default": 1.0, "lower": 0.1, "upper": 5, "unit": "m", "doc": "base circle"},
        {"name": "r", "default": 0.4, "lower": 0.05, "upper": 5, "unit": "m", "doc": "platform circle"},
    ],
    "legs": {"kind": "RPR", "count": 3, "base": {"circle": "R", "start": "pi/2"},
             "platform": {"circle": "r", "start": "pi/2"}, "range": [0.3, 1.5],
             "bodies": {"cylinder": {"mass": 1.0, "centre": 0.2, "inertia": 0.01},
                        "piston": {"mass": 0.5, "centre": 0.3, "inertia": 0.005}}},
    "platform": {"mass": 2.0, "centre": [0, 0], "inertia": 0.05},
}
PRR3 = {
    "name": "prr3", "doc": "planar 3-PRR, sliders parallel to x", "frame": "planar", "home": [0, 0, 0],
    "characteristic_length": "r",
    "parameters": [
        {"name": "R", "default": 1.0, "lower": 0.1, "upper": 5, "unit": "m", "doc": "base circle"},
        {"name": "r", "default": 0.3, "lower": 0.05, "upper": 5, "unit": "m", "doc": "platform circle"},
        {"name": "l", "default": 0.9, "lower": 0.05, "upper": 5, "unit": "m", "doc": "links"},
    ],
    "legs": {"kind": "PRR", "count": 3, "base": {"circle": "R", "start": "pi/2"},
             "platform": {"circle": "r", "start": "pi/2"}, "distal": "l", "axis": ["-1", "0"]},
}


FIVE_BAR_OF_RR_LEGS = {
    "name": "five_bar_described",
    "doc": "the symmetric planar 5R, described: two RR legs from the base ends to the end effector",
    "frame": "planar_point",
    "home": [0, "r1 + r2 / 2"],
    "modes": {"out_out": [1, -1], "out_in": [1, 1], "in_out": [-1, -1], "in_in": [-1, 1]},
    "parameters": [
        {"name": "r1", "default": 1.2, "lower": 0.01, "upper": 10, "unit": "m", "doc": "proximal links"},
        {"name": "r2", "default": 1.0, "lower": 0.01, "upper": 10, "unit": "m", "doc": "distal links"},
        {"name": "r3", "default": 0.8, "lower": 0.0, "upper": 10, "unit": "m", "doc": "half base"},
    ],
    "legs": {"kind": "RR", "count": 2, "base": [["-r3", 0], ["r3", 0]], "platform": [[0, 0], [0, 0]],
             "proximal": "r1", "distal": "r2"},
}

# the five-bar of RR legs with elastic elements (steel tubes, 1e4 N m/rad drives) and capsules of 5 cm: one
# description, derived once, for the stiffness's and the collisions' tests
FIVE_BAR_ELASTIC = {**FIVE_BAR_OF_RR_LEGS, "name": "five_bar_elastic",
                    "legs": {**FIVE_BAR_OF_RR_LEGS["legs"], "capsule": "0.05",
                             "elastic": {"material": "steel", "section": {"shape": "tube", "d": "0.02", "t": "0.002"},
                                         "drive": "10000.0"}}}

RR = [{"type": "R", "actuated": True, "link": ["r1", 0]}, {"type": "R", "link": ["r2", 0]}]
FIVE_BAR_OF_CHAINS = {
    "name": "five_bar_chains",
    "doc": "the symmetric planar 5R, its two legs given joint by joint",
    "frame": "planar_point",
    "home": [0, "r1 + r2 / 2"],
    "parameters": [
        {"name": "r1", "default": 1.2, "lower": 0.01, "upper": 10, "unit": "m", "doc": "proximal links"},
        {"name": "r2", "default": 1.0, "lower": 0.01, "upper": 10, "unit": "m", "doc": "distal links"},
        {"name": "r3", "default": 0.8, "lower": 0.0, "upper": 10, "unit": "m", "doc": "half base"},
    ],
    "legs": [
        {"kind": "chain", "base": [["-r3", 0]], "platform": [[0, 0]], "joints": RR,
         "branches": {"out": [1.6, -1.1], "in": [0.6, 1.1]}},
        {"kind": "chain", "base": [["r3", 0]], "platform": [[0, 0]], "joints": RR,
         "branches": {"out": [1.5, 1.1], "in": [2.5, -1.1]}},
    ],
}


def delta_of_chains() -> dict:
    """examples/delta_chains.toml: the Delta description's machine with each arm and parallelogram as a chain
    (the actuated revolute about the tangent, the arm, the parallelogram forearm, the platform's point joint),
    without bodies."""
    return tomllib.loads((EXAMPLES / "delta_chains.toml").read_text())


def rrr3_of_chains() -> dict:
    """The 3-RRR description with each leg as a chain in its frame turned to its base joint (x outwards):
    the actuated revolute, the proximal link, the elbow and the distal link; its branches named as the RR
    leg's (left: the elbow on the sign +1 of the two circles)."""
    raw = tomllib.loads(DESCRIPTIONS["rrr3"].read_text())
    legs = raw["legs"]
    raw["name"] = "rrr3_chains"
    raw["legs"] = {"kind": "chain", "count": 3, "base": legs["base"], "platform": legs["platform"],
                   "joints": [{"type": "R", "actuated": True, "link": ["l1", 0]}, {"type": "R", "link": ["l2", 0]}],
                   "branches": {"left": [-2.1, -2.1], "right": [2.1, 2.1]}}
    return raw


def five_bar_of_chains_with_bodies(values: dict) -> dict:
    """The five-bar of chains with the hand-written model's links as the bodies after its joints (Lara-Molina
    eqs. 13-19: masses, centres and moments about z)."""
    raw = copy.deepcopy(FIVE_BAR_OF_CHAINS)
    raw["name"] = "five_bar_chains_with_bodies"
    for table in raw["legs"]:
        for joint, k, length in zip(table["joints"], (1, 2), ("r1", "r2"), strict=True):
            mass, centre, ratio = (values[f"{n}{k}"] for n in ("m", "c", "g"))
            joint["body"] = {"mass": mass, "centre": [f"{centre!r} * {length}", 0],
                             "inertia": f"{ratio * mass!r} * {length}**2"}
    return raw


def delta_and_its_chains_with_bodies() -> tuple[dict, dict]:
    """The Delta description with its bodies and gravity, and its chains with the same bodies: the rotor on
    the actuated joint, the arm a bar turning about it, the parallelogram's rods (half their mass at either
    end in the description) a rod of their mass at its middle with the moment m L^2 / 4 across it, the
    platform's mass."""
    delta = tomllib.loads(DESCRIPTIONS["delta"].read_text())
    delta["name"] = "delta_with_gravity_for_chains"
    chains = delta_of_chains()
    chains["name"] = "delta_chains_with_bodies"
    chains["parameters"] = delta["parameters"]
    chains["platform"], chains["gravity"] = delta["platform"], delta["gravity"]
    arm, rods = chains["legs"]["joints"][:2]
    arm["rotor"] = "j_m"
    arm["body"] = {"mass": "m_a", "centre": ["L_a/2", 0, 0], "inertia": [0, "m_a*L_a**2/12", 0]}
    rods["body"] = {"mass": "m_b", "centre": ["L_b/2", 0, 0], "inertia": [0, "m_b*L_b**2/4", "m_b*L_b**2/4"]}
    return delta, chains


def assert_five_bar_torques(described: pkm.Mechanism, small: Any, x: np.ndarray, mode: str,
                            rng: np.random.Generator) -> None:
    """A described five-bar's actuated torques along random rates and accelerations at the poses x equal the
    hand-written chain model's to 1e-10 of the largest."""
    hand = pkm.load("five_bar")
    x_dot, x_ddot = rng.normal(size=(2, len(x), 2))
    mine = described.inverse_dynamics(x, x_dot, x_ddot, small, mode=mode)
    theirs = hand.inverse_dynamics(x, x_dot, x_ddot, hand.design(), mode=mode, joint_torques=True)
    scale = np.abs(theirs).max(axis=1, keepdims=True)
    np.testing.assert_allclose(mine / scale, theirs / scale, atol=1e-10, err_msg=mode)


def assert_forward_kinematics_returns_the_pose(m: pkm.Mechanism, x: np.ndarray) -> None:
    """At the poses x of the first working mode, each configuration's signature (its legs' sides, the sign of
    the type-II determinant) names the assembly modes whose solutions hold it: one of them returns the pose to
    1e-9."""
    q = m.inverse_kinematics(x, passive=True)
    signature = m.forward.seeds.signature(m.functions, q, x, m.design().vector())
    for signs in {tuple(s) for s in signature}:
        mine = np.all(signature == signs, axis=1)
        ranks = [a for a in m.assembly_modes if a.signs[:-1] == signs]
        found = np.stack([m.forward_kinematics(q[mine, : m.n_act], assembly=a.name) for a in ranks])
        errors = np.linalg.norm(found - x[mine], axis=2)
        assert np.nanmin(np.where(np.isnan(errors), np.inf, errors), axis=0).max() < 1e-9


def assert_five_bar_gci(described: pkm.Mechanism) -> tuple[dict, Any]:
    """A described five-bar's GCI and its design gradient in (r1, r2, r3) over a fixed disc (the hand-derived
    model's MIW at the default design, shrunk by 0.8) equal the hand-derived model's to 1e-10 and 1e-9, in
    the modes out_out and in_out; the disc and its placement's centre and radius."""
    hand = pkm.load("five_bar")
    design = hand.design()
    small = {n: design[n] for n in ("r1", "r2", "r3")}
    disc = hand.region("miw")
    centre, radius = (np.array(v).ravel() for v in disc.placement(hand.functions, design.vector()))
    for mode in ("out_out", "in_out"):
        fixed = disc.at(centre, 0.8 * radius)
        mine, mine_gradient = described.global_index("gci", small, region=fixed, mode=mode, gradient=True)
        theirs, their_gradient = hand.global_index("gci", design, region=fixed, mode=mode, gradient=True)
        assert abs(mine - theirs) <= 1e-10
        for name in small:
            assert abs(mine_gradient[name] - their_gradient[name]) <= 1e-9
    return {"shape": "disc", "centre": centre.tolist(), "size": [0.8 * float(radius[0])]}, design


def fuzz(examples: int):
    """Hypothesis's settings of the fuzz tests: ``examples`` drawn derandomized (a fixed seed), no example
    database, no deadline, no health check on slow or large draws."""
    from hypothesis import HealthCheck, settings

    return settings(max_examples=examples, derandomize=True, database=None, deadline=None,
                    suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large,
                                           HealthCheck.filter_too_much])


def watch_atlas(monkeypatch: Any) -> tuple[threading.Event, threading.Event]:
    """Events set when the explorer's atlas computes its first chunk of designs and when it ends (returns or
    is cancelled), by wrapping ``pkm.atlas._chunk`` and the explorer's ``compute_atlas``."""
    from pkm import atlas
    from pkm.explore import api

    started, ended = threading.Event(), threading.Event()
    chunk, compute_atlas = atlas._chunk, api.compute_atlas

    def first_chunk(*args: Any) -> Any:
        started.set()
        return chunk(*args)

    def watched(*args: Any, **options: Any) -> Any:
        try:
            return compute_atlas(*args, **options)
        finally:
            ended.set()

    monkeypatch.setattr(atlas, "_chunk", first_chunk)
    monkeypatch.setattr(api, "compute_atlas", watched)
    return started, ended
