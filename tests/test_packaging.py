"""Packaging: the licence is declared the way current setuptools expects (an SPDX expression and its
file, so that building prints no deprecation warning), and the README says how to run pkm."""

from __future__ import annotations

import tomllib
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent


def test_the_licence_is_an_spdx_expression_with_its_file():
    project = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]
    assert project["license"] == "MIT"
    assert project["license-files"] == ["LICENSE"]
    assert (ROOT / "LICENSE").read_text().startswith("MIT License")


def test_the_readme_says_how_to_run_pkm_after_make_demo():
    readme = (ROOT / "README.md").read_text()
    assert ".venv/bin/pkm" in readme
    assert "source .venv/bin/activate" in readme
