"""The two-slider gantry of Wu, Wang, Wang and Shao 2008, and its symmetric variant (section 6.3).

Two sliders move along vertical columns at x = -(d1 + d2) and d1 + d2; three links of length l join
them to a translating platform of width 2 d2 and height l2 (A1B1B3A3 a parallelogram), and a
counterweight on each column moves opposite to its slider. The platform reference point O' = (x, y)
is its centre; q_i is the height of the lower joint B_i of slider i; theta_i is the angle of link
A_iB_i from the vertical. See ``symbolic/mechanisms/slider_gantry.py`` for the equations and
docs/papers/wu2008.md for the mapping to the paper.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, ClassVar

import numpy as np

from pkm.design import Condition, Parameter
from pkm.dynamics.trajectories import Trajectory
from pkm.errors import DesignError, check_real
from pkm.kinematics import Branch, DesignLike
from pkm.mechanism import Mechanism
from pkm.models.slider_gantry.legs import described
from pkm.models.slider_gantry.structure import structure
from pkm.regions import Rectangle, trajectory_region
from pkm.spec.given_legs import GivenLegs

DEG = math.pi / 180
INF = math.inf
# Wu's Table 3 move across the middle of his 500 x 400 mm task rectangle, centred at y = 0.5 m [m, m/s, m/s^2]
TABLE3_MOVE = {"start": (-0.25, 0.5), "end": (0.25, 0.5), "v_max": 1.0, "a_max": 6.67}


def _length(name, default, doc, *, lower=0.0, closed=False, required=True):
    return Parameter(name, default, lower, INF, "m", doc, closed_lower=closed, required=required)


def _mass(name, default, doc, *, unit="kg", default_from=None):
    return Parameter(name, default, 0.0, INF, unit, doc, required=False, default_from=default_from)


GEOMETRY = (
    _length("l", 0.6164, "length of each link A_iB_i (Wu Table 1: 616.4 mm)"),
    _length(
        "d1",
        0.357,
        "half the horizontal distance between the slider joints B_i, less the platform half-width d2: "
        "Wu's d1 of eqs. 1-2 and 15 (Table 1: 357 mm)",
    ),
    _length("d2", 0.1, "half the platform width; the columns stand at x = +-(d1 + d2) (Table 1: 100 mm)", closed=True),
    _length("l2", 0.2, "platform height A1A3 = slider joint spacing B1B3 (Table 1: 200 mm)"),
    Parameter("qs", -0.4, -INF, INF, "m", "lower stroke limit of both sliders, q_iS (frame of pkm: Wu gives none)"),
    Parameter("ql", 0.5, -INF, INF, "m", "upper stroke limit of both sliders, q_iL; ql - qs = 900 mm (Table 1)"),
    Parameter(
        "theta_s",
        10 * DEG,
        0.0,
        math.pi / 2,
        "rad",
        "smallest |theta_i| allowed in the task rectangle: margin from theta = 0 (Wu theta_1S = 10 deg)",
        required=False,
    ),
    Parameter(
        "theta_l",
        80 * DEG,
        0.0,
        math.pi / 2,
        "rad",
        "largest |theta_i| allowed in the task rectangle: margin from the serial singularity at 90 deg "
        "(Wu theta_2L = 80 deg)",
        required=False,
    ),
)

INERTIAL = (
    _mass("m11", 250.0, "mass of slider 1, which carries B1 and B3 (Wu Table 2)"),
    _mass("m21", 198.0, "mass of slider 2 (Table 2)"),
    _mass("m12", 80.0, "mass of link A1B1 (Table 2)"),
    _mass("m22", 80.0, "mass of link A2B2 (Table 2)"),
    _mass("m13", 462.0, "mass of counterweight 1: half the moving mass without counterweights (Table 2)"),
    _mass("m23", 462.0, "mass of counterweight 2 (Table 2)"),
    _mass("m4", 80.0, "mass of link A3B3 of the parallelogram (Table 2)"),
    _mass("mN", 236.0, "mass of the moving platform (Table 2)"),
    _mass("I12", 11.3, "moment of inertia of link A1B1 about B1 (Table 2)", unit="kg m^2"),
    _mass("I22", 11.3, "moment of inertia of link A2B2 about B2 (Table 2)", unit="kg m^2"),
    _mass("I4", 11.3, "moment of inertia of link A3B3 about B3; Wu: the same as link A1B1", unit="kg m^2",
          default_from=("I12", 1.0)),
    Parameter("s12", 0.3082, 0.0, INF, "m", "distance from B1 to the centre of mass of link A1B1; default l/2 "
              "(Wu gives none)", closed_lower=True, required=False, default_from=("l", 0.5)),
    Parameter("s22", 0.3082, 0.0, INF, "m", "distance from B2 to the centre of mass of link A2B2; default l/2",
              closed_lower=True, required=False, default_from=("l", 0.5)),
    Parameter("s4", 0.3082, 0.0, INF, "m", "distance from B3 to the centre of mass of link A3B3; default s12",
              closed_lower=True, required=False, default_from=("s12", 1.0)),
)

FOURTH_LINK = (
    _mass("m5", 80.0, "mass of the added link A4B4 (Wu section 6.3); default m4", default_from=("m4", 1.0)),
    _mass("I5", 11.3, "moment of inertia of link A4B4 about B4; default I4", unit="kg m^2", default_from=("I4", 1.0)),
    Parameter("s5", 0.3082, 0.0, INF, "m", "distance from B4 to the centre of mass of link A4B4; default s4",
              closed_lower=True, required=False, default_from=("s4", 1.0)),
)

GRAVITY = Parameter(
    "g", 9.8, 0.0, INF, "m/s^2", "gravitational acceleration along -y (Wu: 9.8); 0 for a horizontal machine",
    closed_lower=True, required=False,
)
ELASTIC = (
    Parameter("b_l", 0.2, 0.0, INF, "m", "outer side of the links' steel square tube (their beams' section; a "
              "200 x 200 x 20 mm tube of l = 0.6164 m weighs 70 kg, Wu's links 80 kg)", required=False),
    Parameter("t_l", 0.02, 0.0, INF, "m", "wall of the links' square tube", required=False),
    Parameter("k_s", 1e8, 0.0, INF, "N/m", "axial stiffness of each slider's drive along its column (a ball "
              "screw's)", required=False),
)


def _pivot_inertia(link: str, inertia: str, mass: str, offset: str) -> Condition:
    return Condition(
        f"{inertia} >= {mass} {offset}^2 (the inertia of {link} about its pivot includes m s^2)",
        lambda d: d[inertia] - d[mass] * d[offset] ** 2 + 1e-12,
    )


CONDITIONS = (
    Condition("l > d1 (both links reach the platform at x = 0: Wu section 3.1)", lambda d: d["l"] - d["d1"]),
    Condition("qs < ql (the slider stroke is positive)", lambda d: d["ql"] - d["qs"]),
    Condition("theta_s < theta_l (angle margins)", lambda d: d["theta_l"] - d["theta_s"]),
    _pivot_inertia("link A1B1", "I12", "m12", "s12"),
    _pivot_inertia("link A2B2", "I22", "m22", "s22"),
    _pivot_inertia("link A3B3", "I4", "m4", "s4"),
)


@dataclass(frozen=True)
class TaskRectangle:
    """An axis-aligned task rectangle: centre (x, y) [m], width b [m] and height h [m]."""

    centre: tuple[float, float]
    width: float
    height: float

    @property
    def box(self) -> np.ndarray:
        """(lo, hi) per axis, shape (2, 2)."""
        half = np.array([self.width, self.height]) / 2
        c = np.array(self.centre)
        return np.stack([c - half, c + half], axis=1)


class SliderGantry(GivenLegs, Mechanism):
    name = "slider_gantry"
    doc = (
        "two-slider gantry of Wu 2008 Fig. 1: sliders on vertical columns, three equal links (A1B1B3A3 a "
        "parallelogram), counterweights, a translating platform (x, y)"
    )
    parameters = (*GEOMETRY, *INERTIAL, GRAVITY, *ELASTIC)
    conditions = (*CONDITIONS, Condition("2 t_l < b_l (the tube's walls within its side)",
                                         lambda d: d["b_l"] - 2 * d["t_l"]))
    working_modes = (
        Branch("below", (1.0, 1.0), "both sliders below their platform joints: Wu's machine (eq. 2 with '-')",
               ("wu2008",)),
        Branch("above", (-1.0, -1.0), "both sliders above their platform joints (eq. 2 with '+')"),
    )
    assembly_modes = (
        Branch("up", (1.0,), "platform above the line through the points (+-d1, q_i + l2/2)"),
        Branch("down", (-1.0,), "platform below that line"),
    )
    pose_names = ("x", "y")
    pose_units = ("m", "m")
    actuator_names = ("q1", "q2")
    actuator_units = ("m", "m")
    regions: ClassVar[dict[str, Any]] = {
        "task": Rectangle(
            "task",
            "task rectangle Q1Q2Q3Q4 of Wu Fig. 2: the largest rectangle centred on x = 0 with "
            "theta_s <= |theta_i| <= theta_l and both sliders within [qs, ql] (mode below)",
            function="task_rectangle",
        ),
        "table3_move": trajectory_region(
            Trajectory.trapezoidal(TABLE3_MOVE["start"], TABLE3_MOVE["end"], TABLE3_MOVE["v_max"],
                                   TABLE3_MOVE["a_max"]),
            "table3_move", "Wu's Table 3 move: from (-0.25, 0.5) to (0.25, 0.5) m, trapezoidal velocity of 1 m/s "
            "and 6.67 m/s^2 (the trajectory quantities along it: pkm.Mechanism.trajectory_quantities)"),
    }
    structure = staticmethod(structure)
    symmetric: ClassVar[bool] = False  # the right chain a parallelogram too (Wu section 6.3)

    @classmethod
    def legs_description(cls) -> dict:
        """Its two PRR legs (:mod:`pkm.models.slider_gantry.legs`)."""
        return described(cls.parameters, cls.symmetric)

    def workspace_box(self, design: np.ndarray) -> np.ndarray:
        """|x| <= l - d1 (both links reach); y within the strokes plus or minus l and l2/2."""
        d = self.design_dict(design)
        half = d["l"] - d["d1"]
        return np.array([[-half, half], [d["qs"] + d["l2"] / 2 - d["l"], d["ql"] + d["l2"] / 2 + d["l"]]])

    def task_rectangle(self, design: DesignLike = None) -> TaskRectangle:
        """The design's task rectangle Q1Q2Q3Q4 (Wu section 4.1); :class:`DesignError` if it is empty."""
        vector = self.design_vector(design)
        centre, half = (np.asarray(a, dtype=float).ravel() for a in self.functions["task_rectangle"](vector))
        if not (half[0] > 0 and half[1] > 0):
            d = self.design_dict(vector)
            raise DesignError(
                f"the design has no task rectangle: half width {half[0]:.4g} m (needs d1 - l sin(theta_s) > 0 "
                f"and l sin(theta_l) - d1 > 0), half height {half[1]:.4g} m (needs the stroke ql - qs = "
                f"{d['ql'] - d['qs']:.4g} m to exceed the rise between the links' extreme angles)"
            )
        return TaskRectangle((float(centre[0]), float(centre[1])), 2 * float(half[0]), 2 * float(half[1]))

    def fit_task(self, width: float, height: float, design: DesignLike = None) -> TaskRectangle:
        """A width x height task rectangle centred in the design's task rectangle; :class:`DesignError`
        naming the violated condition when it does not fit."""
        width, height = (check_real(f"task rectangle {name}", value, "a finite number > 0 [m]", DesignError)
                         for name, value in (("width", width), ("height", height)))
        for name, value in (("width", width), ("height", height)):
            if not value > 0:
                raise DesignError(f"task rectangle {name} = {value:g} m violates {name} > 0")
        own = self.task_rectangle(design)
        for name, value, room in (("width b", width, own.width), ("height h", height, own.height)):
            if value > room * (1 + 1e-9):
                raise DesignError(
                    f"a {width:g} m x {height:g} m task rectangle cannot fit: {name} = {value:g} m exceeds "
                    f"the {room:.4g} m the design allows within its angle margins and strokes"
                )
        return TaskRectangle(own.centre, float(width), float(height))


class SliderGantrySymmetric(SliderGantry):
    name = "slider_gantry_symmetric"
    symmetric: ClassVar[bool] = True
    doc = (
        "symmetric variant of Wu's gantry (section 6.3): the right chain also a parallelogram (link "
        "A4B4), equal sliders; kappa_D symmetric about the y axis"
    )
    parameters = (
        *GEOMETRY,
        *(
            _mass("m21", 250.0, "mass of slider 2, which now carries B2 and B4 (pkm: equal to m11)")
            if p.name == "m21"
            else _mass(p.name, 528.0, f"{p.doc.split(':')[0]}: half the moving mass without counterweights")
            if p.name in ("m13", "m23")
            else p
            for p in INERTIAL
        ),
        *FOURTH_LINK,
        GRAVITY,
        *ELASTIC,
    )
    conditions = (*SliderGantry.conditions, _pivot_inertia("link A4B4", "I5", "m5", "s5"))
