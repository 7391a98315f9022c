"""A plan as text for people (``gvgai-pcg vgdl inspect``): per type its representation and
why, per rule its kind and why, and each table's capacity (a formula, or slots for a level)."""

from __future__ import annotations

from collections import Counter

from gvgai_pcg.vgdl.describe import show
from gvgai_pcg.vgdl.plan import Plan, RulePlan


def describe_plan(plan: Plan) -> str:
    reps = Counter(sprite.representation for sprite in plan.types.values())
    kinds = Counter(rule.kind for rule in plan.rules())
    lines = [
        "plan:",
        "  types: " + ", ".join(f"{count} {rep}" for rep, count in sorted(reps.items())),
        "  rule kinds: " + (", ".join(f"{count} {kind}" for kind, count in sorted(kinds.items())) or "-"),
    ]
    for sprite in plan.types.values():
        axes = " and ".join(
            axis for axis, whole in (("x", sprite.aligned_x), ("y", sprite.aligned_y)) if not whole
        )
        aligned = "aligned" if sprite.aligned else f"off the cells in {axes}: {sprite.why_unaligned}"
        text = f"  {sprite.name}: {sprite.representation} ({sprite.why}); {aligned}"
        if sprite.step_px:
            text += f"; {sprite.step_px} px a move"
        if sprite.singleton_guard:
            text += f"; not created while a {' or '.join(sprite.singleton_guard)} exists (singleton)"
        if sprite.capacity is not None:
            text += f"; slots {sprite.capacity.formula()}"
            if plan.slots is not None:
                text += f" = {plan.slots[sprite.name]}"
            text += f" ({sprite.capacity.why})"
        lines.append(text)
    for title, rules in (("EOS", plan.eos), ("pairs", plan.pairs), ("timed", plan.timed)):
        if rules:
            lines.append(f"  {title}:")
            lines.extend(_rule(rule) for rule in rules)
    for termination in plan.terminations:
        counted = " | ".join("+".join(names) for names in termination.counted) or "-"
        outcome = "win" if termination.win else "lose"
        lines.append(
            f"  termination line {termination.line}: {termination.java_class} counts {counted}, "
            f"limit {termination.limit} -> {outcome}"
        )
    return "\n".join(lines)


def _rule(rule: RulePlan) -> str:
    random = ", random" if rule.random else ""
    score = rule.values.get("scoreChange")
    scored = f", score {show(score)}" if score not in (None, "0") else ""
    return (
        f"    {rule.kind} {rule.first} {rule.second}: {rule.name}(line {rule.line}{scored}{random}) "
        f"on {'+'.join(rule.firsts)} x {'+'.join(rule.seconds) or rule.second}: {rule.why}"
    )
