"""Shared fixtures of the test suite, in one block per concern."""

from __future__ import annotations

from pathlib import Path

import pytest

# --- Generated code: one fresh derivation of generated/ per test session --------------------------------


@pytest.fixture(scope="session")
def fresh_generated(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """generated/ derived afresh from symbolic/ into a temporary folder, once per session.

    The derivation takes seconds; the byte comparison and the numeric comparison of
    tests/test_generated_is_current.py share it. sympy is imported here, not at the top of this
    module, so that tests that never ask for the fixture do not pay for it.
    """
    from symbolic import generate

    out = tmp_path_factory.mktemp("fresh") / "generated"
    generate.write(out)
    return out
