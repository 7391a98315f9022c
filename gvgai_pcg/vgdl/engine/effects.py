"""The effect kernels: one rule (an effect line on one type pair) applied as GVGAI applies it.

Java takes each first sprite in turn (``iSubTypes`` order, then list order), the seconds that
overlap it, and applies the effect to each pair while the first is not killed (a killed avatar is
only disabled, so it goes on). Each kernel below gives that result with batched ops: for these
effects no first sprite's application changes another's, except a stepBack among the sprites of
one table, which ``step_back_in_order`` resolves in slot order (the processing order, see
``layout``).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import torch

from gvgai_pcg._private_apis import assert_async
from gvgai_pcg.games.geometry import NONE
from gvgai_pcg.games.rules import step_back_in_order
from gvgai_pcg.vgdl.engine.checks import score_of
from gvgai_pcg.vgdl.engine.columns import fresh_columns
from gvgai_pcg.vgdl.engine.frame import Entry, Frame, Side, sides
from gvgai_pcg.vgdl.engine.from_above import kill_if_from_above
from gvgai_pcg.vgdl.engine.kill_both import kill_both, kill_listed_cells
from gvgai_pcg.vgdl.engine.layout import Layout
from gvgai_pcg.vgdl.engine.ordered import ordered_step_back
from gvgai_pcg.vgdl.engine.pixel_perfect import step_back_pixel_perfect
from gvgai_pcg.vgdl.engine.pull import pull_with_it
from gvgai_pcg.vgdl.engine.push import bounce_forward
from gvgai_pcg.vgdl.engine.resources import change_resource, collect_resource, kill_if_other_has_more
from gvgai_pcg.vgdl.engine.reverse import reverse_direction
from gvgai_pcg.vgdl.engine.shield import shield_from
from gvgai_pcg.vgdl.engine.spawn_effects import spawn, spawn_if_has_more
from gvgai_pcg.vgdl.engine.transform_grid import transform_into_grid
from gvgai_pcg.vgdl.engine.transform_table import transform_into_table
from gvgai_pcg.vgdl.engine.undo import undo_all
from gvgai_pcg.vgdl.errors import VGDLError
from gvgai_pcg.vgdl.layout import GRID, RECORD, TABLE
from gvgai_pcg.vgdl.plan import RulePlan


@dataclass(frozen=True)
class Rule:
    plan: RulePlan
    firsts: tuple[Side, ...]
    seconds: tuple[Side, ...]
    score: int
    # the error of a creation that finds no room: its record taken, or its table full (made here:
    # no f-string in a graph)
    overflow: str


def make_rules(layout: Layout) -> tuple[Rule, ...]:
    rules = []
    for rule in layout.plan.pairs:
        made = Rule(
            rule,
            tuple(sides(layout, rule.firsts)),
            tuple(sides(layout, rule.seconds)),
            score_of(layout.plan, rule),
            _overflow(layout, rule),
        )
        if rule.kind == "F" and (len(made.firsts) != 1 or made.seconds != made.firsts):
            raise VGDLError(
                layout.plan.path, rule.line, f"{rule.name} among sprites of several tables is not implemented"
            )
        if rule.name == "pullWithIt" and len(made.seconds) != 1:
            raise VGDLError(
                layout.plan.path, rule.line, "pullWithIt by sprites of several tables is not implemented"
            )
        rules.append(made)
    return tuple(rules)


def _overflow(layout: Layout, rule: RulePlan) -> str:
    """The one-line error of ``rule``'s creation that finds no room for its ``stype``."""
    made = rule.values.get("stype")
    where = f"{layout.plan.path}:{rule.line}: {rule.name} into {made!r}"
    place = layout.places.get(str(made))
    if place is not None and place.representation == TABLE:
        return f"{where} found the table {place.key!r} full (its capacity is the plan's)"
    return f"{where}, which already holds its one sprite"


def apply_rule(frame: Frame, rule: Rule) -> None:
    """The rule's kernel; in envs where a shieldFrom shields the rule (its pair's first and second
    and its effect), no first is eligible (Java skips the rule)."""
    frame.skip = frame.shields.get((rule.plan.first, rule.plan.second, rule.plan.name))
    KERNELS[rule.plan.name](frame, rule)
    frame.skip = None


def step_back(frame: Frame, rule: Rule) -> None:
    """stepBack: a first that overlaps a second goes back to where it started the tick. A still
    (grid) first started there already. ``pixelPerfect``: ``pixel_perfect``."""
    if rule.plan.values.get("pixelPerfect"):
        step_back_pixel_perfect(frame, rule)
        return
    for first in rule.firsts:
        if first.representation == GRID:
            continue
        entry = frame.entry(first.key)
        x, y, lastx, lasty = (entry.get(key) for key in ("x", "y", "lastx", "lasty"))
        eligible = frame.eligible(first)
        axis = _aligned_axis(frame.layout, first)
        if rule.plan.kind == "F" and axis is not None:
            present = frame.present(rule.seconds[0])
            x, y = ordered_step_back(x, y, lastx, lasty, eligible, present, axis == "x")
        elif rule.plan.kind == "F":
            x, y = step_back_in_order(
                x, y, lastx, lasty, eligible, frame.present(rule.seconds[0]), first.aligned
            )
        else:
            fx, fy = frame.xy(first)
            back = eligible & (frame.overlap_count(fx, fy, first.aligned, first, list(rule.seconds)) > 0)
            # A record's mask is [B, 1]: its positions are written back [B], never as views.
            back = back.squeeze(-1) if first.representation == RECORD else back
            x, y = torch.where(back, lastx, x), torch.where(back, lasty, y)
        entry.update({"x": x, "y": y})


def _aligned_axis(layout: Layout, side: Side) -> str | None:
    """The one axis along which every sprite of ``side`` stays on whole cells; None where both
    do (``step_back_in_order`` compares those by position) or neither does."""
    if side.aligned or side.representation != TABLE:
        return None
    names = [layout.group(side.key).kinds[code] for code in side.kinds]
    for axis in ("x", "y"):
        if all(getattr(layout.plan.types[name], f"aligned_{axis}") for name in names):
            return axis
    return None


def kill_sprite(frame: Frame, rule: Rule) -> None:
    """killSprite: a first that overlaps a second is killed, ``scoreChange`` each time it is
    applied: once for a sprite (then it is killed), once per second for an avatar (only
    disabled, it stays a first)."""
    for first in rule.firsts:
        if first.representation == GRID:
            _kill_cells(frame, rule, first)
            continue
        x, y = frame.xy(first)
        hits = frame.overlap_count(x, y, first.aligned, first, list(rule.seconds)) * frame.eligible(first)
        touched = hits > 0
        frame.kill(first, touched)
        applied = hits if first.key in frame.layout.avatars else touched.long()
        frame.add_score(rule.score * applied.sum(-1))


def _kill_cells(frame: Frame, rule: Rule, first: Side) -> None:
    """killSprite of a grid type: every sprite of it not yet killed in a cell a second covers."""
    grid = frame.grid(first.key)
    batch, height, width = grid.shape
    touched = torch.zeros(batch, height * width, dtype=torch.int32, device=grid.device)
    for second in rule.seconds:
        x, y = frame.xy(second)
        index, valid = frame.cells(x, y, second.aligned, height, width)
        valid = valid & frame.present(second).unsqueeze(-1)
        touched = touched.scatter_add(1, index.reshape(batch, -1), valid.reshape(batch, -1).to(torch.int32))
    killed = frame.grid_killed(first.key)
    newly = torch.where(touched.view(grid.shape) > 0, grid - killed, torch.zeros_like(grid))
    frame.killed[first.key] = killed + newly
    frame.add_score(rule.score * newly.flatten(1).sum(-1, dtype=torch.int32))  # int32: a faster sum


def transform_to(frame: Frame, rule: Rule) -> None:
    """transformTo (first a record, ``stype`` a record): a first not disabled that overlaps a
    second becomes an ``stype`` sprite where it is (its last position copied; its facing copied
    only if ``stype``'s default is NONE; its other columns fresh), is killed, and kills the first
    second it overlaps in list order with ``killSecond``; once, since it is then killed. A disabled
    first is not transformed but scores for every second it overlaps (Java adds the score anyway).
    A record made into its own type is renewed in place; one made by this rule is no first of it
    (Java's rule takes its sprites before it applies)."""
    made = str(rule.plan.values["stype"])
    if made in frame.layout.grids:
        transform_into_grid(frame, rule)
        return
    if frame.layout.places[made].representation == TABLE:
        transform_into_table(frame, rule)
        return
    target = frame.entry(made)
    made_now = torch.zeros_like(target.get("alive"))
    for first in rule.firsts:
        record = frame.entry(first.key)
        x, y = record.get("x").unsqueeze(-1), record.get("y").unsqueeze(-1)
        eligible = frame.eligible(first).squeeze(-1)
        if first.key == made:
            eligible = eligible & ~made_now
        hits = torch.zeros_like(record.get("x"))
        firsts_hit: list[tuple[Side, torch.Tensor, torch.Tensor | None]] = []
        found = torch.zeros_like(eligible)
        for second in rule.seconds:
            if second.representation == GRID:
                index, counts = frame.cell_counts(second.key, x, y, first.aligned)
                index, hit = index.squeeze(1), counts.squeeze(1) > 0
                hits = hits + counts.squeeze(1).sum(-1)
            else:
                index, hit = None, frame.overlap_matrix(x, y, first.aligned, first, second).squeeze(1)
                hits = hits + hit.sum(-1)
            first_hit = hit & (hit.cumsum(-1) == 1) & ~found.unsqueeze(-1)
            found = found | hit.any(-1)
            firsts_hit.append((second, first_hit, index))
        hits = hits * eligible
        disabled = frame.is_disabled(first.key)
        disabled = torch.zeros_like(eligible) if disabled is None else disabled
        fire = (hits > 0) & ~disabled
        frame.add_score(rule.score * torch.where(disabled, hits, fire.long()))
        if first.key != made:
            assert_async(  # no host sync: the tick stays one graph
                ~(fire & target.get("alive")).any(),
                rule.overflow,
            )
        _create(frame, made, fire, record)
        made_now = made_now | fire
        if first.key != made:
            frame.mark_killed(first.key, fire)
        if rule.plan.values.get("killSecond"):
            for second, first_hit, index in firsts_hit:
                chosen = first_hit & fire.unsqueeze(-1)
                if second.representation == GRID:
                    kill_listed_cells(frame, second.key, index, chosen)
                else:
                    frame.kill(second, chosen)


def _create(frame: Frame, name: str, where: torch.Tensor, source: Entry) -> None:
    """Put an ``name`` sprite (a record) where ``source`` (a record) is, where ``where``: fresh
    but for its position, last position and facing."""
    layout = frame.layout
    target = frame.entry(name)
    default = layout.orientation[name]
    ori = source.get("ori") if default == NONE else torch.full_like(source.get("ori"), default)
    values = {
        key: torch.where(where, source.get(key), target.get(key)) for key in ("x", "y", "lastx", "lasty")
    }
    values["ori"] = torch.where(where, ori, target.get("ori"))
    values["alive"] = target.get("alive") | where
    for column, value in fresh_columns(layout.plan, (name,)).items():
        current = target.get(column)
        values[column] = torch.where(where, torch.full_like(current, value), current)
    target.update(values)


KERNELS: dict[str, Callable[[Frame, Rule], None]] = {
    "stepBack": step_back,
    "killSprite": kill_sprite,
    "transformTo": transform_to,
    "spawn": spawn,
    "spawnIfHasMore": spawn_if_has_more,
    "changeResource": change_resource,
    "reverseDirection": reverse_direction,
    "collectResource": collect_resource,
    "killIfOtherHasMore": kill_if_other_has_more,
    "killIfFromAbove": kill_if_from_above,
    "shieldFrom": shield_from,
    "pullWithIt": pull_with_it,
    "bounceForward": bounce_forward,
    "undoAll": undo_all,
    "killBoth": kill_both,
}
