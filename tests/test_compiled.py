"""The compiled path's switch: PKM_COMPILED=0 (or no library) evaluates with CasADi's interpreter, says so
once, and gives the compiled path's values (tests/test_contract.py compares every kernel)."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import pkm
from pkm import compiled


@pytest.fixture
def interpreter(monkeypatch):
    monkeypatch.setenv("PKM_COMPILED", "0")
    compiled._library.cache_clear()
    compiled.kernel.cache_clear()
    monkeypatch.setattr(compiled, "_noticed", [])
    yield
    monkeypatch.delenv("PKM_COMPILED")
    compiled._library.cache_clear()
    compiled.kernel.cache_clear()


def test_the_interpreter_fallback_says_so_once_and_gives_the_same_values(interpreter):
    m = pkm.load("five_bar")
    x = np.array([[0.1, 1.5], [-0.3, 1.9], [5.0, 5.0]])
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        slow = m.local_index("inverse_condition_f", x)
        m.jacobian(x[:2])
    notices = [w for w in caught if issubclass(w.category, compiled.CompiledPathWarning)]
    assert len(notices) == 1
    assert "PKM_COMPILED=0" in str(notices[0].message)
    assert compiled.status()["path"] == "interpreter"
    compiled._library.cache_clear()
    compiled.kernel.cache_clear()
    with pytest.MonkeyPatch.context() as patch:
        patch.delenv("PKM_COMPILED")
        fast = m.local_index("inverse_condition_f", x)
    np.testing.assert_array_equal(np.isnan(fast), np.isnan(slow))
    np.testing.assert_allclose(fast[:2], slow[:2], rtol=1e-13)
