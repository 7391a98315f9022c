"""The generic step's SpawnPoint (``vgdl/engine/spawn.py``), shieldFrom (``shield.py``) and
pullWithIt (``pull.py``) kernels on small levels worked out by hand from RULES.md §2-3."""

from __future__ import annotations

import torch

from gvgai_pcg.games import rng
from gvgai_pcg.levels import Level
from gvgai_pcg.vgdl.engine import VGDLGame

TEXT = """BasicGame
    SpriteSet
        floor > Immovable
        water > Immovable
        forest > SpawnPoint stype=log prob={prob} cooldown=3
        log > Missile orientation=LEFT speed=0.1
        avatar > MovingAvatar
    InteractionSet
        avatar log > shieldFrom ftype=killSprite stype=water
        avatar log > pullWithIt
        avatar EOS > stepBack
        avatar water > killSprite
        log EOS > killSprite
    TerminationSet
        SpriteCounter stype=avatar limit=0 win=False
    LevelMapping
        . > floor
        ~ > water
        f > forest water
        A > avatar floor
        L > avatar log water
        M > avatar water
"""
NIL, LEFT, RIGHT = 0, 1, 2


def game(prob: str = "1") -> VGDLGame:
    return VGDLGame.from_text(TEXT.format(prob=prob), "riding.txt")


def play(vgdl: VGDLGame, levels: list[Level], actions: list[int], seeds: torch.Tensor | None = None) -> list:
    seeds = torch.arange(len(levels)) if seeds is None else seeds
    state = vgdl.compile(levels, seeds, "cpu")
    history = []
    for action in actions:
        vgdl.tick(state, torch.full((len(levels),), action))
        history.append(state.clone())
    return history


def logs(state, env: int = 0) -> list[tuple[int, int]]:
    table = state.get("log")
    slots = table.get("alive")[env].nonzero().flatten().tolist()
    return sorted((table.get("x")[env, k].item(), table.get("y")[env, k].item()) for k in slots)


def test_a_spawn_point_spawns_at_its_cooldown_and_the_log_moves_from_its_second_update():
    history = play(game(), [Level("mine", ("~~f", "A.."))], [NIL] * 5)
    # tick 0: spawned (logs are updated before spawners: its first update is tick 1, its move tick 2)
    assert [logs(state) for state in history[:3]] == [[(20, 0)], [(20, 0)], [(19, 0)]]
    assert logs(history[3]) == [(18, 0), (20, 0)]  # tick 3: the next spawn
    assert logs(history[4]) == [(17, 0), (20, 0)]
    born = history[3].get(("log", "born"))[0][history[3].get(("log", "alive"))[0]]
    assert sorted(born.tolist()) == [1 << 20, 4 << 20]  # created in ticks 0 and 3: list order


def test_a_sprite_spawned_before_its_type_is_updated_has_its_first_update_in_the_same_tick():
    # the forest drawn after the log is updated before it (reverse drawing order)
    forest = "        forest > SpawnPoint stype=log prob=1 cooldown=3\n"
    log = "        log > Missile orientation=LEFT speed=0.1\n"
    text = TEXT.format(prob="1").replace(forest + log, log + forest)
    assert text != TEXT.format(prob="1")
    vgdl = VGDLGame.from_text(text, "early.txt")
    assert vgdl.layout.plan.update_order.index("forest") < vgdl.layout.plan.update_order.index("log")
    history = play(vgdl, [Level("mine", ("~~f", "A.."))], [NIL] * 3)
    assert [logs(state) for state in history] == [[(20, 0)], [(19, 0)], [(18, 0)]]


def test_a_spawn_point_draws_by_its_cell_on_the_spawners_stream():
    seeds = torch.arange(16) * 31
    history = play(game("0.5"), [Level("mine", ("~~f", "A.."))] * 16, [NIL], seeds)
    drawn = rng.uniform(seeds, torch.zeros(16, dtype=torch.int64), 0 * (1 << 16) + 20, 1)
    spawned = history[0].get(("log", "alive")).any(-1)
    assert spawned.tolist() == (drawn < 0.5).tolist()
    assert 0 < int(spawned.sum()) < 16  # both outcomes happen


def test_a_log_shields_the_frog_from_the_water_and_carries_it_unless_it_moved():
    history = play(game(), [Level("mine", ("~L~~", "...."))], [NIL, NIL, LEFT, NIL, RIGHT])
    frog = [(s.get(("avatar", "x")).item(), s.get(("avatar", "alive")).item()) for s in history]
    # 0: the log's first update (it did not move): no pull; 1: pulled 1 px left with it; 2: LEFT
    # to x = -1, stepped back by the edge, still on the log (shielded) but not pulled (it moved:
    # its gate is shut); 3: pulled again; 4: RIGHT to 18, off the log (now at 6): drowned
    assert frog == [(10, True), (9, True), (9, True), (8, True), (18, False)]
    assert [logs(state) for state in history] == [[(10, 0)], [(9, 0)], [(8, 0)], [(7, 0)], [(6, 0)]]


def test_a_frog_on_bare_water_drowns():
    history = play(game(), [Level("mine", ("~M~", "..."))], [NIL])
    assert not history[0].get(("avatar", "alive")).item() and history[0].get("lost").item()


RAFTS = """BasicGame
    SpriteSet
        water > Immovable
        raft > Missile orientation=LEFT
{kinds}
        avatar > MovingAvatar
    InteractionSet
        avatar raft > pullWithIt
    TerminationSet
        SpriteCounter stype=avatar limit=0 win=False
    LevelMapping
        ~ > water
        s > water anchored
        d > water drifting
        A > avatar anchored
"""
ANCHORED = "            anchored > speed=0"
DRIFTING = "            drifting > speed=0.1"


def test_the_first_raft_in_list_order_pulls_once_a_tick_even_when_it_did_not_move():
    """At tick 1 the frog (on an anchored raft) also overlaps a drifting raft that moved 1 px: Java
    pulls once a tick, by the first overlapping second in list order (the kinds in subtype order),
    so it is carried only when the drifting raft comes first."""
    level = Level("mine", ("Ad~",))
    for kinds, carried in (((ANCHORED, DRIFTING), False), ((DRIFTING, ANCHORED), True)):
        vgdl = VGDLGame.from_text(RAFTS.format(kinds="\n".join(kinds)), f"rafts{carried}.txt")
        history = play(vgdl, [level], [NIL, NIL])
        assert history[1].get(("avatar", "x")).item() == (-1 if carried else 0)
