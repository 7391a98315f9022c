"""Frogs scenarios (RULES.md §6.7) on tiny inline levels, at exact ticks and pixels.

Where a scenario needs a log spawn to happen (or not), the test monkeypatches
``gvgai_pcg.games.rng.uniform`` (the only random call of the Frogs tick); the spawn-rate tests use
the real generator on a large batch.
"""

from __future__ import annotations

import pytest
import torch

from gvgai_pcg.envs.states import merge_states
from gvgai_pcg.games import get_game
from gvgai_pcg.games.base import pad_level
from gvgai_pcg.games.frogs import logs as frogs_logs
from gvgai_pcg.games.frogs import rules as frogs
from gvgai_pcg.games.render import render_tiles
from gvgai_pcg.levels import Level, human_level

GAME = get_game("frogs")
CPU = torch.device("cpu")


def play(rows: list[str], actions: list[str], seed: int = 0) -> list[dict]:
    """Snapshots after the reset tick (index 0) and after each action (index k = tick k)."""
    state = GAME.compile([Level("frogs", tuple(rows))], torch.tensor([seed]), CPU)
    snapshots = []
    for name in ["NIL", *actions]:
        GAME.tick(state, torch.tensor([GAME.actions.index(name)]))
        snapshots.append(GAME.snapshot(state, 0))
    return snapshots


def frog(snapshot: dict) -> tuple[int, int] | None:
    avatar = snapshot["avatar"]
    return None if avatar is None else (avatar["x"], avatar["y"])


def sprites(snapshot: dict, name: str) -> list[tuple[int, int]]:
    return [(x, y) for kind, x, y in snapshot["sprites"] if kind == name]


@pytest.fixture
def spawn_only_at(monkeypatch):
    """Make every spawner fire exactly at the given ticks (when they are spawn ticks at all)."""

    def patch(ticks: set[int]) -> None:
        firing = torch.tensor(sorted(ticks), dtype=torch.int64)

        def uniform(seed, tick, slot, stream):
            fire = torch.isin(tick, firing)
            shape = torch.broadcast_shapes(tick.unsqueeze(-1).shape, torch.as_tensor(slot).shape)
            return torch.where(fire.unsqueeze(-1), 0.0, 1.0).to(torch.float64).expand(shape)

        monkeypatch.setattr(frogs.rng, "uniform", uniform)

    return patch


# --- the log shield and the water ---

RIVER_ROWS = ["gwwwwwwww", "000000=00", "+++++++++", "++++A++++", "wwwwwwwww"]


def test_a_one_pixel_overlap_with_a_log_shields_from_water():
    # The log starts at x = 60 and is at 60 - k in tick k; the frog (x = 40) hops in at tick 11.
    s = play(RIVER_ROWS, ["UP"] + ["NIL"] * 9 + ["UP", "NIL", "NIL"])
    assert sprites(s[11], "log") == [(49, 10)]
    assert frog(s[11]) == (40, 10) and s[11]["status"] == "running"
    assert frog(s[12]) == (39, 10)  # riding from the next tick on
    assert frog(s[13]) == (38, 10)


def test_water_without_a_log_kills():
    s = play(RIVER_ROWS, ["UP"] + ["NIL"] * 8 + ["UP"])
    assert sprites(s[10], "log") == [(50, 10)]  # edge-adjacent: no overlap
    assert frog(s[10]) is None and s[10]["status"] == "lose" and s[10]["score"] == 0


def test_the_spawner_tiles_2_and_4_have_no_water(spawn_only_at):
    spawn_only_at(set())
    # The level log of the `4` tile has left it by tick 10; the frog stands there from tick 20.
    rows = ["gwwwwwwww", "000000004", "+++++++++", "++++++++A", "wwwwwwwww"]
    s = play(rows, ["UP"] + ["NIL"] * 18 + ["UP"] + ["NIL"] * 10)
    assert frog(s[20]) == (80, 10) and frog(s[30]) == (80, 10) and s[30]["status"] == "running"
    assert sprites(s[30], "forestSparse") == [(80, 10)]
    drown = play(["gwwwwwwww", "000000003", "+++++++++", "++++++++A", "wwwwwwwww"], ["UP", "UP"])
    assert frog(drown[2]) is None and drown[2]["status"] == "lose"


def test_a_truck_kills_the_frog():
    s = play(["gwwww", "+++++", "....l", "+++++", "++A++", "wwwww"], ["UP", "UP"] + ["NIL"] * 4)
    # The fast truck drives 40 → 38 → 36 …; the frog (x = 20) is on the highway from tick 2.
    assert frog(s[5]) == (20, 20) and sprites(s[5], "fastLtruck") == [(30, 20)]  # edge-adjacent
    assert frog(s[6]) is None and s[6]["status"] == "lose" and sprites(s[6], "fastLtruck") == [(28, 20)]


# --- riding a log ---

TOP_RIVER = ["=========", "+++++++++", "++++A+++g", "wwwwwwwww"]


def test_riding_pulls_one_pixel_and_any_direction_suppresses_the_pull():
    s = play(TOP_RIVER, ["UP", "UP", "NIL", "UP", "NIL", "RIGHT", "NIL", "DOWN", "NIL"])
    assert frog(s[2]) == (40, 0)  # hopped on: moved itself, no pull
    assert frog(s[3]) == (39, 0)  # NIL: carried 1 px left
    assert frog(s[4]) == (39, 0)  # UP off the screen: stepped back by the edge, and no pull
    assert frog(s[5]) == (38, 0)
    assert frog(s[6]) == (48, 0)  # a 10-px hop keeps the misalignment, no pull
    assert frog(s[7]) == (47, 0)
    assert frog(s[8]) == (47, 10)  # down to the grass, still misaligned
    assert frog(s[9]) == (47, 10) and s[9]["status"] == "running"


def test_a_blocked_move_from_a_log_into_trees_drowns_the_frog():
    rows = ["wwwwwwwww", "=========", "+++++++++", "++++A+++g", "wwwwwwwww"]
    s = play(rows, ["UP", "UP", "NIL", "UP"])
    assert frog(s[3]) == (39, 10)
    assert frog(s[4]) is None and s[4]["status"] == "lose"  # shield tested at (39, 0): no log there
    safe = play(rows, ["UP", "UP", "NIL", "NIL"])
    assert frog(safe[4]) == (38, 10)


def test_a_freshly_spawned_log_does_not_pull_before_it_moves(spawn_only_at):
    spawn_only_at({10})
    rows = ["gwwwwww++2", "++++++++++", "+++++++++A", "wwwwwwwwww"]
    # The level log of the `2` tile leaves the cell; a log is spawned at (90, 0) in tick 10.
    s = play(rows, ["NIL"] * 8 + ["UP", "UP", "NIL", "NIL", "NIL"])
    assert frog(s[9]) == (90, 10) and frog(s[10]) == (90, 0)
    assert sorted(sprites(s[10], "log")) == [(80, 0), (90, 0)]
    assert frog(s[11]) == (90, 0)  # the new log's first update: it does not move, no pull
    assert frog(s[12]) == (89, 0)  # it moves from tick 12, and pulls
    assert frog(s[13]) == (88, 0)


def test_the_goal_counts_on_any_overlap_before_the_tree_step_back():
    rows = ["wwwwgwwww", "+++++++++", "=========", "+++++++++", "++++A++++", "wwwwwwwww"]
    s = play(rows, ["UP", "UP", "NIL", "UP", "UP"])
    assert frog(s[4]) == (39, 10)
    assert s[5]["score"] == 1 and s[5]["status"] == "win"
    assert frog(s[5]) == (39, 10)  # overlapped the trees too: stepped back
    assert sprites(s[5], "goal") == []


def test_a_log_leaving_on_the_left_carries_the_frog_off_screen_and_it_drowns_next_tick():
    rows = ["gwwwwwwww", "B00000000", "+++++++++", "wwwwwwwww"]
    s = play(rows, ["NIL", "NIL"])
    assert frog(s[0]) == (0, 10) and sprites(s[0], "log") == [(0, 10)]
    assert frog(s[1]) == (-1, 10) and sprites(s[1], "log") == []  # the log at x = -1 is removed
    assert frog(s[2]) is None and s[2]["status"] == "lose"


# --- trucks ---


def test_trucks_wrap_overtake_and_never_stop():
    rows = [
        "g" + "w" * 27,
        "." * 26 + "x-",
        "l_" + "." * 26,
        "....._l" + "." * 21,
        "+" * 13 + "A" + "+" * 14,
        "w" * 28,
    ]
    s = play(rows, ["NIL"] * 20)
    assert sprites(s[1], "slowRtruck") == [(0, 10)]  # 270 → 271 → 0 within tick 1
    assert sprites(s[1], "fastRtruck") == [(262, 10)]
    assert sprites(s[5], "fastRtruck") == [(270, 10)]
    assert sprites(s[6], "fastRtruck") == [(0, 10)]  # 270 → 272 → 0 within one tick
    assert sprites(s[6], "slowRtruck") == [(5, 10)]
    assert sorted(sprites(s[1], "fastLtruck")) == [(58, 30), (270, 20)]  # 0 → -2 → 270
    assert sorted(sprites(s[1], "slowLtruck")) == [(9, 20), (49, 30)]
    # Row 3: the fast truck passes through the slow one and drives on.
    row3 = lambda snapshot, name: [x for x, y in sprites(snapshot, name) if y == 30]  # noqa: E731
    assert row3(s[10], "fastLtruck") == [40] and row3(s[10], "slowLtruck") == [40]
    assert row3(s[20], "fastLtruck") == [20] and row3(s[20], "slowLtruck") == [30]


# --- spawners ---

DENSE_ROWS = ["gwwwwwwwww", "0000000002", "++++A+++++", "wwwwwwwwww"]


def test_dense_spawner_logs_run_one_pixel_behind_then_exactly_adjacent(spawn_only_at):
    spawn_only_at(set(range(100)))
    s = play(DENSE_ROWS, ["NIL"] * 12)
    assert sprites(s[0], "log") == [(90, 10), (90, 10)]  # the level log and the tick-0 spawn
    assert sprites(s[1], "log") == [(89, 10), (90, 10)]
    assert sprites(s[2], "log") == [(88, 10), (89, 10)]
    assert sprites(s[9], "log") == [(81, 10), (82, 10)]
    assert sprites(s[10], "log") == [(80, 10), (81, 10), (90, 10)]  # overlap by 1 px in the spawn tick
    assert sprites(s[11], "log") == [(79, 10), (80, 10), (90, 10)]  # then exactly adjacent
    assert sprites(s[12], "log") == [(78, 10), (79, 10), (89, 10)]


def test_sparse_spawner_logs_can_overlap_by_half_a_cell(spawn_only_at):
    spawn_only_at(set(range(100)))
    s = play(["gwwwwwwwww", "0000000003", "++++A+++++", "wwwwwwwwww"], ["NIL"] * 7)
    assert sprites(s[0], "log") == [(90, 10)]
    assert sprites(s[5], "log") == [(86, 10), (90, 10)]
    assert sprites(s[7], "log") == [(84, 10), (89, 10)]


@pytest.mark.parametrize(("spawner", "cooldown", "prob"), [("2", 10, 0.4), ("4", 5, 0.1)])
def test_spawn_ticks_and_rates(spawner, cooldown, prob):
    batch, ticks = 4000, 2 * cooldown + 1
    level = Level("frogs", ("gwwwwwwwww", "000000000" + spawner, "++++A+++++", "wwwwwwwwww"))
    state = GAME.compile([level] * batch, torch.arange(batch), CPU)
    counts = []
    for _ in range(ticks):
        GAME.tick(state, torch.zeros(batch, dtype=torch.int64))
        counts.append(state.get(("logs", "alive")).sum(-1))
    new = torch.stack(counts).diff(dim=0, prepend=torch.ones(1, batch, dtype=torch.int64))
    for tick in range(ticks):
        rate = new[tick].float().mean().item()
        if tick % cooldown:
            assert rate == 0, f"a log was spawned in tick {tick}"
        else:
            assert abs(rate - prob) < 0.03, f"spawn rate {rate} in tick {tick}, expected {prob}"


def test_a_log_heavy_level_stays_within_the_log_table_for_2000_ticks(spawn_only_at):
    spawn_only_at(set(range(2001)))  # every spawner fires at every spawn tick: the worst case
    rows = [
        "gwwwwwwwwwwwwwwwwwwwwwwwwwww",
        "==========================14",
        "=========================342",
        "==========================32",
        "++++++++++++A+++++++++++++++",
        "wwwwwwwwwwwwwwwwwwwwwwwwwwww",
    ]
    state = GAME.compile([Level("frogs", tuple(rows))], torch.tensor([0]), CPU)
    capacity = state.get("logs").batch_size[1]
    most = 0
    for _ in range(2001):
        GAME.tick(state, torch.zeros(1, dtype=torch.int64))
        most = max(most, int(state.get(("logs", "alive")).sum()))
    assert most <= capacity - 1
    spawners = state.get("spawners")
    cooldown = torch.tensor(frogs.SPAWN_COOLDOWN)[spawners.get("kind")]
    bound = int((frogs_logs.spawner_ring_size(spawners.get("x"), cooldown) * spawners.get("alive")).sum())
    assert most >= bound  # the ring sizes are reached, so the bound is tight


def test_an_undersized_log_table_fails_loudly(spawn_only_at, monkeypatch):
    spawn_only_at(set(range(100)))
    monkeypatch.setattr(frogs_logs, "spawner_ring_size", lambda x, cooldown: torch.ones_like(x))
    state = GAME.compile([Level("frogs", tuple(DENSE_ROWS))], torch.tensor([0]), CPU)
    with pytest.raises(RuntimeError, match="ring slot occupied"):
        for _ in range(12):
            GAME.tick(state, torch.zeros(1, dtype=torch.int64))


@pytest.mark.parametrize(("spawner", "fires"), [("2", {0}), ("4", {0, 5})])
def test_spawned_and_level_logs_are_removed_in_the_tick_they_reach_x_minus_1(spawn_only_at, spawner, fires):
    # Removal finds the logs at x = −1 (the cleanup): check it against the positions they must have.
    spawn_only_at(fires)
    s = play(["gwwwwwwwww", "000000000" + spawner, "++++A+++++", "wwwwwwwwww"], ["NIL"] * 100)
    for tick, snapshot in enumerate(s):
        # The level log is at 90 - t; a log spawned at t0 is at 90 until t0 + 1, then 90 - (t - t0 - 1).
        xs = [90 - tick] + [90 - max(tick - t0 - 1, 0) for t0 in sorted(fires) if t0 <= tick]
        assert sorted(sprites(snapshot, "log")) == sorted((x, 10) for x in xs if x >= 0), f"tick {tick}"


def test_log_keys_follow_the_logs_and_dead_slots_are_never_near():
    levels = [human_level("frogs", i) for i in range(5)]
    state = GAME.compile([pad_level(level, 11, 28) for level in levels], torch.arange(5), CPU)
    for _ in range(400):
        GAME.tick(state, torch.zeros(5, dtype=torch.int64))
        logs = state.get("logs")
        alive, x, y = logs.get("alive"), logs.get("x"), logs.get("y")
        expected = torch.where(alive, frogs_logs.log_key(x, y, state.get("tick").unsqueeze(-1)), 0)
        assert torch.equal(logs.get("key"), expected)
        assert (x[alive] >= 0).all()


@pytest.mark.parametrize("index", range(5))
def test_level_logs_borrow_only_ring_slots_first_written_after_they_are_gone(index):
    state = GAME.compile([human_level("frogs", index)], torch.tensor([0]), CPU)
    spawners, logs = state.get("spawners")[0], state.get("logs")[0]
    cooldown = torch.tensor(frogs.SPAWN_COOLDOWN)[spawners.get("kind")]
    rings = spawners.get("ring")
    assert (
        int(rings.sum())
        <= logs.batch_size[0] - 1
        <= int(rings.sum()) + human_level("frogs", index).count("=")
    )
    for slot in logs.get("alive").nonzero().flatten().tolist():
        j = slot - spawners.get("base")
        inside = (j >= 0) & (j < rings)
        assert int(inside.sum()) <= 1
        if inside.any():
            assert int(logs.get("x")[slot]) + 2 <= int((j * cooldown)[inside])


def test_a_merged_batch_equals_single_envs():
    # A partial reset pads the entity tables of the smaller state with zeros (dead slots).
    actions = torch.randint(0, 5, (300, 2), generator=torch.Generator().manual_seed(1))
    running = GAME.compile([human_level("frogs", 0), human_level("frogs", 3)], torch.tensor([3, 4]), CPU)
    alone = GAME.compile([human_level("frogs", 0)], torch.tensor([3]), CPU)
    for tick in range(40):
        GAME.tick(running, actions[tick])
        GAME.tick(alone, actions[tick, :1])
    fresh = GAME.compile([human_level("frogs", 1)], torch.tensor([5]), CPU)
    other = GAME.compile([human_level("frogs", 1)], torch.tensor([5]), CPU)
    GAME.tick(fresh, torch.zeros(1, dtype=torch.int64))
    GAME.tick(other, torch.zeros(1, dtype=torch.int64))
    capacity = running.get("logs").batch_size[1]
    merged = merge_states(running, fresh, torch.tensor([1]))
    assert merged.get("logs").batch_size[1] == fresh.get("logs").batch_size[1] > capacity  # padded
    for tick in range(40, actions.shape[0]):
        GAME.tick(merged, actions[tick])
        GAME.tick(alone, actions[tick, :1])
        GAME.tick(other, actions[tick, 1:])
        assert GAME.snapshot(merged, 0) == GAME.snapshot(alone, 0), f"tick {tick}"
        assert GAME.snapshot(merged, 1) == GAME.snapshot(other, 0), f"tick {tick}"


# --- human levels ---


def test_level_4_starts_the_frog_on_a_drifting_three_log_raft():
    level = human_level("frogs", 4)
    state = GAME.compile([level], torch.tensor([0]), CPU)
    for tick in range(25):
        GAME.tick(state, torch.zeros(1, dtype=torch.int64))
        s = GAME.snapshot(state, 0)
        assert frog(s) == (180 - tick, 80) and s["status"] == "running"
        assert [x for x, y in sprites(s, "log") if y == 80] == [170 - tick, 180 - tick, 190 - tick]


def test_level_4_keeps_its_10_row_screen_in_a_batch_of_full_levels():
    levels = [human_level("frogs", 0), human_level("frogs", 4)]
    state = GAME.compile(levels, torch.tensor([0, 1]), CPU)
    assert state.get("wall").shape == (2, 11, 28)
    assert state.get("height").tolist() == [11, 10] and state.get("width").tolist() == [28, 28]
    assert not any(state.get(grid)[1, 10].any() for grid in ("wall", "water", "grass", "goal"))


@pytest.mark.parametrize("index", range(5))
def test_max_score_is_one_goal_per_level(index):
    assert GAME.max_score(human_level("frogs", index)) == 1


def test_batched_equals_single():
    levels = [pad_level(human_level("frogs", i % 5), 11, 28) for i in range(6)]
    seeds = torch.tensor([11, 22, 33, 44, 55, 66])
    actions = torch.randint(0, 5, (60, len(levels)), generator=torch.Generator().manual_seed(7))
    batched = GAME.compile(levels, seeds, CPU)
    singles = [GAME.compile([level], seeds[i : i + 1], CPU) for i, level in enumerate(levels)]
    for tick in range(actions.shape[0]):
        GAME.tick(batched, actions[tick])
        tiles = render_tiles(GAME, batched)
        for i, single in enumerate(singles):
            GAME.tick(single, actions[tick, i : i + 1])
            assert GAME.snapshot(batched, i) == GAME.snapshot(single, 0), f"env {i}, tick {tick}"
            assert torch.equal(tiles[i], render_tiles(GAME, single)[0])
