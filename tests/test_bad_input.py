"""Bad input to the API: pkm's own ValueError subclasses naming the thing and the violated condition.

DESIGN.md section 8: unknown names, bad designs, unreachable and non-finite poses, and singular poses,
which give the index's limiting value and never raise (unless ``strict``).
"""

from __future__ import annotations

import math
import re

import numpy as np
import pytest

import pkm
from pkm import registry
from pkm.design import parse_design
from pkm.errors import DesignError, PkmError, PoseError, SingularityError, UnknownNameError

m = pkm.load("five_bar")
DESIGN = {"r1": 1.2, "r2": 1.0, "r3": 0.8}
POSE = np.array([0.1, 1.5])
FAR = np.array([3.0, 3.0])
Y_COL = math.sqrt(1.2**2 - (1.0 - 0.8) ** 2)  # both distal links horizontal: a type II singularity
# |P - O1| = r1 + r2 with O1 = (-r3, 0), and 0.2 < |P - O2| < 2.2: on chain 1's outer circle, inside chain 2's annulus
STRETCHED = [-0.8 + 2.2 * math.cos(math.pi / 3), 2.2 * math.sin(math.pi / 3)]


@pytest.mark.parametrize(
    "error", [PkmError, UnknownNameError, DesignError, PoseError, SingularityError]
)
def test_every_error_is_a_value_error(error):
    assert issubclass(error, ValueError)
    assert issubclass(error, PkmError)


@pytest.mark.parametrize(
    ("call", "name"),
    [
        (lambda: pkm.load("six_bar"), "six_bar"),
        (lambda: m.global_index("gci_42", DESIGN), "gci_42"),
        (lambda: m.local_index("kappa_9", POSE, DESIGN), "kappa_9"),
        (lambda: m.inverse_kinematics(POSE, DESIGN, mode="sideways"), "sideways"),
        (lambda: m.jacobian(POSE, DESIGN, mode="OABCDE"), "OABCDE"),
        (lambda: m.forward_kinematics([1.0, 2.0], DESIGN, assembly="left"), "left"),
        (lambda: m.global_index("gci", DESIGN, region="moon"), "moon"),
    ],
    ids=["mechanism", "index", "local index", "mode", "gao mode", "assembly", "region"],
)
def test_unknown_name_is_named(call, name):
    with pytest.raises(UnknownNameError, match=name):
        call()


@pytest.mark.parametrize(
    ("design", "pattern"),
    [
        ({"r1": 1.2, "r2": 1.0}, "missing .*r3"),
        ({**DESIGN, "r4": 0.3}, "unknown .*r4"),
        ({**DESIGN, "r2": math.nan}, "r2 .*not finite"),
        ({**DESIGN, "r3": math.inf}, "r3 .*not finite"),
        ({**DESIGN, "r1": 0.0}, "r1"),
        ({**DESIGN, "r1": -1.0}, "r1"),
        ({**DESIGN, "r2": 0.0}, "r2"),
        ({"r1": 0.5, "r2": 0.4, "r3": 1.0}, r"cannot be assembled.*r1 \+ r2 > r3"),
    ],
    ids=["missing", "extra", "nan", "inf", "r1 zero", "r1 negative", "r2 zero", "cannot assemble"],
)
def test_bad_design_is_a_design_error_naming_the_parameter(design, pattern):
    with pytest.raises(DesignError, match=pattern):
        m.inverse_kinematics(POSE, design)
    with pytest.raises(DesignError, match=pattern):
        m.global_index("gci", design, region="miw")


def test_pose_out_of_reach_is_nan_in_a_batch():
    x = np.stack([POSE, FAR, [-3.0, 0.5]])
    np.testing.assert_array_equal(m.reachable(x, DESIGN), [True, False, False])
    for result in (
        m.inverse_kinematics(x, DESIGN),
        m.jacobian(x, DESIGN),
        m.forward_jacobian(x, DESIGN),
        m.local_index("inverse_condition_f", x, DESIGN),
    ):
        assert np.all(np.isfinite(result[0]))
        assert np.all(np.isnan(result[1:]))


@pytest.mark.parametrize("method", ["inverse_kinematics", "jacobian", "forward_jacobian"])
def test_pose_out_of_reach_raises_when_strict(method):
    with pytest.raises(PoseError, match="out of reach"):
        getattr(m, method)(np.stack([POSE, FAR]), DESIGN, strict=True)


def test_actuator_angles_that_cannot_close_are_nan_or_raise_when_strict():
    q = np.array([[1.6, 1.4], [math.pi, 0.0]])  # second: elbows 2 (r1 + r3) = 4 apart, r2 = 1
    x = m.forward_kinematics(q, DESIGN)
    assert np.all(np.isfinite(x[0]))
    assert np.all(np.isnan(x[1]))
    with pytest.raises(PoseError):
        m.forward_kinematics(q, DESIGN, strict=True)


@pytest.mark.parametrize("bad", [math.nan, math.inf, -math.inf])
def test_non_finite_pose_is_a_pose_error(bad):
    x = np.array([[0.1, 1.5], [0.0, bad]])
    for call in (m.inverse_kinematics, m.jacobian, m.reachable):
        with pytest.raises(PoseError, match="non-finite"):
            call(x, DESIGN)
    with pytest.raises(PoseError, match="non-finite"):
        m.local_index("inverse_condition_f", x, DESIGN)
    with pytest.raises(PoseError, match="non-finite"):
        m.forward_kinematics([bad, 1.0], DESIGN)


def test_pose_of_the_wrong_shape_is_a_pose_error():
    with pytest.raises(PoseError, match="shape"):
        m.inverse_kinematics([0.1, 1.5, 0.0], DESIGN)


SINGULAR = {
    "type I, folded elbow (inner boundary of chain 2)": ([0.8, 0.2], "out_out"),
    "type I, stretched chain (outer boundary of chain 1)": (STRETCHED, "out_out"),
    "type II, distal links aligned": ([0.0, Y_COL], "out_out"),
}


@pytest.mark.parametrize(("pose", "mode"), list(SINGULAR.values()), ids=list(SINGULAR))
def test_singular_pose_gives_zero_inverse_condition_and_never_raises(pose, mode):
    assert m.reachable(pose, DESIGN, mode=mode)
    for name in ("inverse_condition_f", "inverse_condition_2"):
        assert m.local_index(name, pose, DESIGN, mode=mode) == pytest.approx(0.0, abs=1e-6), name
    for name in ("velocity_max", "velocity_min"):
        assert m.local_index(name, pose, DESIGN, mode=mode) >= 0.0, name
    m.jacobian(pose, DESIGN, mode=mode)
    m.forward_jacobian(pose, DESIGN, mode=mode)


def test_jacobian_at_a_serial_singularity_raises_when_strict():
    pose, mode = SINGULAR["type I, folded elbow (inner boundary of chain 2)"]
    with pytest.raises(SingularityError):
        m.jacobian(pose, DESIGN, mode=mode, strict=True)
    m.forward_jacobian(pose, DESIGN, mode=mode, strict=True)


def test_forward_jacobian_at_a_parallel_singularity_raises_when_strict():
    pose, mode = SINGULAR["type II, distal links aligned"]
    with pytest.raises(SingularityError):
        m.forward_jacobian(pose, DESIGN, mode=mode, strict=True)
    m.jacobian(pose, DESIGN, mode=mode, strict=True)


@pytest.mark.parametrize(
    "options",
    [
        {"region": "reachable", "gradient": True},
        {"region": "reachable", "resolution": 0},
        {"region": "miw", "resolution": 0},
        {"region": "reachable", "resolution": -4},
        {"region": "miw", "resolution": 2.5},
        {"region": "reachable", "singularity_margin": 1.0},
    ],
    ids=["gradient of sampled", "zero grid", "zero quadrature", "negative grid", "fractional", "margin of one"],
)
def test_bad_global_index_option_is_a_pkm_error(options):
    with pytest.raises(PkmError, match="|".join(k for k in options if k != "region")):
        m.global_index("gci", DESIGN, **options)


@pytest.mark.parametrize(
    ("value", "needle"),
    [
        (None, "r1 = None violates: a real number"),
        ("1.2", "r1 = '1.2' violates: a real number"),
        ([1.2], "r1 = [1.2] violates: a real number"),
        (True, "r1 = True violates: a real number"),
        (10**400, "an integer of 401 digits violates |r1| <= 1e+12"),
        (1e308, "r1 = 1e+308 m violates |r1| <= 1e+12"),
    ],
)
def test_design_values_that_are_not_usable_numbers_are_pkms_error(value, needle):
    with pytest.raises(pkm.DesignError, match=re.escape(needle)):
        pkm.load("five_bar").design({"r1": value}, partial=True)


NOT_NAMES = [["five_bar"], {"name": "five_bar"}, 3, b"gci", np.array(["out_out"])]
NAME_LOOKUPS = {
    "mechanism": registry.mechanism,
    "index": lambda name: m.global_index(name, DESIGN, region="miw", resolution=2),
    "region": lambda name: m.global_index("gci", DESIGN, region=name, resolution=2),
    "mode of an index": lambda name: m.global_index("gci", DESIGN, region="miw", mode=name, resolution=2),
    "local index": lambda name: m.local_index(name, POSE, DESIGN),
    "mode": lambda name: m.inverse_kinematics(POSE, DESIGN, mode=name),
    "assembly": lambda name: m.forward_kinematics([1.6, 1.4], DESIGN, assembly=name),
    "inertia space": lambda name: m.inertia_matrix(POSE, DESIGN, space=name),
    "problem": pkm.synthesize,
    "paper": registry.paper,
}


@pytest.mark.parametrize("name", NOT_NAMES, ids=["list", "dict", "int", "bytes", "array"])
@pytest.mark.parametrize("lookup", list(NAME_LOOKUPS.values()), ids=list(NAME_LOOKUPS))
def test_a_name_that_is_not_a_string_is_pkms_error(lookup, name):
    with pytest.raises(UnknownNameError, match=r"violates: a name \(a string\); known: "):
        lookup(name)


@pytest.mark.parametrize("text", [None, 3, b"r1=1.2", ["r1=1.2"], {"r1": 1.2}])
def test_a_design_text_that_is_not_a_string_is_pkms_error(text):
    with pytest.raises(DesignError, match=r"design text = .* violates: a string name=value"):
        parse_design(text)


@pytest.mark.parametrize(
    ("design", "needle"),
    [
        ("r1=1.2", "design = 'r1=1.2' violates: a mapping name -> value, a sequence of 18 values"),
        ({1.2, 1.0}, "violates: a mapping name -> value"),
        (3, "design = 3 violates: a mapping name -> value"),
        (["a"] * 18, "design parameter r1 = 'a' violates: a real number"),
        ([1j] * 18, "design parameter r1 = 1j violates: a real number"),
        ([[1.2], [1.0, 0.8]], "a design vector needs 18 values"),
        ({1: 2.0, ("r1",): 1.0}, "unknown design parameter(s) ('r1',), 1"),
    ],
    ids=["text", "set", "scalar", "strings", "complex", "ragged", "keys not strings"],
)
def test_a_design_of_the_wrong_kind_is_pkms_error(design, needle):
    with pytest.raises(DesignError, match=re.escape(needle)):
        m.inverse_kinematics(POSE, design)


BATCH_METHODS = {
    "inverse_kinematics": (lambda p: m.inverse_kinematics(p, DESIGN), (0, 2)),
    "forward_kinematics": (lambda q: m.forward_kinematics(q, DESIGN), (0, 2)),
    "jacobian": (lambda p: m.jacobian(p, DESIGN), (0, 2, 2)),
    "forward_jacobian": (lambda p: m.forward_jacobian(p, DESIGN), (0, 2, 2)),
    "psi": (lambda p: m.psi(p, DESIGN), (0, 4, 2)),
    "reachable": (lambda p: m.reachable(p, DESIGN), (0,)),
    "local_index": (lambda p: m.local_index("inverse_condition_f", p, DESIGN), (0,)),
    "inertia_matrix": (lambda p: m.inertia_matrix(p, DESIGN), (0, 2, 2)),
    "actuated inertia_matrix": (lambda p: m.inertia_matrix(p, DESIGN, space="actuated"), (0, 2, 2)),
    "inverse_dynamics": (lambda p: m.inverse_dynamics(p, [0.1, 0.0], [0.0, 0.2], DESIGN), (0, 2)),
    "inverse_dynamics of its velocities": (lambda v: m.inverse_dynamics(POSE, v, [0.0, 0.2], DESIGN), (0, 2)),
    "natural_frequencies": (lambda p: m.natural_frequencies(p, DESIGN).frequencies, (0, 4)),
}


@pytest.mark.parametrize(("call", "shape"), list(BATCH_METHODS.values()), ids=list(BATCH_METHODS))
def test_an_empty_batch_gives_an_empty_result_of_the_right_shape(call, shape):
    assert call(np.empty((0, 2))).shape == shape


BAD_ARRAYS = {
    "wrong width": (np.zeros((3, 3)), "must have shape"),
    "3-D": (np.zeros((2, 2, 2)), "must have shape"),
    "scalar": (0.5, "must have shape"),
    "ragged": ([[0.1, 1.5], [0.1]], "violates: an array of real numbers"),
    "object array": (np.array([0.1, None], dtype=object), "violates: an array of real numbers"),
    "text": ("0.1,1.5", "violates: an array of real numbers"),
    "list of text": (["0.1", "1.5"], "violates: an array of real numbers"),
    "complex": ([0.1 + 1j, 1.5], "violates: an array of real numbers"),
    "booleans": ([True, False], "violates: an array of real numbers"),
    "None": (None, "violates: an array of real numbers"),
    "mapping": ({"x": 0.1, "y": 1.5}, "violates: an array of real numbers"),
    "integer too large": ([10**400, 1], "violates: an array of real numbers"),
}


@pytest.mark.parametrize(("values", "needle"), list(BAD_ARRAYS.values()), ids=list(BAD_ARRAYS))
@pytest.mark.parametrize("call", [c for c, _ in BATCH_METHODS.values()], ids=list(BATCH_METHODS))
def test_an_array_of_the_wrong_shape_or_kind_is_a_pose_error_naming_the_parameter(call, values, needle):
    with pytest.raises(PoseError, match=rf"^(pose|actuated joints|velocity)\b.*{re.escape(needle)}"):
        call(values)


@pytest.mark.parametrize("wrench", ["abc", {"F_x": 1}, [[1, 2, 3, 4, 5, 6], [1, 2]], [1j] * 6])
def test_a_wrench_that_is_not_real_numbers_is_a_pose_error(wrench):
    mech = pkm.load("ups_pu")
    with pytest.raises(PoseError, match="wrench"):
        mech.statics(np.array([0.4, 0.0, 0.0]), wrench)


@pytest.mark.parametrize("theta", ["x", 1j, [[0.1]], None])
def test_a_theta_that_is_not_real_numbers_is_a_pose_error(theta):
    with pytest.raises(PoseError, match="theta"):
        pkm.load("passive_leg").workspace_boundary(theta)


def test_a_design_of_another_mechanism_is_a_design_error():
    """A described five-bar with as many parameters as the five-bar: a Design is not taken by its length."""
    from helpers import FIVE_BAR_OF_RR_LEGS

    five_bar = pkm.load("five_bar")
    padding = [{"name": f"p{k}", "default": 1.0, "lower": 0.0, "upper": 2.0, "unit": "m", "doc": "unused"}
               for k in range(len(five_bar.parameters) - len(FIVE_BAR_OF_RR_LEGS["parameters"]))]
    other = pkm.load({**FIVE_BAR_OF_RR_LEGS, "name": "five_bar_padded",
                      "parameters": FIVE_BAR_OF_RR_LEGS["parameters"] + padding})
    assert len(other.parameters) == len(five_bar.parameters)
    with pytest.raises(DesignError, match="a design of the five_bar"):
        five_bar.reachable([0.0, 1.6], other.design())
    with pytest.raises(DesignError, match="unknown design parameter"):
        five_bar.design(other.design())


@pytest.mark.parametrize("command", ["atlas five_bar gci", "sweep five_bar --indices gci"])
def test_a_parameter_named_twice_in_axes_exits_2(command, capsys):
    from pkm.cli import main

    assert main([*command.split(), "--axes", "r1=0.5:1.5,r1=0.6:1.2"]) == 2
    err = capsys.readouterr().err
    assert "r1 is given twice" in err
    assert len(err.strip().splitlines()) == 1


@pytest.mark.parametrize("name", pkm.mechanisms())
def test_an_empty_batch_gives_empty_results(name):
    mech = pkm.load(name)
    poses = np.empty((0, mech.n_out))
    assert mech.inverse_kinematics(poses).shape == (0, mech.n_act)
    assert mech.jacobian(poses).shape == (0, mech.n_act, mech.n_out)
    for assembly in mech.assemblies[:2]:
        assert mech.forward_kinematics(np.empty((0, mech.n_act)), assembly=assembly).shape == (0, mech.n_out)


@pytest.mark.parametrize(("command", "dimension"), [("ups_pu gci", "3-D sampled workspace"),
                                                    ("ups_pu gci --region task", "region task")])
def test_a_resolution_beyond_the_node_budget_exits_2_before_any_work(command, dimension, capsys):
    from pkm.cli import main

    assert main(["index", *command.split(), "--resolution", "1000"]) == 2
    err = capsys.readouterr().err
    assert "resolution = 1000 violates: at most" in err
    assert dimension in err


def _wu2008():
    from pkm.models.slider_gantry import wu2008

    return wu2008


JUNK_NUMBERS = {
    "resolution=10**400": (lambda: m.global_index("gci", DESIGN, region="miw", resolution=10**400), "resolution"),
    "fit_task(10**400, 0.1)": (lambda: pkm.load("slider_gantry").fit_task(10**400, 0.1), "task rectangle width"),
    "fit_task('a', 0.1)": (lambda: pkm.load("slider_gantry").fit_task("a", 0.1), "task rectangle width = 'a'"),
    "singularity_margin='a'": (lambda: m.global_index("gci", DESIGN, singularity_margin="a"), "singularity_margin"),
    "tol='abc'": (lambda: pkm.synthesize("five_bar.max_gci_miw", tol="abc"), "tol = 'abc'"),
    "tol=[1e-3]": (lambda: pkm.synthesize("five_bar.max_gci_miw", tol=[1e-3]), "tol = "),
    "workspace_synthesis(None, 0.4, 0.17)": (lambda: _wu2008().workspace_synthesis(None, 0.4, 0.17), "b = None"),
    "k_av_closed_form(0.6164, 0.357, 0.0)": (lambda: _wu2008().k_av_closed_form(0.6164, 0.357, 0.0), "b = 0"),
}


@pytest.mark.parametrize(("call", "named"), list(JUNK_NUMBERS.values()), ids=list(JUNK_NUMBERS))
def test_numbers_that_are_not_numbers_are_pkms_error_naming_the_argument(call, named):
    with pytest.raises(PkmError, match=re.escape(named)):
        call()


def test_negative_leg_lengths_are_not_assembled():
    """The 2-UPS-PU's forward polynomial knows the squared leg lengths only: their signs are checked."""
    u = pkm.load("ups_pu")
    q = u.inverse_kinematics([0.5, 0.2, -0.1])
    for assembly in u.assemblies:
        assert np.all(np.isnan(u.forward_kinematics(-q, assembly=assembly)))
    with pytest.raises(PoseError, match="cannot be assembled"):
        u.forward_kinematics(-q, strict=True)
    assert any(np.allclose(u.forward_kinematics(q, assembly=a), [0.5, 0.2, -0.1]) for a in u.assemblies)


def test_a_wrench_batch_of_another_length_than_the_poses_is_a_pose_error():
    u = pkm.load("ups_pu")
    poses = np.array([[0.5, 0.1, 0.0], [0.55, 0.0, 0.1], [0.6, -0.1, 0.0]])
    with pytest.raises(PoseError, match="wrench has 2 rows; the poses have 3"):
        u.statics(poses, np.zeros((2, 6)))
    with pytest.raises(PoseError, match="wrench contains non-finite values"):
        u.statics(poses, [0.0, 0.0, np.nan, 0.0, 0.0, 0.0])
    assert u.statics(poses, np.zeros((3, 6))).actuators.shape == (3, 3)


def test_pkm_load_takes_a_mapping_as_a_description_and_names_what_it_lacks():
    """pkm.load reads a mapping as a machine description (issue 24): a field it does not know is refused by
    name."""
    from pkm.spec.schema import DescriptionError

    with pytest.raises(DescriptionError, match="description field r1 violates: a known field"):
        pkm.load({"r1": 1.2})
