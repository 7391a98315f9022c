import pytest

from tests.games.golden_replay import assert_replays, golden_files


@pytest.mark.parametrize("path", golden_files("solarfox"), ids=lambda p: p.stem)
def test_solarfox_matches_gvgai_trace(path):
    assert_replays(path)


def test_every_solarfox_trace_is_replayed():
    assert len(golden_files("solarfox")) == 8
