"""The generic step hands its kernels only a table's occupied prefix (``frame``'s narrowed
tables): ticked that way, a batch ends every tick in the same state as ticked with every table
whole, where a creation has to widen a table mid-tick too."""

from __future__ import annotations

import torch

from gvgai_pcg.levels import Level, human_levels
from gvgai_pcg.vgdl.engine import VGDLGame, frame
from gvgai_pcg.vgdl.registry import registered_game

# Frogs with a river of twenty dense forests and no log: at tick 0 about eight logs are made at
# once, more than the narrowed log table's free slots (it is empty, so narrowed to eight).
FORESTS = Level("frogs", ("w" * 22, "w" + "1" * 20 + "w", "wg" + "+" * 8 + "A" + "+" * 10 + "w", "w" * 22))


def alive_sprites(state, key: str) -> list[list[tuple[int, int, int]]]:
    """Each env's live sprites of table ``key`` as (slot, x, y)."""
    table = state.get(key)
    alive, x, y = table.get("alive"), table.get("x"), table.get("y")
    return [
        [(slot, int(x[env, slot]), int(y[env, slot])) for slot in alive[env].nonzero().flatten().tolist()]
        for env in range(alive.shape[0])
    ]


def test_narrowed_tables_tick_as_whole_ones(monkeypatch):
    game = VGDLGame.from_file(registered_game("frogs").description, name="vgdl:frogs")
    levels = [FORESTS, FORESTS]
    seeds = torch.arange(len(levels)) + 5
    narrowed, whole = (game.compile(levels, seeds, "cpu") for _ in range(2))
    widened = []
    real_widen = frame.Frame.widen

    def spy(self, key, in_place=False):
        if key in self.full and not in_place:
            widened.append(key)
        real_widen(self, key, in_place)

    monkeypatch.setattr(frame.Frame, "widen", spy)
    generator = torch.Generator().manual_seed(0)
    for step in range(30):
        action = torch.randint(0, game.num_actions, (len(levels),), generator=generator)
        game.tick(narrowed, action)
        with monkeypatch.context() as whole_tables:
            whole_tables.setattr(frame, "NARROW_FROM", 1 << 30)
            game.tick(whole, action)
        for key in ("score", "won", "lost"):
            assert torch.equal(narrowed.get(key), whole.get(key)), f"{key} at tick {step}"
        assert alive_sprites(narrowed, "log") == alive_sprites(whole, "log"), f"logs at tick {step}"
        assert narrowed.get("log").batch_size == whole.get("log").batch_size
    assert "log" in widened  # a creation widened the table mid-tick
    assert 8 < max(len(sprites) for sprites in alive_sprites(whole, "log")) < whole.get("log").batch_size[1]


def test_a_large_batch_with_a_wide_created_table_ticks_eagerly():
    game = VGDLGame.from_file(registered_game("frogs").description, name="vgdl:frogs")
    levels = human_levels("frogs")
    small = game.compile(levels * 12, torch.arange(60), "cpu")
    large = game.compile(levels * 103, torch.arange(515), "cpu")
    assert small.get("log").batch_size[1] >= 256  # as wide in both
    assert game.host_arguments(small) == {"crowded": False}
    assert game.host_arguments(large) == {"crowded": True}
