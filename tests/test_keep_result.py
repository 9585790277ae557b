"""The command line keeps the user's work: a result that --out cannot take once it is computed (the folder
made read-only during the run, a full disk) is written into a new folder of the system's temporary
directory instead, and the command exits 1 with one line naming the path that failed, why, and where the
result is."""

from __future__ import annotations

import errno
import json
import os
import re
import tempfile
from collections.abc import Callable
from pathlib import Path

import numpy as np
import pytest

import pkm.reproduce
from pkm.cli import grid, main
from pkm.cli.commands import synth

KEPT = re.compile(r"^pkm: could not write (?P<path>.+) \((?P<reason>[^()]+)\); the result is kept in (?P<kept>\S+)$")


@pytest.fixture
def out(tmp_path) -> Path:
    """A designer's output folder."""
    folder = tmp_path / "out"
    folder.mkdir()
    return folder


@pytest.fixture
def temporary(tmp_path, monkeypatch) -> Path:
    """The system's temporary directory, for the test: a folder of its own that pytest removes."""
    folder = tmp_path / "tmp"
    folder.mkdir()
    monkeypatch.setattr(tempfile, "tempdir", str(folder))
    return folder


@pytest.fixture
def refuse(monkeypatch) -> Callable[..., None]:
    """``refuse(folder, code)`` makes ``folder`` fail from then on as the system would, whoever runs the
    suite (root ignores ``chmod a-w``): with EACCES a read-only folder refuses to take or give up an entry
    of its own (its sub-folders keep their own permissions); with ENOSPC a full disk refuses to create
    anything below it."""
    refused: list[tuple[Path, int]] = []

    def code_for(path: object, creates: bool) -> int | None:
        path = Path(os.path.abspath(path))
        for folder, code in refused:
            if path.parent == folder if code == errno.EACCES else creates and path.is_relative_to(folder):
                return code
        return None

    def guard(name: str, paths: Callable[..., list[tuple[object, bool]]]) -> None:
        """``paths(*args)``: the paths the call changes, each with whether it creates an entry."""
        original = getattr(os, name)

        def guarded(*args: object, **kwargs: object) -> object:
            if kwargs.get("dir_fd") is None:
                for path, creates in paths(*args, **kwargs):
                    code = code_for(path, creates)
                    if code is not None:
                        raise OSError(code, os.strerror(code), str(path))
            return original(*args, **kwargs)

        monkeypatch.setattr(os, name, guarded)

    def new(path: object) -> list[tuple[object, bool]]:
        return [] if os.path.lexists(path) else [(path, True)]  # an existing entry is not created again

    guard("mkdir", lambda path, *_, **__: new(path))
    guard("open", lambda path, flags, *_, **__: new(path) if flags & os.O_CREAT else [])
    guard("replace", lambda source, destination, **_: [(source, False), (destination, True)])
    guard("rename", lambda source, destination, **_: [(source, False), (destination, True)])
    guard("unlink", lambda path, **_: [(path, False)])
    guard("rmdir", lambda path, **_: [(path, False)])
    return lambda folder, code: refused.append((Path(folder).resolve(), code))


def after(monkeypatch, module: object, name: str, then: Callable[[], None]) -> None:
    """Run ``then`` once ``module.name`` has returned: the computation is done, its result not yet written."""
    original = getattr(module, name)

    def wrapped(*args: object, **kwargs: object) -> object:
        result = original(*args, **kwargs)
        then()
        return result

    monkeypatch.setattr(module, name, wrapped)


def kept_folder(err: str, command: str, temporary: Path, out: Path, reason: str) -> Path:
    """The folder named by the one line on standard error, checked to be a new one of the temporary folder."""
    lines = err.strip().splitlines()
    assert len(lines) == 1, err
    match = KEPT.match(lines[0])
    assert match, lines[0]
    assert Path(match["path"]).resolve().is_relative_to(out.resolve())
    assert match["reason"] == reason
    kept = Path(match["kept"])
    assert kept.parent == temporary
    assert kept.name.startswith(f"pkm-{command}-")
    return kept


@pytest.mark.parametrize("code", [errno.EACCES, errno.ENOSPC])
def test_synth_keeps_its_record_when_out_fails_after_the_synthesis(code, out, temporary, refuse, monkeypatch,
                                                                   capsys):
    after(monkeypatch, synth, "synthesize", lambda: refuse(out, code))
    args = ["synth", "five_bar.max_gci_miw", "--resolution", "2", "--starts", "1", "--out", str(out), "--json"]
    assert main(args) == 1
    captured = capsys.readouterr()
    kept = kept_folder(captured.err, "synth", temporary, out, os.strerror(code))
    record = json.loads((kept / "five_bar.max_gci_miw.json").read_text())
    assert record == json.loads(captured.out)
    assert record["problem"] == "five_bar.max_gci_miw"
    assert [p.name for p in out.iterdir()] == []


def test_a_result_neither_out_nor_the_temporary_folder_takes_is_one_line_exit_1(out, temporary, refuse,
                                                                                 monkeypatch, capsys):
    def full() -> None:
        refuse(out, errno.ENOSPC)
        refuse(temporary, errno.ENOSPC)

    after(monkeypatch, synth, "synthesize", full)
    assert main(["synth", "five_bar.max_gci_miw", "--resolution", "2", "--starts", "1", "--out", str(out)]) == 1
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1
    assert err[0].startswith(f"pkm: computation failed: could not write {out}")
    assert err[0].endswith(f"nor in {temporary} (No space left on device)")


def test_atlas_keeps_its_npz_and_figure_when_out_turns_read_only(out, temporary, refuse, monkeypatch, capsys):
    after(monkeypatch, grid, "atlases", lambda: refuse(out, errno.EACCES))
    assert main(["atlas", "five_bar", "gci", "--resolution", "5", "--executor", "serial", "--out", str(out),
                 "--json"]) == 1
    captured = capsys.readouterr()
    kept = kept_folder(captured.err, "atlas", temporary, out, "Permission denied")
    data = json.loads(captured.out)
    npz, figure = Path(data["npz"]), Path(data["figure"])
    assert (npz.parent, figure.parent) == (kept, kept)
    assert figure.stat().st_size > 0
    with np.load(npz) as saved:
        metadata = json.loads(str(saved["metadata"]))
        assert saved["values_out_out"].shape == (len(saved["u"]), len(saved["v"]))
    assert metadata["index"] == "gci"
    assert [p.name for p in out.iterdir() if not p.name.startswith(".")] == []


def test_sweep_keeps_its_listing_with_its_chunks_on_a_full_disk(out, temporary, refuse, monkeypatch, capsys):
    after(monkeypatch, grid, "atlases", lambda: refuse(out, errno.ENOSPC))
    assert main(["sweep", "five_bar", "--indices", "gci", "--resolution", "5", "--executor", "serial",
                 "--out", str(out), "--json"]) == 1
    captured = capsys.readouterr()
    kept = kept_folder(captured.err, "sweep", temporary, out, "No space left on device")
    folder = Path(json.loads(captured.out)["folder"])
    assert folder.parent == kept
    listing = json.loads((folder / "index.json").read_text())
    assert listing["chunks"]
    for chunk in listing["chunks"]:
        with np.load(folder / chunk["file"]) as data:
            assert int(data["count"]) == chunk["count"]
    assert all(Path(f).is_file() for f in listing["figures"].values())
    assert (folder / "gci.npz").is_file()


@pytest.mark.parametrize("file_systems", ["one", "two"])
def test_reproduce_keeps_its_report_when_out_turns_read_only(file_systems, out, temporary, refuse, monkeypatch,
                                                             capsys):
    """The staged report moves into the kept folder by renames, or by copies where the temporary directory
    lies on another file system than --out."""
    if file_systems == "two":
        rename = os.replace

        def across(source: os.PathLike, destination: os.PathLike, **kwargs: object) -> None:
            if Path(source).is_relative_to(out) and Path(destination).is_relative_to(temporary):
                raise OSError(errno.EXDEV, os.strerror(errno.EXDEV), str(source), None, str(destination))
            rename(source, destination, **kwargs)

        monkeypatch.setattr(os, "replace", across)
    after(monkeypatch, pkm.reproduce, "write_report", lambda: refuse(out, errno.EACCES))
    assert main(["reproduce", "wu2008", "--quick", "--out", str(out), "--json"]) == 1
    captured = capsys.readouterr()
    kept = kept_folder(captured.err, "reproduce", temporary, out, "Permission denied")
    [summary] = json.loads(captured.out)
    assert Path(summary["folder"]) == kept / "wu2008"
    report = json.loads((kept / "wu2008" / "report.json").read_text())
    assert report["claims"]
    assert all((kept / "wu2008" / name).is_file() for name in report["figures"])
    assert (kept / "wu2008" / "report.md").is_file()
    assert [p.name for p in out.iterdir() if not p.name.startswith(".")] == []
