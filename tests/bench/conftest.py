"""The bench tests check the harness (its windows, tables and shards), not the compiler: the engine
ticks eagerly here unless a test is marked ``compiled``. Compiling a tick takes tens of seconds per
game and batch shape, and the compiled ticks' own tests are in tests/engine/."""

import pytest

from gvgai_pcg.engine.compiled import COMPILE_VARIABLE


@pytest.fixture(autouse=True)
def eager_ticks(request: pytest.FixtureRequest, monkeypatch: pytest.MonkeyPatch) -> None:
    if request.node.get_closest_marker("compiled") is None:
        monkeypatch.setenv(COMPILE_VARIABLE, "0")
