"""Nam and Park 2006: the 2-DOF manipulator with revolute actuators and a passive leg. Checks eqs. 6, 9,
11, 12-13, 14-15, 20 and 24-25 against pkm's derivation, the number of forward solutions, the
singularity-free claim over the design space, the rotational range, the trends of section 6 (Figs. 4-9)
in both readings of the indices, and the composed optimum; draws the atlases of Figs. 4-7, the
workspaces with 1/kappa and the singularity loci of Fig. 8 and the actuator limits of Fig. 9.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import numpy as np

from pkm import figures, registry
from pkm.batch import evaluate
from pkm.mechanism import Mechanism
from pkm.models.passive_leg import nam2006
from pkm.progress import Progress
from pkm.reproduce.report import claim, reproduced_by, status, synthesis_record
from pkm.synthesis import synthesize

TITLE = "Nam, Park 2006: kinematics and optimization of a 2-DOF parallel manipulator with a passive leg"
PROBLEM = "passive_leg.max_composed"
FIG8 = ((0.9, 1.2), (1.2, 0.9), (1.2, 1.2))
ETA_NAMES = ("eta_1 (GCI)", "eta_2 (manipulability)", "eta_3 (space utilisation)")
ROUND_OFF = 1e-9
FK_CONFIGURATIONS = 1000  # random actuator angles per design for the count of forward solutions


def _settings(quick: bool) -> dict[str, int | None]:
    if quick:
        return {"atlas": 11, "quadrature": 4, "poses": 40, "fig8": 50, "synthesis_resolution": 4,
                "baseline_resolution": 9, "starts": 1}
    return {"atlas": 31, "quadrature": 8, "poses": 200, "fig8": 160, "synthesis_resolution": None,
            "baseline_resolution": 61, "starts": 3}


def _design(m: Mechanism, r: float, l_b: float) -> np.ndarray:
    return nam2006.chart_designs(m, np.array([r]), np.array([l_b]))[0]


def _random_poses(m: Mechanism, d: np.ndarray, count: int, rng: np.random.Generator) -> np.ndarray:
    """Poses drawn in (theta, l_c) inside the outer boundary."""
    theta = rng.uniform(-1.3, 1.3, count)
    outer = m.workspace_boundary(theta, d)["l_CM"]
    l_c = rng.uniform(0.05, 0.95, count) * outer
    return np.column_stack([-l_c * np.sin(theta), l_c * np.cos(theta)])


def _wrap(a: np.ndarray) -> np.ndarray:
    return np.mod(a + math.pi, 2 * math.pi) - math.pi


def _equations(m: Mechanism, rng: np.random.Generator, count: int) -> dict[str, float]:
    """Largest errors of the paper's equations, as printed and as derived, over random poses of every mode."""
    d = _design(m, 1.2, 1.2)
    x = _random_poses(m, d, count, rng)
    keys = ("eq6", "eq6_printed", "eq9", "eq9_printed", "eq11", "eq11_printed", "eq20", "eq24_printed", "fk_missing")
    out = dict.fromkeys(keys, 0.0)
    for branch in m.working_modes:
        q = m.inverse_kinematics(x, d, mode=branch.name, passive=True)
        ok = np.all(np.isfinite(q), axis=1)
        q, xs = q[ok], x[ok]
        phi, phi_printed = evaluate(m.functions["paper_inverse"], xs, np.array(branch.signs), d)
        out["eq6"] = max(out["eq6"], float(np.abs(_wrap(phi[:, :, 0] - q[:, :2])).max()))
        out["eq6_printed"] = max(out["eq6_printed"], float(np.abs(_wrap(phi_printed[:, :, 0] - q[:, :2])).max()))
        _, eq11, eq11_printed, eq9, eq9_printed = evaluate(m.functions["paper_forward"], q, d)
        scale = (d[2] + d[3]) ** 2
        out["eq9"] = max(out["eq9"], float(np.abs(eq9).max() / scale))
        out["eq9_printed"] = max(out["eq9_printed"], float(np.abs(eq9_printed).max() / scale))
        out["eq11"] = max(out["eq11"], float(np.abs(eq11).max() / scale**4))
        out["eq11_printed"] = max(out["eq11_printed"], float(np.abs(eq11_printed).max() / scale**4))
        J_q, J_x, det_jx, eq24, _ = evaluate(m.functions["paper_first_order"], q, xs, d)
        J = m.jacobian(xs, d, mode=branch.name)
        paper = np.linalg.solve(J_q, J_x)
        out["eq20"] = max(out["eq20"], float(np.abs(paper - J).max() / np.abs(J).max()))
        out["eq24_printed"] = max(out["eq24_printed"], float(np.abs(eq24 - det_jx).max() / np.abs(det_jx).max()))
        roots = m.forward_solutions(q[:, :2], d)
        miss = np.nanmin(np.linalg.norm(roots.pose - xs[:, None, :], axis=2), axis=1)
        out["fk_missing"] = max(out["fk_missing"], float(miss.max()))
    return out


def _forward_counts(m: Mechanism, rng: np.random.Generator, count: int) -> dict[str, Any]:
    """Numbers of real forward solutions over random actuator angles of random designs of the space."""
    counts = []
    for _ in range(8):
        r, l_b = rng.uniform(0.6, 2.0, 2)
        d = _design(m, r, l_b)
        q = rng.uniform(-math.pi, math.pi, size=(count, 2))
        counts.append(m.forward_solutions(q, d).count)
    counts = np.concatenate(counts)
    return {"max": int(counts.max()), "histogram": {int(k): int((counts == k).sum()) for k in np.unique(counts)}}


def _boundaries(m: Mechanism) -> dict[str, float]:
    """eqs. 12-13 against the reach and the joint range sampled along rays, and the printed forms."""
    d = _design(m, 1.2, 1.2)
    theta = np.linspace(-1.4, 1.4, 29)
    b = m.workspace_boundary(theta, d)
    sampled = np.array([_last_along_ray(lambda x: m.reachable(x, d, mode="out_out"), t, 3 * b["l_CM"].max())
                        for t in theta])
    inner_design = m.design({"R": 1.0, "r": 0.5, "l_a": 1.2, "l_b": 0.9})
    inner = m.workspace_boundary(theta, inner_design)
    real = np.isfinite(inner["l_cm"]) & (inner["l_cm"] < inner["l_CM"])

    def above_inner(x):
        margins = m.region_margins(x, inner_design, mode="out_out")
        return (margins["angle_b1"] < 0) | (margins["angle_b2"] < 0)

    sampled_inner = np.array([_last_along_ray(above_inner, t, inner["l_CM"][k]) if real[k] else math.nan
                              for k, t in enumerate(theta)])
    return {
        "l_CM_error": float(np.abs(sampled - b["l_CM"]).max()),
        "l_CM_printed_ratio": float(np.mean(b["l_CM_printed"] / b["l_CM"])),
        "l_cm_error": float(np.abs(sampled_inner[real] - inner["l_cm"][real]).max()) if real.any() else math.nan,
        "l_cm_printed_ratio": float(np.mean(inner["l_cm_printed"][real] / inner["l_cm"][real])),
        "inner_thetas": int(real.sum()),
    }


def _last_along_ray(holds, theta: float, length: float, steps: int = 60) -> float:
    """The largest l_c in (0, length) where ``holds`` at C = l_c (-sin theta, cos theta), from a scan and
    a bisection (a ray along which the set is an interval from near 0)."""
    grid = np.linspace(1e-6, length, 400)
    inside = holds(np.column_stack([-grid * math.sin(theta), grid * math.cos(theta)]))
    if not inside.any():
        return math.nan
    k = int(np.flatnonzero(inside)[-1])
    if k == len(grid) - 1:
        return float(grid[-1])
    lo, hi = grid[k], grid[k + 1]
    for _ in range(steps):
        mid = (lo + hi) / 2
        if holds(np.array([[-mid * math.sin(theta), mid * math.cos(theta)]]))[0]:
            lo = mid
        else:
            hi = mid
    return float(lo)


def _workspace_area(m: Mechanism, resolution: int) -> dict[str, float]:
    """The area inside eq. 12's boundary by the region's quadrature, and of the poses of a grid over the
    workspace box that mode out_out reaches within section 4's limits and |theta| <= theta_max."""
    d = _design(m, 1.2, 1.2)
    box = m.workspace_box(d)
    xs = np.linspace(*box[0], resolution + 1)
    ys = np.linspace(*box[1], resolution // 2 + 1)
    X, Y = np.meshgrid((xs[1:] + xs[:-1]) / 2, (ys[1:] + ys[:-1]) / 2, indexing="ij")
    poses = np.column_stack([X.ravel(), Y.ravel()])
    margins = m.region_margins(poses, d, mode=nam2006.MODE)
    with np.errstate(invalid="ignore"):
        inside = np.all([v >= 0 for v in margins.values()], axis=0)
    inside &= np.abs(np.arctan2(-poses[:, 0], poses[:, 1])) <= d[4]
    cell = (xs[1] - xs[0]) * (ys[1] - ys[0])
    quadrature = float(m.global_index("region_measure", d, region="workspace"))
    return {"quadrature": quadrature, "sampled": float(inside.sum() * cell), "grid": int(inside.size)}


def _existence(m: Mechanism, rng: np.random.Generator) -> dict[str, int]:
    """Eqs. 14-15: where each radicand keeps its sign over theta in (-pi/2, pi/2) against the stated
    conditions, for random designs (R = 1)."""
    theta = np.linspace(-math.pi / 2 + 1e-6, math.pi / 2 - 1e-6, 721)
    wrong14 = wrong15 = 0
    for _ in range(300):
        r, l_a, l_b = rng.uniform(0.2, 2.5, 3)
        d = np.array([1.0, r, l_a, l_b, 1.4])
        fn = m.functions["workspace_boundary"]
        *_, eq14, eq15 = evaluate(fn, theta[:, None], d)
        wrong14 += bool((eq14.min() >= 0) != (l_a + l_b > max(r, 1 - r)))
        wrong15 += bool((eq15.max() < 1e-12) != (l_b - l_a >= 1 - r))
    return {"eq14_disagreements": wrong14, "eq15_disagreements": wrong15, "designs": 300}


def _atlas(m: Mechanism, s: dict[str, int], which: nam2006.Reading) -> dict[str, np.ndarray]:
    u = np.linspace(0.5, 2.0, s["atlas"])
    U, V = np.meshgrid(u, u, indexing="ij")
    values = nam2006.etas(m, nam2006.chart_designs(m, U.ravel(), V.ravel()), which, resolution=s["quadrature"])
    values = values.reshape(len(u), len(u), 3)
    bounds = nam2006.extremes(which, s["atlas"], s["quadrature"])
    hat = np.stack(nam2006.normalised(values, bounds, which.normalise), axis=-1)
    return {"u": u, "values": values, "hat": hat, "composed": np.prod(hat, axis=-1), "bounds": bounds,
            "in_space": (U + V > 1)}


def _trend(atlas: dict[str, Any], k: int | None) -> dict[str, float]:
    """Fractions of admissible neighbours along l_b and r where the index increases, and the relative
    spread over r (at each l_b) for r >= 1.2."""
    z = atlas["composed"] if k is None else atlas["values"][:, :, k]
    u = atlas["u"]
    along_lb = np.diff(z, axis=1)
    along_r = np.diff(z, axis=0)
    ok_lb, ok_r = np.isfinite(along_lb), np.isfinite(along_r)
    wide = z[u >= 1.2]
    wide = wide[:, np.any(np.isfinite(wide), axis=0)]
    with np.errstate(invalid="ignore", divide="ignore"):
        spread = np.nanmax((np.nanmax(wide, axis=0) - np.nanmin(wide, axis=0)) / np.nanmean(wide, axis=0))
    rows_low = along_r[:, u < 1.2]
    rows_high = along_r[:, u > 1.2]
    return {
        "increasing_in_l_b": float(np.mean(along_lb[ok_lb] > 0)),
        "increasing_in_r": float(np.mean(along_r[ok_r] > 0)),
        "spread_over_r_from_1.2": float(spread),
        "increasing_in_r_l_b_below_1.2": float(np.mean(rows_low[np.isfinite(rows_low)] > 0)),
        "increasing_in_r_l_b_above_1.2": float(np.mean(rows_high[np.isfinite(rows_high)] > 0)),
        "admissible_fraction": float(np.mean(np.isfinite(z))),
    }


STATEMENTS = {
    "gci_flat_in_r_rising_in_l_b": lambda t: t[0]["spread_over_r_from_1.2"] < 0.05 and t[0]["increasing_in_l_b"] > 0.9,
    "manipulability_flat_in_r_rising_in_l_b": lambda t: (t[1]["spread_over_r_from_1.2"] < 0.05
                                                       and t[1]["increasing_in_l_b"] > 0.99),
    "manipulability_rising_in_l_b": lambda t: t[1]["increasing_in_l_b"] > 0.99,
    "space_utilization_rising_in_l_b": lambda t: t[2]["increasing_in_l_b"] > 0.9,
    "space_utilization_crossover_at_l_b_1.2": lambda t: (t[2]["increasing_in_r_l_b_below_1.2"] > 0.5
                                                       and t[2]["increasing_in_r_l_b_above_1.2"] < 0.5),
    "composed_rising_in_l_b": lambda t: t["composed"]["increasing_in_l_b"] > 0.9,
    "composed_flat_in_r": lambda t: t["composed"]["spread_over_r_from_1.2"] < 0.05,
}


def _statements(m: Mechanism, trends: dict[str, Any]) -> dict[str, dict[str, bool]]:
    """Which statement of section 6 each reading reproduces, and eta_3's scale independence (the same
    design at R = 1 and R = 2)."""
    out = {key: {name: bool(test(t)) for name, t in trends.items()} for key, test in STATEMENTS.items()}
    design = _design(m, 1.2, 1.2)
    doubled = design.copy()
    doubled[:4] *= 2
    out["space_utilization_scale_free"] = {}
    for name, reading in nam2006.READINGS.items():
        pair = [float(m.global_index("space_utilization", d, region=reading.region)) for d in (design, doubled)]
        out["space_utilization_scale_free"][name] = bool(abs(pair[1] - pair[0]) <= 1e-9 * abs(pair[0]))
    return out


def _draw_atlases(atlas: dict[str, Any], path: Path, title: str) -> str:
    fig = figures.figure(13, 3.6)
    u = atlas["u"]
    panels = [(atlas["hat"][:, :, k], f"normalised {ETA_NAMES[k]}") for k in range(3)]
    panels.append((atlas["composed"], "composed eta (eq. 31)"))
    for ax, (z, label) in zip(fig.subplots(1, 4), panels, strict=True):
        ax.set_facecolor("0.8")
        limits = figures.robust_limits(z)
        image = ax.contourf(u, u, z.T, levels=limits.levels(), cmap="viridis", extend=limits.extend)
        ax.set_xlabel("r / R")
        ax.set_ylabel("l_b / R")
        ax.set_title(label, fontsize=9)
        figures.colour_bar(fig, image, limits, ax=ax, label="")
    fig.suptitle(f"{title}; grey: not admissible (a folded leg, a type-2 singularity or a joint limit inside "
                 "the region)", fontsize=9)
    figures.save(fig, path, dpi=80)
    return path.name


def _fig8(m: Mechanism, s: dict[str, int], path: Path) -> tuple[dict[str, Any], str]:
    """1/kappa_f over each Fig. 8 design's reachable poses on mode out_out with the outer boundary and
    the loci det J_q = 0 (type 1) and det J_x = 0 (type 2)."""
    fig = figures.figure(14, 3.6)
    out = {}
    axes = fig.subplots(1, 3)
    for ax, (r, l_b) in zip(axes, FIG8, strict=True):
        d = _design(m, r, l_b)
        reach = d[2] + d[3]
        xs = np.linspace(-reach, reach, s["fig8"])
        ys = np.linspace(1e-3, reach, s["fig8"] // 2)
        X, Y = np.meshgrid(xs, ys, indexing="ij")
        poses = np.column_stack([X.ravel(), Y.ravel()])
        kappa = m.local_index("inverse_condition_f", poses, d, mode=nam2006.MODE).reshape(X.shape)
        dets = m.singularity_measures(poses, d, mode=nam2006.MODE)
        margins = m.region_margins(poses, d, mode=nam2006.MODE)
        theta = np.linspace(-d[4], d[4], 200)
        outer = m.workspace_boundary(theta, d)["l_CM"]
        image = ax.contourf(X, Y, kappa, levels=np.linspace(0, 1, 11), cmap="viridis")
        ax.contour(X, Y, dets["det_J_x"].reshape(X.shape), levels=[0.0], colors="r")
        ax.contour(X, Y, np.minimum(margins["angle_b1"], margins["angle_b2"]).reshape(X.shape), levels=[0.0],
                   colors="orange", linestyles="dashed")
        ax.plot(-outer * np.sin(theta), outer * np.cos(theta), "k-", lw=1)
        ax.set_aspect("equal")
        ax.set_title(f"r = {r}, l_b = {l_b}", fontsize=9)
        ax.set_xlabel("x_c")
        ax.set_ylabel("y_c")
        unreached = np.isnan(kappa) & (np.hypot(X, Y) < np.interp(np.arctan2(-X, Y), theta, outer))
        bands = np.hypot(X, Y) / np.interp(np.arctan2(-X, Y), theta, outer)
        outer_band = kappa[(bands > 0.7) & (bands < 1)]
        inner_band = kappa[(bands > 0.05) & (bands < 0.35)]
        out[f"r={r},l_b={l_b}"] = {
            "unreached_inside_l_CM": int(unreached.sum()),
            "hole_centre": [float(np.mean(np.abs(X[unreached]))), float(np.mean(Y[unreached]))]
            if unreached.any() else None,
            "mean_inverse_kappa_outer_band": float(np.nanmean(outer_band)),
            "mean_inverse_kappa_inner_band": float(np.nanmean(inner_band)),
            "type2_locus_inside": bool(np.nanmin(dets["det_J_x"]) < 0 < np.nanmax(dets["det_J_x"])),
        }
    fig.colorbar(image, ax=list(axes), label="1/kappa_f", shrink=0.9)
    fig.suptitle("Fig. 8 (mode out_out, R = 1): black l_CM (eq. 12 as derived), red det J_x = 0 (type 2),\n"
                 "orange dashed angle b_i = pi (section 4), white inside l_CM: unreached (a folded leg, type 1)",
                 fontsize=9)
    figures.save(fig, path, dpi=80)
    return out, path.name


def _fig9(m: Mechanism, path: Path) -> tuple[dict[str, float], str]:
    """The actuator angles over the workspace of Fig. 8c's design at each theta: their extremes, and
    whether phi1's maximum for theta >= 0 lies on the outer boundary."""
    d = _design(m, 1.2, 1.2)
    theta = np.linspace(-1.4, 1.4, 57)
    outer = m.workspace_boundary(theta, d)["l_CM"]
    frac = np.linspace(0.01, 1.0, 200)
    L = outer[:, None] * frac[None, :]
    T = np.repeat(theta[:, None], len(frac), axis=1)
    poses = np.column_stack([(-L * np.sin(T)).ravel(), (L * np.cos(T)).ravel()])
    q = m.inverse_kinematics(poses * (1 - 1e-9), d, mode=nam2006.MODE).reshape(len(theta), len(frac), 2)
    at_outer = np.nanargmax(q[:, :, 0], axis=1) >= len(frac) - 2
    positive = theta >= 0
    fig = figures.figure(6, 4)
    ax = fig.subplots()
    for k, style in ((0, "b"), (1, "r")):
        ax.fill_between(np.degrees(theta), np.degrees(np.nanmin(q[:, :, k], axis=1)),
                        np.degrees(np.nanmax(q[:, :, k], axis=1)), color=style, alpha=0.3, label=f"phi{k + 1}")
    ax.set_xlabel("theta [deg]")
    ax.set_ylabel("actuator angle [deg]")
    ax.set_title("operating ranges of the actuators (Fig. 9), r = l_b = 1.2", fontsize=9)
    ax.legend()
    figures.save(fig, path, dpi=80)
    return {"phi1_max_on_outer_boundary_theta_ge_0": float(np.mean(at_outer[positive]))}, path.name


def run(folder: Path, *, quick: bool = False) -> dict[str, Any]:
    """Compute every claim and figure into ``folder``; returns the report dictionary."""
    m = registry.mechanism("passive_leg")
    s = _settings(quick)
    rng = np.random.default_rng(2006)
    bar = Progress(6, "nam2006")
    eqs = _equations(m, rng, s["poses"])
    counts = _forward_counts(m, rng, FK_CONFIGURATIONS)
    bounds = _boundaries(m)
    existence = _existence(m, rng)
    area = _workspace_area(m, s["fig8"] * 2)
    bar.advance()
    atlases = {name: _atlas(m, s, r) for name, r in nam2006.READINGS.items()}
    trends = {name: {k: _trend(a, k) for k in range(3)} | {"composed": _trend(a, None)}
              for name, a in atlases.items()}
    drawn = [_draw_atlases(atlases["supported"], folder / "atlases_figs4-7.png", "supported reading"),
             _draw_atlases(atlases["literal"], folder / "atlases_figs4-7_literal.png", "literal reading")]
    bar.advance()
    fig8, fig8_name = _fig8(m, s, folder / "workspaces_fig8.png")
    fig9, fig9_name = _fig9(m, folder / "actuator_limits_fig9.png")
    drawn += [fig8_name, fig9_name]
    bar.advance()
    result = synthesize(registry.problem(PROBLEM), resolution=s["synthesis_resolution"],
                        baseline_resolution=s["baseline_resolution"], starts=s["starts"])
    bar.advance()
    rotation = {f"r={r:.4g},l_b={lb:.4g}": _rotation_deg(m, r, lb)
                for r, lb in (*FIG8, tuple(result.variables.values()))}
    eq25 = _eq25(m)
    in_space = atlases["supported"]["in_space"]
    admissible = float(np.mean(np.isfinite(atlases["supported"]["composed"])[in_space]))
    t, tl = trends["supported"], trends["literal"]
    readings = _statements(m, trends)
    claims = [
        claim("eq6_as_printed", "eq. 6 as printed (r_i - alpha_i in the denominator) gives the actuator angles", 0.0,
              eqs["eq6_printed"], "rad", status(eqs["eq6_printed"] < ROUND_OFF), "largest angle error, four modes"),
        claim("eq6_corrected", "eq. 6 with gamma_i - alpha_i in the denominator", 0.0, eqs["eq6"], "rad",
              status(eqs["eq6"] < ROUND_OFF), "its second case, -(gamma + alpha)/(2 beta), is tan(phi/2), not phi"),
        claim("eq9_as_printed", "eq. 9 as printed holds at assembled configurations", 0.0, eqs["eq9_printed"], "-",
              status(eqs["eq9_printed"] < ROUND_OFF), "relative to (l_a + l_b)^2; from eq. 8 it is (A + 2B) s^2 + "
              f"4 C s + (A - 2B) = 0, whose residual is {eqs['eq9']:.1e}"),
        claim("eq11_as_printed", "eq. 11 as printed holds at assembled configurations", 0.0, eqs["eq11_printed"], "-",
              status(eqs["eq11_printed"] < ROUND_OFF), "eq. 8's factors 2 make the last term 4 (B2 C1 - B1 C2)^2; "
              f"with it the residual is {eqs['eq11']:.1e}"),
        claim("fk_six_solutions", "the forward kinematics has up to six solutions (eq. 11): six occur", 6,
              counts["max"], "-", status(counts["max"] == 6),
              f"real roots over random actuator angles and designs: {counts['histogram']}; the IK pose is among "
              f"them to {eqs['fk_missing']:.1e} m"),
        claim("eq12_as_printed", "l_CM of eq. 12 as printed against the derived outer boundary (ratio)", 1.0,
              bounds["l_CM_printed_ratio"], "-", status(abs(bounds["l_CM_printed_ratio"] - 1) < 1e-9),
              "the printed /2 halves the boundary"),
        claim("eq12_derived", "l_CM = -R|sin theta| + sqrt(...) against the reach sampled along rays", 0.0,
              bounds["l_CM_error"], "m", status(bounds["l_CM_error"] < 1e-6), "r = l_b = 1.2, 29 angles"),
        claim("eq13_derived", "l_cm = R|sin theta| + sqrt(...) against the joint range angle b_i < pi sampled "
              "along rays", 0.0, bounds["l_cm_error"], "m", status(bounds["l_cm_error"] < 1e-6),
              f"R = 1, r = 0.5, l_a = 1.2, l_b = 0.9 (l_b - l_a < R - r), {bounds['inner_thetas']} angles where l_cm "
              f"is real; printed/derived = {bounds['l_cm_printed_ratio']:.3f}"),
        claim("workspace_area", "the workspace inside eq. 12's boundary (section 4): its area by the region's "
              "quadrature against the sampled workspace", None, area, "m^2",
              "not_stated" if abs(area["sampled"] - area["quadrature"]) <= 1e-2 * area["quadrature"] else "differs",
              "the paper states no area; agreement to 1 % means match of the two computations; r = l_b = 1.2; "
              "sampled: grid cells whose centre mode out_out reaches within the joint ranges of "
              "section 4 and |theta| <= theta_max"),
        claim("eq14_condition", "eq. 14 holds for every theta iff l_a + l_b > max(r, R - r)", 0,
              existence["eq14_disagreements"], "designs", status(existence["eq14_disagreements"] == 0),
              f"of {existence['designs']} random designs; l_CM > 0 needs more: (l_a + l_b)^2 > R^2 + r^2 - 2 r R "
              "cos theta"),
        claim("eq15_condition", "eq. 15 holds for every theta iff l_b - l_a >= R - r", 0,
              existence["eq15_disagreements"], "designs", status(existence["eq15_disagreements"] == 0),
              f"of {existence['designs']} random designs (with equality the radicand touches 0 at theta = 0, l_c = 0)"),
        claim("eq20_jacobian", "J = J_q^-1 J_x of eqs. 19-21 against pkm's loop-closure J", 0.0, eqs["eq20"], "-",
              status(eqs["eq20"] < ROUND_OFF), "eq. 16 as printed has the wrong sign of the theta term for leg 2; "
              "eq. 20's - Z_2 has the right one"),
        claim("eq24_as_printed", "eq. 24 as printed equals -2 l_c det J_x", 0.0, eqs["eq24_printed"], "-",
              status(eqs["eq24_printed"] < ROUND_OFF), "relative; the derived second term is 4 r (...)(...)"),
        claim("eq25_always", "X1 Y2 - X2 Y1 <= 0 everywhere in the workspace (eq. 25)", 0.0,
              eq25["fraction"], "-", status(eq25["fraction"] == 0),
              "fraction of 2000 random poses of r = l_b = 1.2 (out_out) where it fails; the least -2 l_c det J_x "
              f"there is {eq25['least_det_measure_there']:.3g} m^3"
              + (" (> 0: eq. 26's argument fails but not its conclusion for this design)"
                 if eq25["least_det_measure_there"] > 0 else "")),
        claim("singularity_free", "every design with l_b - l_a = R - r is free of singularities in its workspace",
              1.0, admissible, "fraction of the design space", status(admissible > 0.999),
              "admissible = no folded leg (type 1: r < R), no type-2 singularity and no joint limit of section 4 "
              "inside the region; fails for r < R and for small l_b"),
        claim("rotation_90", "rotational capability of about +-90 deg", 90.0, rotation, "deg",
              status(all(v >= 90.0 - 1e-9 for v in rotation.values())),
              "the largest |theta| with l_CM > 0 ((l_a + l_b)^2 > R^2 + r^2 - 2 r R cos theta), capped at 90 deg, "
              "at Fig. 8's designs and pkm's optimum"),
        claim("trend_gci", "GCI: little variation for r > 1.2, increases with l_b (Fig. 4)", None,
              t[0], "-", status(t[0]["spread_over_r_from_1.2"] < 0.05 and t[0]["increasing_in_l_b"] > 0.9),
              "supported reading, admissible designs; reproduced by "
              f"{reproduced_by(readings, 'gci_flat_in_r_rising_in_l_b')}"),
        claim("trend_manipulability", "manipulability: little variation with r, increases monotonically with l_b "
              "(Fig. 5)", None, {"supported": t[1], "literal": tl[1]}, "-",
              status(t[1]["spread_over_r_from_1.2"] < 0.05 and t[1]["increasing_in_l_b"] > 0.99),
              "|det J_f| increases with l_b but grows with r (the mechanism grows with r at fixed R); the literal "
              "|det J| decreases with l_b; rising in l_b in "
              f"{reproduced_by(readings, 'manipulability_rising_in_l_b')}"),
        claim("trend_space_utilization", "space utilisation increases with l_b; with r for l_b < 1.2, against r for "
              "l_b > 1.2 (Fig. 6)", None, {"supported": t[2], "literal": tl[2]}, "-",
              status(t[2]["increasing_in_l_b"] > 0.9 and t[2]["increasing_in_r_l_b_below_1.2"] > 0.5
                      and t[2]["increasing_in_r_l_b_above_1.2"] < 0.5),
              "measured in the plane (dW = l_c dtheta dl_c); eq. 28's dtheta dl_c decreases with r at every l_b; "
              f"crossover reproduced by {reproduced_by(readings, 'space_utilization_crossover_at_l_b_1.2')}, "
              "scale-free in "
              f"{reproduced_by(readings, 'space_utilization_scale_free')}"),
        claim("trend_composed", "composed index increases with l_b, r has little effect (Fig. 7)", None,
              t["composed"], "-",
              status(t["composed"]["increasing_in_l_b"] > 0.9 and t["composed"]["spread_over_r_from_1.2"] < 0.05),
              f"rising in l_b in {reproduced_by(readings, 'composed_rising_in_l_b')}; flat in r in "
              f"{reproduced_by(readings, 'composed_flat_in_r')}"),
        claim("fig8_inverse_kappa_outer", "1/kappa is greater nearer the outer boundary (Fig. 8)", None,
              {k: [v["mean_inverse_kappa_inner_band"], v["mean_inverse_kappa_outer_band"]] for k, v in fig8.items()},
              "-", status(all(v["mean_inverse_kappa_outer_band"] > v["mean_inverse_kappa_inner_band"]
                               for v in fig8.values())),
              "mean 1/kappa_f at l_c/l_CM in (0.05, 0.35) and in (0.7, 1)"),
        claim("fig8_small_r_distortion", "for r < R the workspace inside l_CM is whole and its 1/kappa contours are "
              "only distorted, near (+-0.5, 0.5) (Fig. 8a)", [0.5, 0.5], fig8["r=0.9,l_b=1.2"]["hole_centre"], "m",
              status(fig8["r=0.9,l_b=1.2"]["unreached_inside_l_CM"] == 0),
              "pkm finds two holes (mirror images, centre (+-|x|, y)) inside l_CM that a folded leg cannot reach: a "
              "type-1 locus inside the workspace, where the paper sees distorted contours"),
        claim("fig9_first_actuator", "for theta >= 0 phi1 reaches its maximum on the outer boundary (Fig. 9)", 1.0,
              fig9["phi1_max_on_outer_boundary_theta_ge_0"], "fraction of theta", status(
                  fig9["phi1_max_on_outer_boundary_theta_ge_0"] > 0.99), "r = l_b = 1.2"),
        claim("optimum_l_b", "the composed optimum lies at the largest l_b (section 6.2)", 2.0,
              result.variables["l_b"], "l_b / R", status(abs(result.variables["l_b"] - 2.0) < 1e-3),
              f"pkm's optimum r/R = {result.variables['r']:.4g}; the paper states no optimal r"),
    ]
    bar.advance()
    record = synthesis_record(result)
    text = (
        f"IPOPT maximises the composed index (supported reading) over r/R, l_b/R in [0.5, 2]: "
        f"{', '.join(f'{k} = {v:.4g}' for k, v in result.variables.items())} with eta = {result.objective:.6g} "
        f"(verified {result.verified_objective:.6g}) in {result.optimizer['wall_time_s']:.2f} s and "
        f"{result.optimizer['evaluations']} evaluations; the grid of the paper's method "
        f"({result.baselines['grid'].evaluations} designs, {result.baselines['grid'].wall_time_s:.2f} s) reaches "
        f"{result.baselines['grid'].best.objective:.6g}."
    )
    bar.advance()
    bar.close()
    return {
        "paper": "nam2006",
        "title": TITLE,
        "summary": "R = 1 (lengths in units of R); working mode out_out (Fig. 1). Indices in the reading the paper's "
        "statements support (pose-plane area, |det J_f|, Frobenius kappa, range normalisation) unless a claim "
        "says literal.",
        "settings": {**s, "quick": quick},
        "claims": claims,
        "beyond_paper": {"syntheses": [{**record, "text": text}], "text": text},
        "figures": drawn,
        "extremes": {"synthesis": nam2006.extremes(nam2006.SUPPORTED),
                     "atlases": {name: a["bounds"] for name, a in atlases.items()}},
        "readings": readings,
        "trends": trends,
        "fig8": fig8,
    }


def _rotation_deg(m: Mechanism, r: float, l_b: float) -> float:
    """The largest |theta| <= 90 deg at which l_CM > 0: the workspace's theta range with theta_max = 90 deg."""
    d = _design(m, r, l_b)
    d[4] = math.pi / 2
    _, hi = m.functions["workspace_range_positive"](d)
    return math.degrees(float(hi))


def _eq25(m: Mechanism) -> dict[str, float]:
    """Where X1 Y2 - X2 Y1 > 0 (against eq. 25) over random poses of Fig. 8c's design on Fig. 1's mode,
    and the least -2 l_c det J_x there (eq. 26's argument needs it to vanish with the cross product)."""
    d = _design(m, 1.2, 1.2)
    x = _random_poses(m, d, 2000, np.random.default_rng(25))
    q = m.inverse_kinematics(x, d, mode=nam2006.MODE, passive=True)
    _, _, det_jx, _, eq25 = evaluate(m.functions["paper_first_order"], q, x, d)
    against = eq25[:, 0, 0] > 0
    return {"fraction": float(np.mean(against)),
            "least_det_measure_there": float(det_jx[against, 0, 0].min()) if against.any() else math.nan}
