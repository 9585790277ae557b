"""pkm.spec.derivation: a process's derivations share one server process; one that takes longer than its limit
stops the server and the next derivation starts another; a process forked from this one derives with its own."""

from __future__ import annotations

import copy
import multiprocessing
import os
import re

import pytest
from helpers import FIVE_BAR_OF_CHAINS

import pkm
from pkm.errors import ComputationError
from pkm.spec import derivation, machine


def _five_bar(name: str, proximal: float) -> dict:
    raw = copy.deepcopy(FIVE_BAR_OF_CHAINS)
    raw["name"] = name
    raw["parameters"][0]["default"] = proximal
    return raw


def test_a_derivation_beyond_its_limit_stops_the_server_and_the_next_starts_another(monkeypatch):
    pkm.load(_five_bar(f"derived_first_{os.getpid()}", 1.21))
    server = derivation._SERVERS[os.getpid()]
    first = server.process
    assert first is not None
    assert first.poll() is None
    monkeypatch.setattr(machine, "DERIVATION_SECONDS", 1e-3)
    with pytest.raises(ComputationError, match=re.escape("took longer than its limit of 0.001 s")):
        pkm.load(_five_bar(f"derived_slow_{os.getpid()}", 1.22))
    assert first.poll() is not None
    monkeypatch.undo()
    m = pkm.load(_five_bar(f"derived_again_{os.getpid()}", 1.23))
    assert m.inverse_kinematics([0.0, 1.7]).shape == (2,)
    assert server.process is not None
    assert server.process is not first


def _derive_in_child(name: str) -> tuple[int, bool]:
    m = pkm.load(_five_bar(name, 1.24))
    return os.getpid(), bool(m.n_out == 2)


def test_a_forked_process_derives_with_a_server_of_its_own():
    pkm.load(_five_bar(f"derived_parent_{os.getpid()}", 1.25))
    with multiprocessing.get_context("fork").Pool(1) as pool:
        pid, loaded = pool.apply(_derive_in_child, (f"derived_child_{os.getpid()}",))
    assert loaded
    assert pid != os.getpid()
    assert derivation._SERVERS[os.getpid()].process.poll() is None


def test_a_server_that_ends_without_answering_says_why(monkeypatch, tmp_path):
    """A server that ends without answering (here one started where the derivation's modules are not) fails the
    derivation with its last words, and the next derivation starts a working server."""
    server = derivation._Server()
    monkeypatch.setattr(derivation, "ROOT", tmp_path)
    code, words = server.derive(tmp_path / "a.json", tmp_path / "a.py", 60)
    assert code == 1
    assert "ended without an answer" in words
    assert "symbolic" in words
    assert server.process is None
    monkeypatch.undo()
    m = pkm.load(_five_bar(f"derived_after_{os.getpid()}", 1.26))
    assert m.n_out == 2
