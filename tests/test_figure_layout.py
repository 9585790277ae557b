"""Every figure pkm draws can be read: no text leaves the canvas or covers another text
(:func:`pkm.figures.text_problems`) in the atlas and sweep figures of every mechanism (low resolution; the
reproductions' figures are checked by their own tests, helpers.check_figures_readable); the check finds what it
looks for; colour limits clip an outlier instead of letting it flatten a map."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from pkm import figures, registry
from pkm.atlas import default_modes
from pkm.cli import main


@pytest.fixture
def drawn(monkeypatch):
    """The text problems of each figure saved through :func:`pkm.figures.save`, by file name (the
    files themselves are not written)."""
    found: dict[str, list[str]] = {}

    def collect(fig, path, *, dpi):
        found[Path(path).name] = figures.text_problems(fig)
        return Path(path)

    monkeypatch.setattr(figures, "save", collect)
    return found


def _chart(name: str) -> list[str]:
    """Options of an atlas of a mechanism: its first design space, or where it has none its first two
    parameters within 10% of their defaults."""
    mech = registry.mechanism(name)
    if mech.design_spaces:
        return []
    bounds = [(p.name, *sorted((0.9 * p.default, 1.1 * p.default))) for p in mech.parameters[:2]]
    return ["--axes", ",".join(f"{n}={lo:g}:{hi:g}" for n, lo, hi in bounds)]


@pytest.mark.parametrize("name", registry.mechanisms())
def test_the_atlas_and_sweep_figures_of_every_mechanism_can_be_read(name, drawn, tmp_path):
    mech = registry.mechanism(name)
    grid = [*_chart(name), "--resolution", "4", "--pose-resolution", "4", "--executor", "serial",
            "--out", str(tmp_path)]
    region = mech.region_names()[-1]
    assert main(["atlas", name, "gci", "--region", "reachable", "--modes", ",".join(mech.modes[:2]), *grid]) == 0
    swept = "gamma_max" if "gamma_max" in mech.global_indices() else "manipulability"
    modes = ",".join(default_modes(mech, region)[:2])
    assert main(["sweep", name, "--indices", swept, "--region", region, "--modes", modes, *grid]) == 0
    assert len(drawn) == 2
    assert {name: problems for name, problems in drawn.items() if problems} == {}


def test_text_problems_finds_text_off_the_canvas_and_overlapping_texts():
    fig = figures.figure(4, 3)
    ax = fig.subplots()
    ax.set_title("a readable title")
    ax.set_xlabel("x")
    assert figures.text_problems(fig) == []

    fig.text(0.97, 0.5, "off the right edge")
    ax.annotate("first", (0.5, 0.5))
    ax.annotate("second", (0.52, 0.5))
    ax.annotate("hidden", (0.5, 0.5), visible=False)
    problems = figures.text_problems(fig)
    assert len(problems) == 2, problems
    assert "'off the right edge' leaves the canvas" in problems[0]
    assert "'first' overlaps" in problems[1]
    assert "'second'" in problems[1]


def test_text_problems_finds_crowded_tick_labels_of_one_axis_and_skips_undrawn_ones():
    fig = figures.figure(3, 3)
    ax = fig.subplots()
    ax.set_xticks(np.linspace(0, 1, 31))
    assert any("x tick label" in p and "overlaps x tick label" in p for p in figures.text_problems(fig))
    ax.set_xticks(np.linspace(0, 1, 31), [""] * 31)
    assert figures.text_problems(fig) == []
    ax.set_xticks([0.0, 0.5, 1.0, 1.02])  # the last is outside the view: matplotlib keeps it, draws it not
    ax.set_xlim(0, 1)
    assert figures.text_problems(fig) == []


def test_hide_overlapping_keeps_the_first_of_two_overlapping_labels():
    fig = figures.figure(3, 3)
    ax = fig.subplots()
    texts = [ax.text(0.5, 0.5, "kept"), ax.text(0.51, 0.5, "hidden"), ax.text(0.1, 0.1, "apart")]
    assert figures.hide_overlapping(fig, texts) == 1
    assert [t.get_visible() for t in texts] == [True, False, True]
    assert figures.text_problems(fig) == []


def test_a_figure_saved_in_two_formats_keeps_the_layout_of_the_first(tmp_path):
    """The SVG's axes are where the PNG's are (its layout is not placed again), and a figure drawn afresh for the
    SVG alone is laid out within half a percent of the figure of that (its text measured by another backend)."""

    def drawn():
        fig = figures.figure(8, 4)
        axes = fig.subplots(1, 2)
        u = np.linspace(0, 1, 30)
        for ax in axes:
            filled = ax.contourf(*np.meshgrid(u, u), np.outer(u, np.sin(5 * u)))
            ax.set(title="a panel", xlabel="x [m]", ylabel="y [m]")
        fig.colorbar(filled, ax=list(axes), label="an index")
        fig.suptitle("two panels")
        return fig

    fig = drawn()
    figures.save(fig, tmp_path / "a.png", dpi=120)
    first = [ax.get_position().bounds for ax in fig.axes]
    figures.save(fig, tmp_path / "a.svg", dpi=120)
    assert [ax.get_position().bounds for ax in fig.axes] == first
    assert figures.text_problems(fig) == []
    alone = drawn()
    figures.save(alone, tmp_path / "b.svg", dpi=120)
    np.testing.assert_allclose([ax.get_position().bounds for ax in alone.axes], first, atol=5e-3)


def test_robust_limits_clip_an_outlier_and_the_colour_bar_says_where():
    values = np.linspace(0.0, 1.0, 400).reshape(20, 20)
    assert figures.robust_limits(values) == figures.ColourLimits(0.0, 1.0)
    values[3, 4] = 1e6
    values[5, 6] = np.nan
    limits = figures.robust_limits(values)
    assert (limits.vmin, limits.vmax) == (0.0, pytest.approx(1.0, abs=0.01))
    assert (limits.below, limits.above, limits.extend) == (False, True, "max")
    assert limits.levels()[-1] == limits.vmax

    fig = figures.figure(4, 3)
    ax = fig.subplots()
    image = ax.pcolormesh(values, vmin=limits.vmin, vmax=limits.vmax)
    bar = figures.colour_bar(fig, image, limits, ax=ax, label="index")
    assert bar.extend == "max"
    assert bar.ax.get_ylabel() == f"index\n(clipped above {limits.vmax:.3g})"
    assert figures.text_problems(fig) == []

    values[0, 0] = -1e6
    assert figures.robust_limits(values).extend == "both"
    assert figures.robust_limits([2.0, 2.0]) == figures.ColourLimits(1.0, 3.0)
    with pytest.raises(ValueError, match="at least one finite value"):
        figures.robust_limits([np.nan, np.inf])
