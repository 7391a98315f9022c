import pytest

from tests.games.golden_replay import assert_replays, golden_files


@pytest.mark.parametrize("batched", [False, True], ids=["alone", "batched"])
@pytest.mark.parametrize("path", golden_files("boulderdash"), ids=lambda p: p.stem)
def test_boulderdash_matches_gvgai_trace(path, batched):
    assert_replays(path, batched)


def test_every_boulderdash_trace_is_replayed():
    assert len(golden_files("boulderdash")) == 13
