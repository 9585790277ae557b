"""The Extended URDF export (pkm.export), checked by Pinocchio: each export loaded with its closures as
Gepetto's loader reads them, its closed-loop kinematics solved at random reachable poses by continuation from
the reference configuration, and the actuated joints, the Jacobian and (where the mechanism has bodies) the
actuated-space inertia compared with pkm's. Pinocchio (``pin`` on PyPI) is an optional test dependency: these
tests skip without it, and fail without it where PKM_REQUIRE_PINOCCHIO=1."""

from __future__ import annotations

import itertools
import json
import math
import os
import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pytest
import yaml
from helpers import (
    FIVE_BAR_OF_CHAINS,
    FIVE_BAR_OF_RR_LEGS,
    delta_and_its_chains_with_bodies,
    delta_of_chains,
    five_bar_of_chains_with_bodies,
    rrr3_of_chains,
)

import pkm
from pkm.cli import main
from pkm.errors import DesignError, PkmError, PoseError, UnknownNameError
from pkm.export import structure

try:
    import pinocchio as pin
except ImportError:
    pin = None

REQUIRED = os.environ.get("PKM_REQUIRE_PINOCCHIO") == "1"
DATA = Path(__file__).resolve().parent / "data"
POSES = 20  # random reachable poses per working mode
STEPS = 4  # continuation steps from the reference pose to each pose
TOLERANCE = 1e-9


@pytest.fixture
def pinocchio():
    if pin is None:
        if REQUIRED:
            pytest.fail("PKM_REQUIRE_PINOCCHIO=1 but pinocchio (pip install pin) is not importable")
        pytest.skip("pinocchio (pip install pin) is not installed: the optional test dependency of the URDF export")
    return pin


@dataclass
class Loaded:
    """An export loaded as Gepetto's completeRobotLoader reads it: the tree, its constraints and motors."""

    model: object
    data: object
    constraints: list
    constraint_data: list
    frames: list[tuple[int, int]]
    motors: list[int]
    offsets: np.ndarray
    effector: int
    spec: dict

    @classmethod
    def of(cls, folder: Path) -> Loaded:
        model = pin.buildModelFromUrdf(str(folder / "robot.urdf"), mimic=True)
        spec = yaml.safe_load((folder / "robot.yaml").read_text())
        constraints, frames = [], []
        for (a, b), kind in zip(spec["closed_loop"], spec["type"], strict=True):
            frames.append((model.getFrameId(a), model.getFrameId(b)))
            fa, fb = (model.frames[f] for f in frames[-1])
            contact = pin.ContactType.CONTACT_3D if kind == "3d" else pin.ContactType.CONTACT_6D
            constraints.append(pin.RigidConstraintModel(contact, model, fa.parentJoint, fa.placement,
                                                        fb.parentJoint, fb.placement, pin.ReferenceFrame.LOCAL))
        return cls(model, model.createData(), constraints, [c.createData() for c in constraints], frames,
                   [model.getJointId(name) for name in spec["name_mot"]], np.array(spec["pkm"]["offset"]),
                   model.getFrameId(spec["pkm"]["effector"]), spec)

    def update(self, q: np.ndarray) -> None:
        zero = np.zeros(self.model.nv)
        pin.forwardKinematics(self.model, self.data, q, zero, zero)
        pin.computeJointJacobians(self.model, self.data, q)
        pin.updateFramePlacements(self.model, self.data)
        for c, d in zip(self.constraints, self.constraint_data, strict=True):
            c.calc(self.model, self.data, d)

    def closure(self) -> tuple[np.ndarray, np.ndarray]:
        """The closures' residual (frame B's origin less frame A's, and for 6d the rotation from A to B, in the
        base frame) and its Jacobian from the frames' Jacobians, at the last update. (Pinocchio 4.1's
        RigidConstraintModel.jacobian misplaces the columns after a mimic joint: the frames' are right.)"""
        residuals, rows = [], []
        for c, d, (a, b) in zip(self.constraints, self.constraint_data, self.frames, strict=True):
            rotation = self.data.oMf[a].rotation
            J = [pin.getFrameJacobian(self.model, self.data, f, pin.ReferenceFrame.LOCAL_WORLD_ALIGNED) for f in (a, b)]
            residuals.append(rotation @ d.c1Mc2.translation)
            rows.append(J[1][:3] - J[0][:3])
            if c.type == pin.ContactType.CONTACT_6D:
                residuals.append(rotation @ pin.log3(d.c1Mc2.rotation))
                rows.append(J[1][3:] - J[0][3:])
        return np.concatenate(residuals), np.vstack(rows)

    def effector_rows(self, oriented: bool) -> tuple[np.ndarray, np.ndarray]:
        """The effector frame's placement and its Jacobian rows (base frame) that the pose fixes."""
        J = pin.getFrameJacobian(self.model, self.data, self.effector, pin.ReferenceFrame.LOCAL_WORLD_ALIGNED)
        return self.data.oMf[self.effector], J if oriented else J[:3]

    def actuated(self, q: np.ndarray) -> np.ndarray:
        out = []
        for jid in self.motors:
            joint = self.model.joints[jid]
            value = q[joint.idx_q] if joint.nq == 1 else math.atan2(q[joint.idx_q + 1], q[joint.idx_q])
            out.append(value)
        return np.array(out) + self.offsets

    def mass_matrix(self, q: np.ndarray) -> np.ndarray:
        """M = sum over the bodies of J_i^T I_i J_i (J_i the body's velocity Jacobian in its frame): Pinocchio
        4.1's crba is wrong where a mimic joint has bodies below it (its kinetic energy differs from the bodies'
        velocities'), so it is checked against this sum only without mimic joints."""
        self.update(q)
        M = np.zeros((self.model.nv, self.model.nv))
        for i in range(1, self.model.njoints):
            J = pin.getJointJacobian(self.model, self.data, i, pin.ReferenceFrame.LOCAL)
            M += J.T @ self.model.inertias[i].matrix() @ J
        if not any(j.shortname() == "JointModelMimic" for j in self.model.joints):
            crba = pin.crba(self.model, self.data, q)
            assert np.allclose(np.triu(crba) + np.triu(crba, 1).T, M, rtol=1e-12, atol=1e-12)
        return M

    def selection(self) -> np.ndarray:
        S = np.zeros((len(self.motors), self.model.nv))
        for row, jid in enumerate(self.motors):
            S[row, self.model.joints[jid].idx_v] = 1.0
        return S


def _target_error(placement, target: np.ndarray, oriented: bool) -> np.ndarray:
    position = placement.translation - target[:3, 3]
    if not oriented:
        return position
    return np.concatenate([position, target[:3, :3] @ pin.log3(target[:3, :3].T @ placement.rotation)])


def solve(loaded: Loaded, effector, q: np.ndarray, target: np.ndarray, tolerance: float) -> tuple[np.ndarray, float]:
    """Newton's method (least-norm steps) on the closures and the effector's placement from ``q``."""
    error = math.inf
    for _ in range(30):
        loaded.update(q)
        h, K = loaded.closure()
        placement, E = loaded.effector_rows(effector.oriented)
        r = np.concatenate([h, _target_error(placement, target, effector.oriented)])
        error = float(np.abs(r).max())
        if error < tolerance:
            break
        step = np.linalg.lstsq(np.vstack([K, E]), r, rcond=None)[0]
        q = pin.integrate(loaded.model, q, -step)
    return q, error


def null_space(K: np.ndarray) -> np.ndarray:
    _, s, vt = np.linalg.svd(K)
    rank = int(np.sum(s > 1e-10 * max(1.0, s.max(initial=0.0))))
    return vt[rank:].T


def first_order(loaded: Loaded, effector, q: np.ndarray, pose: np.ndarray) -> tuple[np.ndarray, np.ndarray, int]:
    """J (q_a_dot = J x_dot) and P = dq/dq_a along the closed loops at a closed configuration, and the
    mechanism's degrees of freedom there (the closures' null space)."""
    loaded.update(q)
    _, K = loaded.closure()
    N = null_space(K)
    _, E = loaded.effector_rows(effector.oriented)
    rows = effector.rates(pose)[: E.shape[0]]
    X = np.linalg.lstsq(rows, E @ N, rcond=None)[0]  # pose rates of the null space's directions
    SN = loaded.selection() @ N
    return SN @ np.linalg.inv(X), N @ np.linalg.inv(SN), N.shape[1]


def sample(m, design, mode: str, reference: np.ndarray, rng) -> np.ndarray:
    """Up to POSES poses near the reference pose that the working mode reaches along a straight path from it,
    away from singularities (the sign of both determinants kept, their size at least a tenth of the
    reference's)."""
    box = m.workspace_box(m.design_vector(design))
    width = box[:, 1] - box[:, 0]
    det_ref = m.singularity(reference, design, mode=mode)
    poses = []
    for _ in range(40):
        x = reference + 0.15 * width * rng.uniform(-1, 1, size=len(reference))
        path = reference + np.linspace(0, 1, 9)[:, None] * (x - reference)
        if not m.reachable(path, design, mode=mode, limits=False).all():
            continue
        dets = m.singularity(path, design, mode=mode)
        if all(np.all(np.sign(dets[k]) == np.sign(det_ref[k])) and np.all(np.abs(dets[k]) > 0.1 * abs(det_ref[k]))
               for k in dets):
            poses.append(x)
        if len(poses) == POSES:
            break
    assert len(poses) >= POSES // 2, f"{m.name} {mode}: {len(poses)} poses near the reference"
    return np.array(poses)


def reference_pose(m, design, mode: str, rng) -> np.ndarray | None:
    """None (the export's own reference pose) where the working mode reaches it and it is not singular (the
    export refuses a singular one: the passive leg's home pose in out_in), else the random pose it reaches
    farthest from both singularities (the larger of the two margins' least)."""
    try:
        built = structure(m, design, mode=mode)
    except PoseError:
        pass
    else:
        if not m.singularity_note(built.reference.pose, design, mode=mode):
            return None
    box = m.workspace_box(m.design_vector(design))
    x = rng.uniform(box[:, 0], box[:, 1], size=(4000, len(box)))
    x = x[m.reachable(x, design, mode=mode)]
    margins = [m.local_index(f"singularity_margin_type{k}", x, design, mode=mode) for k in (1, 2)]
    return x[np.argmax(np.minimum(*margins))]


def check_export(m, design, mode: str, folder: Path, rng) -> dict[str, float]:
    """Export, load, solve at random poses; the largest differences from pkm's q_a, J and M_t."""
    pose = reference_pose(m, design, mode, rng)
    m.export_urdf(design, folder, pose=pose, mode=mode)
    s = structure(m, design, pose=pose, mode=mode)
    loaded = Loaded.of(folder)
    q0 = pin.neutral(loaded.model)
    loaded.update(q0)
    assert np.abs(loaded.closure()[0]).max() < 1e-12, "the reference configuration closes every loop"
    reference = s.reference.pose
    poses = sample(m, design, mode, reference, rng)
    qa_pkm = m.inverse_kinematics(poses, design, mode=mode, limits=False)
    J_pkm = m.jacobian(poses, design, mode=mode)
    inertia = "inertia" in m.functions
    M_pkm = m.inertia_matrix(poses, design, mode=mode, space="actuated") if inertia else None
    errors = {"q_a": 0.0, "J": 0.0, "M_t": 0.0}
    for k, x in enumerate(poses):
        q = q0
        for step in range(1, STEPS + 1):
            target = s.effector.frame(reference + step / STEPS * (x - reference))
            q, residual = solve(loaded, s.effector, q, target, 1e-13 if step == STEPS else 1e-9)
        assert residual < 1e-12, f"{m.name} {mode}: Newton did not close the loops at {x} ({residual:.1e})"
        qa = loaded.actuated(q)
        angles = np.array([u == "rad" for u in m.actuator_units])
        diff = qa - qa_pkm[k]
        diff[angles] = (diff[angles] + math.pi) % (2 * math.pi) - math.pi
        errors["q_a"] = max(errors["q_a"], float(np.abs(diff).max()))
        J, P, freedom = first_order(loaded, s.effector, q, x)
        assert freedom == m.n_out, f"{m.name}: {freedom} degrees of freedom, not {m.n_out}"
        errors["J"] = max(errors["J"], float(np.abs(J - J_pkm[k]).max() / max(1.0, np.abs(J_pkm[k]).max())))
        if inertia:
            M_t = P.T @ loaded.mass_matrix(q) @ P
            errors["M_t"] = max(errors["M_t"], float(np.abs(M_t - M_pkm[k]).max() / max(1.0, np.abs(M_pkm[k]).max())))
    return errors


CASES = [
    ("five_bar", None, ("out_out", "out_in", "in_out", "in_in")),
    ("slider_gantry", None, ("below", "above")),
    ("slider_gantry_symmetric", None, ("below", "above")),
    ("passive_leg", None, ("out_out", "out_in", "in_out", "in_in")),
    ("ups_pu", None, ("legs",)),
    ("rrr3", None, tuple("_".join(sides) for sides in itertools.product(("left", "right"), repeat=3))),
    ("delta", None, ("elbow_out", "elbow_in")),
    ("stewart", None, ("single",)),
]


@pytest.mark.parametrize(("name", "design", "modes"), CASES, ids=[c[0] for c in CASES])
def test_export_agrees_with_pkm_in_pinocchio(pinocchio, tmp_path, name, design, modes):
    assert_export_agrees(pkm.load(name), design, modes, tmp_path)


def assert_export_agrees(m, design, modes, folder: Path) -> None:
    """q_a, J and M_t of the export in Pinocchio against pkm's, in each working mode (:func:`check_export`)."""
    rng = np.random.default_rng(28)
    for mode in modes:
        errors = check_export(m, design, mode, folder / mode, rng)
        assert errors["q_a"] < TOLERANCE, (mode, errors)
        assert errors["J"] < TOLERANCE, (mode, errors)
        assert errors["M_t"] < TOLERANCE, (mode, errors)


def test_bad_input_is_refused_naming_it(tmp_path):
    m = pkm.load("five_bar")
    with pytest.raises(UnknownNameError, match="unknown mechanism 'nothing'"):
        pkm.load("nothing").export_urdf(None, tmp_path / "out")
    with pytest.raises(DesignError, match="r1"):
        m.export_urdf({"r1": -1.0, "r2": 1.0, "r3": 0.8}, tmp_path / "out")
    with pytest.raises(DesignError, match="nothing"):
        m.export_urdf({"nothing": 1.0}, tmp_path / "out")
    with pytest.raises(PkmError, match=r"pose .* reaches"):
        m.export_urdf(None, tmp_path / "out", pose=[0.0, 10.0])
    blocked = tmp_path / "file"
    blocked.write_text("a file, not a folder")
    with pytest.raises(PkmError, match=re.escape(f"folder '{blocked / 'out'}' violates: a folder that can be "
                                                 "written")):
        m.export_urdf(None, blocked / "out")
    assert not (tmp_path / "out").exists()
    assert blocked.read_text() == "a file, not a folder"


def test_a_mechanism_without_a_structure_is_refused(tmp_path):
    m = pkm.load("five_bar")
    bare = type("Bare", (type(m),), {"structure": None})()
    with pytest.raises(PkmError, match="mechanism five_bar violates: a mechanism whose structure"):
        bare.export_urdf(None, tmp_path / "out")


def _gepetto_five_bar(pinocchio) -> tuple[object, dict[str, int]]:
    """Gepetto's five-bar linkage as its robot.urdf places its joints (tests/data, with the source named)."""
    data = json.loads((DATA / "gepetto_5bar_linkage.json").read_text())
    model, joint_of = pinocchio.Model(), {}
    pending = list(data["joints"])
    links = {"built": 0}
    while pending:
        joint = next(j for j in pending if j["parent"] in links)
        pending.remove(joint)
        assert joint["axis"] == [0.0, 0.0, 1.0]
        placement = pinocchio.SE3(pinocchio.rpy.rpyToMatrix(np.array(joint["rpy"])), np.array(joint["xyz"]))
        joint_of[joint["name"]] = links[joint["child"]] = model.addJoint(links[joint["parent"]],
                                                                         pinocchio.JointModelRZ(), placement,
                                                                         joint["name"])
    return model, joint_of


def test_gepetto_five_bar_dimensions_reproduce_its_joint_placements(pinocchio, tmp_path):
    """Gepetto's five-bar has r1 = r2 = 0.46 m and a base of 0.3 m (the distances between its joints' axes):
    the export of those dimensions, at its reference configuration, puts every joint where Gepetto's robot.urdf
    puts it at the same link angles, to 1e-12 in the plane of the linkage (Gepetto's links are stacked in layers
    along the joints' axes, pkm's lie in one plane)."""
    theirs, joint = _gepetto_five_bar(pinocchio)
    data = theirs.createData()
    pinocchio.forwardKinematics(theirs, data, pinocchio.neutral(theirs))
    at = {name: data.oMi[j].translation.copy() for name, j in joint.items()}
    axis = data.oMi[joint["mot1"]].rotation[:, 2]
    assert all(np.allclose(data.oMi[j].rotation[:, 2], axis, atol=1e-12) for j in joint.values())
    x_axis = unit_in_plane(at["mot2"] - at["mot1"], axis)
    to_plane = np.array([x_axis, np.cross(axis, x_axis)])  # their space -> pkm's plane, the base's centre at 0
    centre = (at["mot1"] + at["mot2"]) / 2

    def planar(point):
        return to_plane @ (point - centre)

    def length(a, b):
        return float(np.linalg.norm(planar(at[b]) - planar(at[a])))

    design = {"r1": length("mot1", "free1"), "r2": length("free1", "closedloop1_A"),
              "r3": length("mot1", "mot2") / 2}
    assert design == pytest.approx({"r1": 0.46, "r2": 0.46, "r3": 0.15}, abs=1e-15)
    assert length("mot2", "free2") == pytest.approx(design["r1"], abs=1e-15)
    assert length("free2", "closedloop1_B") == pytest.approx(design["r2"], abs=1e-15)
    m = pkm.load("five_bar")
    m.export_urdf(design, tmp_path / "gepetto")
    ours = Loaded.of(tmp_path / "gepetto")
    ours.update(pinocchio.neutral(ours.model))
    placed = {name: ours.data.oMi[ours.model.getJointId(name)].translation for name in
              ("theta1", "theta2", "elbow1", "elbow2")}
    placed |= {name: ours.data.oMf[ours.model.getFrameId(name)].translation for name in ("end_A", "end_B")}
    assert max(abs(p[2]) for p in placed.values()) == 0.0

    def angle(a, b, points):
        d = points[b] - points[a]
        return math.atan2(d[1], d[0])

    theirs_zero = {name: planar(p) for name, p in at.items()}
    q = pinocchio.neutral(theirs)
    for k in (1, 2):
        proximal = angle(f"theta{k}", f"elbow{k}", placed)
        distal = angle(f"elbow{k}", "end_A", placed)
        q[theirs.joints[joint[f"mot{k}"]].idx_q] = proximal - angle(f"mot{k}", f"free{k}", theirs_zero)
        end = "closedloop1_A" if k == 1 else "closedloop1_B"
        q[theirs.joints[joint[f"free{k}"]].idx_q] = (distal - proximal) - (angle(f"free{k}", end, theirs_zero)
                                                           - angle(f"mot{k}", f"free{k}", theirs_zero))
    pinocchio.forwardKinematics(theirs, data, q)
    pairs = {"mot1": "theta1", "mot2": "theta2", "free1": "elbow1", "free2": "elbow2", "closedloop1_A": "end_A",
             "closedloop1_B": "end_B"}
    gap = max(float(np.abs(planar(data.oMi[joint[g]].translation) - placed[p][:2]).max()) for g, p in pairs.items())
    assert gap < 1e-12, gap


def unit_in_plane(vector: np.ndarray, normal: np.ndarray) -> np.ndarray:
    v = vector - normal * (normal @ vector)
    return v / np.linalg.norm(v)


MIXED = {
    "name": "export_mixed",
    "doc": "a planar 3-DOF machine with an RPR, a PRR and an RR leg, every body given",
    "frame": "planar",
    "home": [0, 0.3, 0],
    "characteristic_length": "a",
    "parameters": [
        {"name": "a", "default": 0.6, "lower": 0.1, "upper": 2.0, "unit": "m", "doc": "link length"},
        {"name": "m", "default": 2.0, "lower": 0.0, "upper": 10.0, "unit": "kg", "doc": "link mass"},
    ],
    "legs": [
        {"kind": "RPR", "base": [[-1, 0]], "platform": [[-0.2, 0]], "range": [0.3, 1.5],
         "bodies": {"cylinder": {"mass": "m", "centre": 0.2, "inertia": "m*0.16/12"},
                    "piston": {"mass": "m/2", "centre": 0.15, "inertia": "m*0.01"}}},
        {"kind": "PRR", "base": [[0.6, -0.5]], "platform": [[0.2, 0]], "axis": [0, 1], "distal": 0.5,
         "bodies": {"slider": {"mass": "3*m"}, "distal": {"mass": "m", "centre": 0.25, "inertia": "m*0.25/12"}}},
        {"kind": "RR", "base": [[0, 1.2]], "platform": [[0, 0.2]], "proximal": "a", "distal": "a",
         "bodies": {"rotor": 0.01, "proximal": {"mass": "m", "centre": "a/2", "inertia": "m*a**2/12"},
                    "distal": {"mass": "m", "centre": "a/3", "inertia": "m*a**2/10"}}},
    ],
    "platform": {"mass": "2*m", "centre": [0.05, 0.02], "inertia": 0.05},
}


def test_prismatic_legs_and_their_bodies_agree_with_pkm_in_pinocchio(pinocchio, tmp_path):
    m = pkm.load(MIXED)
    assert_export_agrees(m, None, m.modes[:2], tmp_path)


@pytest.mark.parametrize(("description", "modes"), [
    (rrr3_of_chains(), ("left_left_left", "right_left_right")),
    (delta_of_chains(), ("single",)),
    (FIVE_BAR_OF_CHAINS, ("out_out", "in_out")),
    (FIVE_BAR_OF_RR_LEGS, ("out_out", "in_out")),
    (delta_and_its_chains_with_bodies()[1], ("single",)),
    (five_bar_of_chains_with_bodies(dict(pkm.load("five_bar").design())), ("out_in",)),
], ids=["rrr3_chains", "delta_chains", "five_bar_chains", "five_bar_rr", "delta_chains_bodies",
        "five_bar_chains_bodies"])
def test_chain_legs_and_point_poses_agree_with_pkm_in_pinocchio(pinocchio, tmp_path, description, modes):
    """Chain legs (a parallelogram's turns undone by mimic joints) and their bodies, and the platform of a point
    pose on prismatic joints as pkm's model has it (a planar point's would otherwise spin freely)."""
    assert_export_agrees(pkm.load(description), None, modes, tmp_path)


def test_the_worked_example_of_docs_export_runs(pinocchio, tmp_path, monkeypatch):
    text = (Path(__file__).resolve().parent.parent / "docs" / "export.md").read_text()
    example = text.split("## Loading it in Pinocchio", 1)[1].split("```python\n", 1)[1].split("```", 1)[0]
    monkeypatch.chdir(tmp_path)
    exec(compile(example, "docs/export.md", "exec"), {})
    assert (tmp_path / "five_bar_export" / "robot.urdf").exists()


@pytest.mark.parametrize(("argv", "message"), [
    (["export", "nothing"], "unknown mechanism 'nothing'"),
    (["export", "five_bar", "--design", "r1=-1"], "r1 = -1 m violates"),
    (["export", "five_bar", "--design", "nothing=1"], "nothing"),
    (["export", "five_bar", "--mode", "sideways"], "sideways"),
    (["export", "five_bar", "--pose", "0,10"], "reaches"),
])
def test_pkm_export_refuses_bad_input_with_one_line_and_exit_2(tmp_path, capsys, argv, message):
    assert main([*argv, "--out", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err
    assert message in err
    assert len(err.strip().splitlines()) == 1
    assert not (tmp_path / "out").exists()
    blocked = tmp_path / "file"
    blocked.write_text("a file, not a folder")
    assert main(["export", "five_bar", "--out", str(blocked / "out")]) == 2


def test_pkm_export_writes_the_three_files_for_a_name_or_a_description_file(tmp_path, capsys):
    assert main(["export", "five_bar", "--design", "r1=0.46,r2=0.46,r3=0.15", "--out", str(tmp_path / "five_bar"),
                 "--json"]) == 0
    folder = Path(json.loads(capsys.readouterr().out)["folder"])
    spec = yaml.safe_load((folder / "robot.yaml").read_text())
    assert spec["name_mot"] == ["theta1", "theta2"]
    assert spec["closed_loop"] == [["end_A", "end_B"]]
    assert "r1 = 0.46 m" in (folder / "robot.urdf").read_text()
    described = Path(__file__).resolve().parent.parent / "pkm" / "models" / "described" / "stewart.toml"
    assert main(["export", str(described), "--out", str(tmp_path / "stewart")]) == 0
    folder = tmp_path / "stewart"
    spec = yaml.safe_load((folder / "robot.yaml").read_text())
    assert spec["type"] == ["3d"] * 6
    assert spec["pkm"]["actuators"] == [f"q{k}" for k in range(1, 7)]
    assert sorted(p.name for p in folder.iterdir()) == ["README.md", "robot.urdf", "robot.yaml"]
