"""Zhao, Tang, Zhao 2008: the 2-UPS-PU parallel manipulator. Checks eq. 6 against the inverse
kinematics, eq. 8 against virtual work, the sign of eq. 9, the convexity of the workspace, the stroke
rule of eq. 10 in the paper's examples, and under both readings of section 6's prescribed workspace
(gamma_u = 60 deg as the cone's apex angle, a tilt radius of 30 deg, or literally as its tilt radius)
Table 1's leg lengths by step 5, Table 1's feasibility under section 5.3's joint limits and Fig. 9's
"the actual workspace contains the prescribed one", and whether Table 1 is optimal for the paper's own
objective; draws the workspace sections with each constraint's boundary (Figs. 5-6), the
determinant map (Fig. 3) and the force map; runs pkm's IPOPT synthesis beyond the paper. Lengths in
mm where the paper gives them, everything else SI.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import numpy as np

from pkm import figures, registry
from pkm.batch import evaluate
from pkm.mechanism import Mechanism
from pkm.models.ups_pu.problems import DEFAULTS, STROKE_RATIO, TASK_MARGIN_MIN, shortest_leg_on_rim
from pkm.models.ups_pu.workspace import MARGINS, least_tilt, section, volume
from pkm.progress import Progress
from pkm.regions import parametrised_global, sampled_check
from pkm.reproduce.report import claim, reproduced_by, status, synthesis_record
from pkm.synthesis import synthesize

TITLE = "Zhao, Tang, Zhao 2008: dimensional synthesis and analysis of the 2-UPS-PU parallel manipulator"
DEG = math.pi / 180
PROBLEM = "ups_pu.min_size_force_task"
FIG3 = {"r": 0.150, "R": 0.200, "alpha": 90 * DEG, "beta": 30 * DEG, "l0": 0.300}
EXAMPLE_53 = {"r": 0.100, "R": 0.120, "alpha": 90 * DEG, "beta": 25 * DEG, "D": 0.005, "l_min": 0.320,
              "l_max": 0.578, "l0_min": 0.320, "l0_max": 0.570, "theta_u_max": 90 * DEG, "theta_s_max": 60 * DEG}
TABLE1_LEGS = {"l_min": 396.0, "l_max": 712.0}
STROKE_LIMIT = 0.8  # eq. 10
READINGS = {"apex_angle": 30 * DEG, "literal_radius": 60 * DEG}  # the task cylinder's tilt radius by reading
PRIMARY = "apex_angle"
LEG_ROUNDING = 0.5  # [mm] Table 1 gives the leg lengths to the millimetre


def _settings(quick: bool) -> dict[str, Any]:
    """Resolutions of the report; the full run solves the synthesis at the problem's own resolution, refined
    to its accuracy (``synthesis_resolution`` None), as ``pkm synth`` does."""
    if quick:
        return {"section_resolution": 60, "rays": 120, "planes": 5, "synthesis_resolution": 2,
                "baseline_resolution": 60, "starts": 1, "levels": 3, "task_resolution": 4, "ray_step_deg": 0.25}
    return {"section_resolution": 240, "rays": 360, "planes": 10, "synthesis_resolution": None,
            "baseline_resolution": 400, "starts": 3, "levels": 11, "task_resolution": 16, "ray_step_deg": 0.1}


def _eq6(m: Mechanism, rng: np.random.Generator) -> dict[str, float]:
    """Eq. 6 at alpha = 90 deg, as printed and with l1 and l2 swapped back, against the inverse kinematics."""
    d = dict(m.design())
    x = np.column_stack([rng.uniform(0.45, 0.65, 50), rng.uniform(-0.6, 0.6, 50), rng.uniform(-0.6, 0.6, 50)])
    q = m.inverse_kinematics(x, limits=False)
    errors = {"as_printed": 0.0, "corrected": 0.0}
    for (l1, l2, l0), pose in zip(q, x, strict=True):
        for key, (first, second) in (("as_printed", (l2, l1)), ("corrected", (l1, l2))):
            r, R, b = d["r"], d["R"], d["beta"]
            s = (first**2 - r**2 - R**2 - l0**2) / (2 * r * math.hypot(l0, R))
            if abs(s) > 1:
                errors[key] = math.inf
                continue
            t1 = math.asin(s) + math.atan(R / l0)
            a = (r**2 + R**2 + l0**2 - second**2) / (2 * r)
            bb = l0 * math.sin(b) * math.sin(t1) - R * math.sin(b) ** 2 * math.cos(t1)
            c = l0 * math.cos(b) * math.cos(t1) + R * math.cos(b) * math.sin(b) * math.sin(t1)
            dd = R * math.cos(b) ** 2
            u = (a + bb) / math.hypot(c, dd)
            if abs(u) > 1:
                errors[key] = math.inf
                continue
            t2 = math.asin(u) - math.atan(dd / c)
            errors[key] = max(errors[key], abs(t1 - pose[1]), abs(t2 - pose[2]))
    return errors


def _eq8(m: Mechanism, rng: np.random.Generator) -> dict[str, float]:
    """Largest relative error of the actuator forces of eq. 8 (physical and as printed) against virtual
    work, J^T f = the wrench's generalised force."""
    x = np.column_stack([rng.uniform(0.45, 0.65, 40), rng.uniform(-0.6, 0.6, 40), rng.uniform(-0.6, 0.6, 40)])
    wrench = rng.normal(size=(40, 6)) * [100, 100, 1000, 10, 10, 10]
    J = m.jacobian(x)
    t1 = x[:, 1]
    axis2 = np.stack([0 * t1, np.cos(t1), np.sin(t1)], axis=1)
    generalised = np.stack([wrench[:, 2], wrench[:, 3], np.einsum("ni,ni->n", wrench[:, 3:], axis2)], axis=1)
    out = {}
    for key, printed in (("physical", False), ("as_printed", True)):
        forces = m.statics(x, wrench, printed=printed).actuators
        residual = np.einsum("nij,ni->nj", J, forces) - generalised
        out[key] = float(np.nanmax(np.abs(residual)) / np.abs(generalised).max())
    return out


def _fig3(m: Mechanism, path: Path, resolution: int) -> tuple[dict[str, float], str]:
    """The determinant of J over (theta1, theta2) for Fig. 3's design at l0 = 300 mm."""
    design = m.design({**m.design(), **{k: v for k, v in FIG3.items() if k != "l0"}})
    axis = np.linspace(-math.pi / 2, math.pi / 2, resolution)
    T1, T2 = np.meshgrid(axis, axis, indexing="ij")
    x = np.stack([np.full(T1.size, FIG3["l0"]), T1.ravel(), T2.ravel()], axis=1)
    det = np.linalg.det(m.jacobian(x, design)).reshape(T1.shape)
    home = float(np.linalg.det(m.jacobian([FIG3["l0"], 0.0, 0.0], design)))
    fig = figures.figure(6, 5)
    ax = fig.subplots()
    image = ax.contourf(np.degrees(T1), np.degrees(T2), det, levels=20, cmap="RdBu_r")
    ax.contour(np.degrees(T1), np.degrees(T2), det, levels=[0.0], colors="k")
    ax.set_xlabel("theta1 [deg]")
    ax.set_ylabel("theta2 [deg]")
    ax.set_title("det J, Fig. 3's design: r = 150, R = 200 mm,\nbeta = 30 deg, l0 = 300 mm (black: det J = 0)")
    fig.colorbar(image, ax=ax, label="det J [m^2/rad^2]")
    figures.save(fig, path, dpi=90)
    return {"det_at_home": home, "positive_fraction": float(np.mean(det > 0))}, path.name


def _sections(m: Mechanism, path: Path, s: dict[str, int]) -> tuple[dict[str, Any], str]:
    """Fig. 6: the workspace of section 5.3's example at l0 = 350, 450, 500 mm with each constraint's
    boundary; areas by sampling and by the ray search; convexity against the convex hull."""
    from matplotlib.path import Path as PolygonPath

    design = m.design({**m.design(), **EXAMPLE_53}).vector()
    fig = figures.figure(15, 5)
    axes = fig.subplots(1, 3)
    out: dict[str, Any] = {}
    for ax, l0 in zip(axes, (0.350, 0.450, 0.500), strict=True):
        cut = section(m, design, l0, resolution=s["section_resolution"], rays=s["rays"])
        inside = cut.grid[cut.mask.ravel()]
        cell = (math.pi / s["section_resolution"]) ** 2
        hull = PolygonPath(_hull(inside)).contains_points(cut.grid).sum() * cell if len(inside) > 2 else 0.0
        out[f"l0_{round(l0 * 1e3)}"] = {
            "sampled_area_rad2": cut.sampled_area,
            "ray_area_rad2": cut.ray_area,
            "hull_area_rad2": float(hull),
            "convexity": cut.sampled_area / hull if hull else math.nan,
            "reentrant_rays": cut.reentrant_rays,
        }
        margins = m.workspace_margins(np.column_stack([np.full(len(cut.grid), l0), cut.grid]), design)
        n = s["section_resolution"]
        G1, G2 = (np.degrees(cut.grid[:, k]).reshape(n, n) for k in (0, 1))
        ax.contourf(G1, G2, cut.mask.astype(float), levels=[0.5, 1.5], colors=["#cde"])
        shown = [name for name in MARGINS if not name.startswith("l0")]
        for k, name in enumerate(shown):
            values = margins[name].reshape(n, n)
            if values.min() < 0 < values.max():
                colour = f"C{k % 10}" if k < 10 else "k"
                ax.contour(G1, G2, values, levels=[0.0], colors=colour, linestyles="-" if k < 10 else "--")
                ax.plot([], [], color=colour, label=name)
        ax.plot(*np.degrees(cut.boundary).T, "r.", markersize=2, label="ray search")
        ax.set_title(f"l0 = {l0 * 1e3:.0f} mm")
        ax.set_xlabel("theta1 [deg]")
        ax.set_ylabel("theta2 [deg]")
    for ax in axes:
        ax.legend(fontsize=6, loc="lower left")
    fig.suptitle("Workspace sections of section 5.3's example with each constraint's boundary (margin = 0)")
    figures.save(fig, path, dpi=80)
    return out, path.name


def _hull(points: np.ndarray) -> np.ndarray:
    """Convex hull (counter-clockwise) of 2-D points by the monotone chain."""
    pts = sorted(map(tuple, np.round(points, 12)))

    def cross(o, a, b):
        return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])

    lower, upper = [], []
    for p in pts:
        while len(lower) >= 2 and cross(lower[-2], lower[-1], p) <= 0:
            lower.pop()
        lower.append(p)
    for p in reversed(pts):
        while len(upper) >= 2 and cross(upper[-2], upper[-1], p) <= 0:
            upper.pop()
        upper.append(p)
    return np.array(lower[:-1] + upper[:-1])


def _readings(m: Mechanism, s: dict[str, Any]) -> tuple[dict[str, dict[str, bool]], dict[str, Any]]:
    """Section 6's statements under each reading of the prescribed workspace (:data:`READINGS`), for Table
    1's geometry: step 5's leg lengths (the shortest UPS leg over the cylinder's bottom rim at l0 = l0min,
    and 1.8 times it) against Table 1's; the least workspace margin over the task cylinder under section
    5.3's joint limits, refined between the quadrature's nodes, with step 5's legs (to the synthesis's
    feasibility tolerance) and with Table 1's as printed; Fig. 9, the least tilt the ray search reaches over
    the cylinder's height against its tilt radius, to the search's step (step 5's l_min puts the cylinder's
    bottom rim on the stroke limit, where the search's last step may end)."""
    d = m.design()
    statements: dict[str, dict[str, bool]] = {"table1_leg_lengths": {}, "table1_holds_task": {}, "fig9_contains": {}}
    values: dict[str, Any] = {}
    levels = d["l0_min"] + DEFAULTS["task_height"] * np.linspace(0, 1, s["levels"])
    tolerance = registry.problem(PROBLEM).feasibility_tolerance
    for name, tilt in READINGS.items():
        settings = {**DEFAULTS, "task_tilt": tilt}
        shortest = shortest_leg_on_rim(m, d["beta"], d["r"], d["R"], d["l0_min"], settings=settings)
        step5 = m.design({**d, **settings, "l_min": shortest, "l_max": STROKE_RATIO * shortest}).vector()
        printed = m.design({**d, **settings}).vector()
        margin = {key: float(parametrised_global(m, TASK_MARGIN_MIN, m.regions["task"], design[None],
                                                 branch=m.working_mode(None), resolution=s["task_resolution"])[0])
                  for key, design in (("step5_legs", step5), ("table1_legs", printed))}
        step = s["ray_step_deg"] * DEG
        reach = least_tilt(m, step5, levels, rays=s["rays"], step=step)
        legs = {"l_min": shortest * 1e3, "l_max": STROKE_RATIO * shortest * 1e3}
        statements["table1_leg_lengths"][name] = abs(legs["l_min"] - TABLE1_LEGS["l_min"]) <= LEG_ROUNDING
        statements["table1_holds_task"][name] = margin["step5_legs"] >= -tolerance
        statements["fig9_contains"][name] = bool(np.all(reach >= tilt - step * (1 + 1e-9)))
        tilts = {f"{l0 * 1e3:.0f}": float(g / DEG) for l0, g in zip(levels, reach, strict=True)}
        values[name] = {"task_tilt_deg": tilt / DEG, "step5_legs_mm": legs, "least_task_margin": margin,
                        "least_tilt_deg": tilts}
    return statements, values


def _convexity(m: Mechanism, s: dict[str, int]) -> dict[str, Any]:
    """Every section of section 5.3's example over its l0 stroke (``planes`` of them): the ratio of the
    sampled area to its convex hull's and the rays along which the workspace re-enters (not star-shaped)."""
    from matplotlib.path import Path as PolygonPath

    design = m.design({**m.design(), **EXAMPLE_53}).vector()
    result = volume(m, design, planes=s["planes"], resolution=s["section_resolution"], rays=s["rays"])
    planes = []
    for cut in result["sections"]:
        inside = cut.grid[cut.mask.ravel()]
        cell = (math.pi / s["section_resolution"]) ** 2
        hull = PolygonPath(_hull(inside)).contains_points(cut.grid).sum() * cell if len(inside) > 2 else 0.0
        planes.append({"l0_mm": round(cut.l0 * 1e3, 1), "convexity": cut.sampled_area / hull if hull else math.nan,
                       "reentrant_rays": cut.reentrant_rays})
    return {"planes": planes, "volume_sampled": result["sampled"], "volume_ray_search": result["ray_search"]}


def _force_map(m: Mechanism, design: dict[str, float], path: Path) -> str:
    """The largest actuator force holding the payload over the top and bottom of the task cylinder."""
    d = np.array(list(design.values()))
    fig = figures.figure(10, 4.5)
    axes = fig.subplots(1, 2)
    phi = np.linspace(0, 2 * math.pi, 121)
    gamma = np.linspace(0, design["task_tilt"], 31)
    P, G = np.meshgrid(phi, gamma, indexing="ij")
    for ax, l0 in zip(axes, (design["l0_min"], design["l0_min"] + design["task_height"]), strict=True):
        y = np.stack([np.full(P.size, l0), (G * np.cos(P)).ravel(), (G * np.sin(P)).ravel()], axis=1)
        (x,) = evaluate(m.functions["tilt_to_pose"], y, d)
        x = x[:, :, 0]
        (f,) = evaluate(m.functions["actuator_forces"], m.inverse_kinematics(x, d), x, d)
        force = np.abs(f[:, :, 0]).max(axis=1).reshape(P.shape)
        image = ax.contourf(np.degrees(G * np.cos(P)), np.degrees(G * np.sin(P)), force, levels=20)
        ax.set_aspect("equal")
        ax.set_title(f"l0 = {l0 * 1e3:.0f} mm")
        ax.set_xlabel("gamma cos(phi) [deg]")
        ax.set_ylabel("gamma sin(phi) [deg]")
        fig.colorbar(image, ax=ax, label="largest |actuator force| [N]")
    fig.suptitle("pkm's design: actuator forces over the task cylinder (payload at its height above U0)")
    figures.save(fig, path, dpi=80)
    return path.name


def run(folder: Path, *, quick: bool = False) -> dict[str, Any]:
    """Compute every claim and figure into ``folder``; returns the report dictionary."""
    m = registry.mechanism("ups_pu")
    s = _settings(quick)
    rng = np.random.default_rng(2008)
    bar = Progress(5, "zhao2008")
    eq6 = _eq6(m, rng)
    eq8 = _eq8(m, rng)
    fig3, fig3_name = _fig3(m, folder / "determinant_fig3.png", 2 * s["section_resolution"] // 3)
    bar.advance()
    sections, sections_name = _sections(m, folder / "workspace_sections_fig6.png", s)
    bar.advance()
    readings, reading_values = _readings(m, s)
    primary = reading_values[PRIMARY]
    legs = primary["step5_legs_mm"]
    convex = _convexity(m, s)
    result = synthesize(
        registry.problem(PROBLEM),
        resolution=s["synthesis_resolution"],
        baseline_resolution=s["baseline_resolution"],
        starts=s["starts"],
    )
    bar.advance()
    record = synthesis_record(result)
    table1 = result.baselines["table1"].best
    monte_carlo = result.baselines["monte_carlo"]
    dense = sampled_check(m, TASK_MARGIN_MIN, m.regions["task"], np.array(list(result.design.values())),
                          branch=m.working_mode(None), resolution=30)
    force_name = _force_map(m, result.design, folder / "actuator_forces.png")
    bar.advance()
    convexity = min(p["convexity"] for p in convex["planes"])
    reentrant = [p for p in convex["planes"] if p["reentrant_rays"]]
    strokes = {
        "section_5.3_legs": (EXAMPLE_53["l_max"] - EXAMPLE_53["l_min"]) / EXAMPLE_53["l_min"],
        "section_5.3_l0": (EXAMPLE_53["l0_max"] - EXAMPLE_53["l0_min"]) / EXAMPLE_53["l0_min"],
        "table1_legs": (TABLE1_LEGS["l_max"] - TABLE1_LEGS["l_min"]) / TABLE1_LEGS["l_min"],
        "table1_l0": (650.0 - 450.0) / 450.0,
    }
    claims = [
        claim("eq6_as_printed", "eq. 6 (alpha = 90 deg) as printed recovers theta1, theta2 from the leg lengths",
              0.0, eq6["as_printed"], "rad", "match" if eq6["as_printed"] < 1e-9 else "differs",
              "as printed theta1 reads l2 and its 'a' reads l1: the legs are swapped"),
        claim("eq6_corrected", "eq. 6 with l1 and l2 swapped back against the inverse kinematics (eq. 4)",
              0.0, eq6["corrected"], "rad", "match" if eq6["corrected"] < 1e-9 else "differs",
              "largest angle error over 50 random poses"),
        claim("eq8_physical", "actuator forces of the statics against virtual work (J^T f = generalised force)",
              0.0, eq8["physical"], "-", "match" if eq8["physical"] < 1e-9 else "differs",
              "pkm's wrench matrix: moments with the lever arm, the U joint's torque about X x Rx(theta1) Y"),
        claim("eq8_as_printed", "eq. 8 as printed (unit moment axes, torque about Z) against virtual work",
              0.0, eq8["as_printed"], "-", "match" if eq8["as_printed"] < 1e-9 else "differs",
              "relative to the largest generalised force"),
        claim("eq9_sign_at_home", "|q| > 0 at theta1 = theta2 = 0 for Fig. 3's design (eq. 9)", "> 0",
              fig3["det_at_home"], "m^2/rad^2", "match" if fig3["det_at_home"] > 0 else "differs",
              "pkm's workspace keeps the determinant's home sign instead; the paper's [q] columns are (theta1, "
              "theta2, l0), a cyclic reordering of pkm's, so the determinants are equal"),
        claim("workspace_convex", "the actual workspace is convex (section 6, Fig. 5)", 1.0,
              {"least_hull_ratio": convexity, "planes_with_reentrant_rays": reentrant}, "-",
              "match" if convexity > 0.99 and not reentrant else "differs",
              f"section 5.3's example over {s['planes']} l0 planes in (theta1, theta2): the least ratio of a section's "
              "sampled area to its convex hull's, and the planes where a ray of the ray search re-enters the "
              "workspace (where its star-shape assumption fails)"),
        claim("stroke_rule_section_5.3", "eq. 10 for section 5.3's example: (l_max - l_min) / l_min <= 0.8",
              STROKE_LIMIT, strokes["section_5.3_legs"], "-",
              "match" if strokes["section_5.3_legs"] <= STROKE_LIMIT else "differs",
              "l_min = 320, l_max = 578 mm"),
        claim("stroke_rule_table1", "eq. 10 for Table 1's legs", STROKE_LIMIT, strokes["table1_legs"], "-",
              "match" if strokes["table1_legs"] <= STROKE_LIMIT else "differs", "l_min = 396, l_max = 712 mm"),
        claim("table1_leg_lengths", "Table 1's l_{1,2 min}, l_{1,2 max} [mm] by step 5 from its geometry",
              TABLE1_LEGS, legs, "mm", status(readings["table1_leg_lengths"][PRIMARY]),
              f"step 5: the shortest leg over the cylinder's bottom rim (tilt {primary['task_tilt_deg']:.0f} deg at "
              f"l0 = l0min = 450 mm) and 1.8 times it; reproduced by {reproduced_by(readings, 'table1_leg_lengths')}"),
        claim("table1_holds_task", "Table 1's design holds the prescribed workspace under section 5.3's joint limits "
              "(least workspace margin over the task cylinder >= 0)", ">= 0", primary["least_task_margin"], "m, or -",
              status(readings["table1_holds_task"][PRIMARY]),
              f"with step 5's leg lengths; reproduced by {reproduced_by(readings, 'table1_holds_task')}; with "
              "Table 1's legs as printed (rounded to the mm) the least margin is "
              f"{primary['least_task_margin']['table1_legs']:.2g}"),
        claim("fig9_contains", "Fig. 9: the actual workspace contains the prescribed one (the least tilt the ray "
              "search reaches at each l0 of the task is at least gamma)", f">= {primary['task_tilt_deg']:.0f}",
              primary["least_tilt_deg"], "deg", status(readings["fig9_contains"][PRIMARY]),
              f"Table 1's geometry with step 5's legs, ray steps of {s['ray_step_deg']} deg over {s['rays']} rays (to "
              "one step); "
              f"reproduced by {reproduced_by(readings, 'fig9_contains')}"),
        claim("table1_optimal", "Table 1 is optimal for pi R^2 l0min F with the task cylinder in the workspace",
              None, {"table1_verified": table1.verified_objective, "table1_feasible": table1.feasible,
                     "pkm_verified": result.verified_objective},
              "m^3 N",
              "differs" if (not table1.feasible or result.verified_objective < table1.verified_objective) else "match",
              f"same model with pkm's choices (payload, l0max = l0min + h, the apex-angle reading: "
              f"docs/papers/zhao2008.md); Table 1 as printed is {'feasible' if table1.feasible else 'infeasible'} "
              "there"),
    ]
    bar.advance()
    bar.close()
    text = (
        f"IPOPT minimises pi R^2 l0min F over beta, r, R, l0min, l_min (alpha = 90 deg, l_max = 1.8 l_min): "
        f"{', '.join(f'{k} = {v:.4g}' for k, v in result.variables.items())} with {result.objective:.4g} m^3 N "
        f"(verified {result.verified_objective:.4g}; its cylinder's least margin on a dense grid "
        f"{float(dense):.3g} over {dense.points} points), in {result.optimizer['wall_time_s']:.1f} s and "
        f"{result.optimizer['evaluations']} evaluations. The paper's Monte Carlo search on the same model "
        f"({monte_carlo.evaluations} designs, {monte_carlo.wall_time_s:.1f} s) reaches "
        f"{monte_carlo.best.objective:.4g}; Table 1 has {table1.objective:.4g} and is "
        f"{'feasible' if table1.feasible else 'infeasible'}."
    )
    return {
        "paper": "zhao2008",
        "title": TITLE,
        "summary": "Lengths in metres unless a claim says mm. Section 6's gamma_u = 60 deg is read as the task "
        "cone's apex angle (a tilt radius of 30 deg), the reading that reproduces Table 1 (see readings); the "
        "synthesis keeps section 5.3's joint limits and holds a payload of 50 kg 0.2 m above U0 (the paper states "
        "none).",
        "settings": {**s, "quick": quick, "margins": list(MARGINS)},
        "claims": claims,
        "readings": readings,
        "reading_values": reading_values,
        "beyond_paper": {"syntheses": [{**record, "dense_margin": float(dense), "text": text}], "text": text},
        "figures": [fig3_name, sections_name, force_name],
        "sections": sections,
        "convexity": convex,
    }
