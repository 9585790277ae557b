"""Limits held exactly, between the nodes too (issue "Trust the answer", item 2): every limit margin signed and
continuous beyond the reach, the region extremes refined on it, and a synthesis whose optimum holds an active
stroke at every task pose by the inverse kinematics."""

from __future__ import annotations

import math

import numpy as np
import pytest
from helpers import rpr3_text

import pkm
from pkm.synthesis.designer import design_problem

# a 3-RPR whose platform pattern is turned by alpha from the base's, its strokes within [0.2, 0.65] m
RPR3 = rpr3_text("rpr3_strokes", R=0.5, r=0.2, stroke=(0.2, 0.65), alpha=(0.8, 0, 3.2))
TASK = {"shape": "cylinder", "centre": [0.0, 0.0, 0.0], "size": [0.08, math.radians(15)], "axis": "phi"}


@pytest.fixture(scope="module")
def rpr3(tmp_path_factory):
    path = tmp_path_factory.mktemp("limits") / "rpr3.toml"
    path.write_text(RPR3)
    return pkm.load(str(path))


def _legs(design: dict[str, float], poses: np.ndarray) -> np.ndarray:
    """The legs' lengths |C - A| of the description above, computed here from its geometry."""
    out = []
    for k in range(3):
        base = design["R"] * np.array([math.cos(math.pi / 2 + 2 * math.pi * k / 3),
                                       math.sin(math.pi / 2 + 2 * math.pi * k / 3)])
        angle = math.pi / 2 + design["alpha"] + 2 * math.pi * k / 3 + poses[:, 2]
        tip = poses[:, :2] + design["r"] * np.column_stack([np.cos(angle), np.sin(angle)])
        out.append(np.linalg.norm(tip - base, axis=1))
    return np.column_stack(out)


def test_a_stroke_margin_is_signed_beyond_the_stroke(rpr3):
    """Beyond a stroke the workspace margin is the stroke's margin, negative (it was NaN: the pose was not
    reached, so the margin's least value over a region could not see it); its limits are named per leg."""
    design = dict(rpr3.design())
    poses = np.array([[0.0, 0.0, 0.0], [0.3, 0.0, 0.0], [0.0, 0.6, 0.0], [0.02, -0.01, 0.4]])
    margin = rpr3.local_index("workspace_margin", poses)
    legs = _legs(design, poses)
    expected = np.minimum((legs - 0.2).min(axis=1), (0.65 - legs).min(axis=1))
    expected = np.minimum(expected, (legs**2).min(axis=1))  # the legs' reach, |C - A|^2 >= 0
    np.testing.assert_allclose(margin, expected, rtol=1e-12, atol=1e-14)
    assert (margin[1:3] < 0).all()
    assert rpr3.limits == "workspace_margins"
    assert "assembled" in rpr3.region_names()
    assert rpr3.limit_names[:3] == ("leg 1 reach", "leg 1 range lower", "leg 1 range upper")
    assert np.isnan(rpr3.inverse_kinematics(poses[1:3])).all()
    assert np.isfinite(rpr3.inverse_kinematics(poses[1:3], limits=False)).all()


def test_a_reach_margin_is_signed_beyond_the_assembly():
    """The 3-RRR's workspace margin beyond its legs' reach is the reach margin, negative, where its joints
    (and so its ranges) are undefined, and so is every mechanism's (the five-bar's, from its generated
    inverse kinematics' reach)."""
    rrr3 = pkm.load("rrr3")
    far = np.array([[0.0, 2.0, 0.0], [0.0, 0.0, 0.0]])
    margin = rrr3.local_index("workspace_margin", far)
    assert np.isnan(rrr3.inverse_kinematics(far[:1])).all()
    assert margin[0] < 0 < margin[1]
    step = np.array([[0.0, 2.0 + 1e-3, 0.0]])
    assert rrr3.local_index("workspace_margin", step)[0] < margin[0]  # farther out, more negative
    five_bar = pkm.load("five_bar")  # derived by hand: its inverse kinematics' reach, as generated
    margin = five_bar.local_index("workspace_margin", np.array([[0.0, 1.4], [0.0, 3.0], [0.0, 3.1]]))
    assert np.isnan(five_bar.inverse_kinematics([0.0, 3.0])).all()
    assert margin[2] < margin[1] < 0 < margin[0]


def test_a_synthesis_with_an_active_stroke_holds_it_at_every_task_pose(rpr3):
    """The base radius and the platform's turn of the 3-RPR for its task cylinder, a stroke active at the
    optimum: the driver exchanges the run that the verification found violating the stroke between the nodes
    (it raised SynthesisError, or returned a worse corner where the runs' best lies next to the stroke), and
    the optimum holds every constraint exactly, so that the inverse kinematics reaches every pose of a dense
    grid of the task within the strokes."""
    problem = design_problem(rpr3, task=TASK, variables={"R": (0.3, 0.8), "alpha": (0.0, 1.6)}, objective="gci",
                             resolution=6)
    result = pkm.synthesize(problem, progress=False)
    margin = next(c for c in result.optimum.constraints if c.name.startswith("0 <= workspace_margin_min"))
    assert margin.active
    assert margin.value >= 0
    assert all(c.lower <= c.value <= c.upper for c in result.optimum.constraints)
    assert result.optimum.verified_objective >= max(b.best.verified_objective for b in result.baselines.values())
    radius, angle, phi = np.meshgrid(0.08 * np.sqrt(np.linspace(0, 1, 41)), np.linspace(-math.pi, math.pi, 181),
                                     np.linspace(-math.radians(15), math.radians(15), 31))
    poses = np.column_stack([(radius * np.cos(angle)).ravel(), (radius * np.sin(angle)).ravel(), phi.ravel()])
    q = rpr3.inverse_kinematics(poses, result.optimum.design)
    assert np.isfinite(q).all()
    assert _legs(result.optimum.design, poses).max() <= 0.65
    assert _legs(result.optimum.design, poses).max() > 0.65 - 1e-4  # the stroke is what holds the optimum
