"""docs/mechanisms.md runs as written (its TOML blocks saved under the names their first lines give, its
Python blocks in order), and the pages of the shipped descriptions (docs/mechanisms/<name>.md) are those their
descriptions and syntheses give (pkm.models.described.pages)."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from pkm.models.described import DESCRIPTIONS, pages

DOC = Path(__file__).resolve().parent.parent / "docs" / "mechanisms.md"


def _blocks(kind: str) -> list[str]:
    return re.findall(rf"```{kind}\n(.*?)```", DOC.read_text(), flags=re.S)


def test_the_walkthrough_runs_from_its_description_to_a_verified_synthesis(tmp_path, monkeypatch, capsys):
    for toml in _blocks("toml"):
        name = re.match(r"# (\S+\.toml)\n", toml).group(1)
        (tmp_path / name).write_text(toml)
    monkeypatch.chdir(tmp_path)
    scope: dict = {}
    for block in _blocks("python"):
        exec(compile(block, str(DOC), "exec"), scope)
    assert "description field legs.kind violates" in capsys.readouterr().out
    assert scope["result"].optimum.feasible


def test_the_chain_example_of_the_page_is_the_one_in_examples():
    (hexa,) = (block for block in _blocks("toml") if block.startswith("# hexa.toml"))
    assert hexa == (DOC.parent.parent / "examples" / "hexa.toml").read_text()


@pytest.mark.parametrize("name", list(DESCRIPTIONS))
def test_a_shipped_description_has_its_page_and_figures(name):
    assert pages.check([name]) == []
    for axes, _ in pages.PLANES[name]:
        assert (pages.FOLDER / pages._figure_name(name, axes)).stat().st_size > 10_000
