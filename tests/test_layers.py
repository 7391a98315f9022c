"""Imports only go downward: the package's import graph against its layers, statically.

The graph is read from the source with ``ast``, not by importing: every ``import gvgai_pcg...``
and ``from gvgai_pcg... import ...`` of every module, including those inside functions (a lazy
import is still a dependency), but not those under ``if TYPE_CHECKING:`` (annotations only).
``from package import name`` counts as an import of ``package.name`` where that is a module.

The layers, lowest first. A module may import its own layer and the layers below it:

1. ``progress``: terminal progress bars, imports nothing of gvgai_pcg.
   ``config rules``: the config schema's rules, the log backends' names and the entry-point loop
   of every registry (``plugins``), nothing of gvgai_pcg either, so that a curriculum or a learner
   declares its schema without the config checks.
2. ``registry``: ``games`` (the package's ``__init__``), ``games.spec`` and ``games.registry``:
   the game specs and the one registry. Built-in games are found by scanning the game folders
   and loading them by name on first use (like entry points), so parsing a level can ask for
   its game's format without importing any game.
3. ``levels``: the ``Level`` value, formats, human levels, test sets, seed ranges.
4. ``kit``: what every game builds on: ``engine`` (row copies, buffers), the game kit
   (``games.base``, ``geometry``, ``rules``, ``rng``, ``render``), the generator kit
   (``generators._common``) and ``vgdl``, GVGAI's game descriptions read as Java reads them
   (pure Python, it imports nothing of gvgai_pcg; games built from VGDL files sit above it).
5. ``game``: the game folders ``games/<name>/`` (rules, generator, checks, spec). A game folder
   never imports another game folder (checked apart).
6. ``readers``: ``generators`` and ``analysis``: the registry's readers.
7. ``envs``: the TorchRL env, level sources (``LevelSource``), transforms, the buffers its
   processes share, and the Gymnasium ids' registration (which names the entry points in
   ``gym`` as strings and imports only the registry).
8. ``curricula``: the curricula that hand the env its levels, built on the env's level sources.
   The env never imports a curriculum: it reads what it needs from the ``LevelSource`` contract.
9. ``gym``: the Gymnasium API, which trains on the curricula by name.
10. ``rundir``: the run directory's I/O (atomic files, the folder lock, the log, checkpoints and
   snapshots, provenance, the stop signal, earlier outputs set aside), which ``rl``, ``evaluation``,
   ``report`` and ``study`` read and write without the training code.
11. ``rl``: models, A2C, the training loop, the training session, and ``config``, the training config's
   checks and its memory estimate (they ask the models for their names).
12. ``evaluation``.
13. ``apps``: ``report``, ``bench`` (every benchmark and the device check), ``play``.
14. ``study``, in four layers of its own: ``study.sweeps`` (conditions, budgets, borrowed runs,
   publishing), ``study.verdicts`` (the runs read into tables, the claims' rules, intervals, the
   one judging system), ``study.pages`` (the results pages, written from the verdicts), and the
   package itself with ``pipeline`` and ``sweep_status``, which run a sweep through all three.
15. ``commands``: ``commands``, ``cli`` and the package root (which registers the Gymnasium ids).

Importing ``a.b.c`` also runs ``a/b/__init__.py``, which has a layer of its own: it may sit
above some of its modules (``generators`` above the kit ``generators._common``) as long as it
imports nothing above them, so that importing the kit never pulls in a higher layer. The package
root is left out of that: it registers the Gymnasium ids, which reads only the registry.

``KNOWN_VIOLATIONS`` lists the upward edges that exist today and are being removed elsewhere;
the test fails on any other, and on a listed one that no longer exists (so the list shrinks).
"""

from __future__ import annotations

import ast
from functools import cache
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
PACKAGE = "gvgai_pcg"

LAYERS: tuple[tuple[str, tuple[str, ...]], ...] = (
    ("progress", ("gvgai_pcg.progress",)),
    ("config rules", ("gvgai_pcg.config_rules", "gvgai_pcg.log_backends", "gvgai_pcg.plugins")),
    ("private APIs", ("gvgai_pcg._private_apis",)),
    ("registry", ("gvgai_pcg.games:", "gvgai_pcg.games.spec", "gvgai_pcg.games.registry")),
    ("levels", ("gvgai_pcg.levels",)),
    (
        "kit",
        (
            "gvgai_pcg.engine",
            "gvgai_pcg.games.base",
            "gvgai_pcg.games.actions",
            "gvgai_pcg.games.lookup",
            "gvgai_pcg.games.geometry",
            "gvgai_pcg.games.rules",
            "gvgai_pcg.games.rng",
            "gvgai_pcg.games.render",
            "gvgai_pcg.generators._common",
            "gvgai_pcg.vgdl",
        ),
    ),
    ("game", ("gvgai_pcg.games",)),
    ("readers", ("gvgai_pcg.generators", "gvgai_pcg.analysis")),
    ("envs", ("gvgai_pcg.envs",)),
    ("curricula", ("gvgai_pcg.curricula",)),
    ("gym", ("gvgai_pcg.gym",)),
    ("run directory", ("gvgai_pcg.rundir",)),
    ("rl", ("gvgai_pcg.rl", "gvgai_pcg.config")),
    ("evaluation", ("gvgai_pcg.evaluation",)),
    ("apps", ("gvgai_pcg.report", "gvgai_pcg.bench", "gvgai_pcg.play")),
    ("study sweeps", ("gvgai_pcg.study.sweeps",)),
    ("study verdicts", ("gvgai_pcg.study.verdicts",)),
    ("study pages", ("gvgai_pcg.study.pages",)),
    ("study", ("gvgai_pcg.study",)),
    ("commands", ("gvgai_pcg.commands", "gvgai_pcg.cli", "gvgai_pcg:")),
)

# Upward imports tolerated for now: none (the last, rl/agent.py playing through evaluation's
# runner, went with the one policy loader in evaluation/policy.py).
KNOWN_VIOLATIONS: set[tuple[str, str]] = set()

MAX_ROOT_MODULES = 7  # __init__ included


def module_name(path: Path) -> str:
    parts = path.relative_to(ROOT).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


@cache
def modules() -> dict[str, Path]:
    return {module_name(path): path for path in (ROOT / PACKAGE).rglob("*.py")}


def _type_checking_nodes(tree: ast.AST) -> set[int]:
    """ids of the nodes under ``if TYPE_CHECKING:`` blocks."""
    skipped = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.If) and "TYPE_CHECKING" in ast.unparse(node.test):
            skipped |= {id(inner) for child in node.body for inner in ast.walk(child)}
    return skipped


@cache
def imports() -> dict[str, frozenset[str]]:
    """Module -> the gvgai_pcg modules it imports explicitly (anywhere in its body)."""
    known = modules()
    graph = {}
    for name, path in known.items():
        tree = ast.parse(path.read_text(), str(path))
        skipped = _type_checking_nodes(tree)
        package = name.split(".") if path.name == "__init__.py" else name.split(".")[:-1]
        targets = set()
        for node in ast.walk(tree):
            if id(node) in skipped:
                continue
            if isinstance(node, ast.Import):
                targets |= {alias.name for alias in node.names}
            elif isinstance(node, ast.ImportFrom):
                base = node.module or ""
                if node.level:
                    base = ".".join(package[: len(package) - node.level + 1] + ([base] if base else []))
                for alias in node.names:
                    targets.add(f"{base}.{alias.name}" if f"{base}.{alias.name}" in known else base)
        graph[name] = frozenset(t for t in targets if t in known and t != name)
    return graph


def parents(name: str) -> list[str]:
    """The packages whose ``__init__`` runs before ``name`` (the root left out)."""
    parts = name.split(".")
    return [".".join(parts[:i]) for i in range(2, len(parts))]


def layer_of(name: str) -> int:
    """The index in LAYERS of the longest pattern that matches ``name`` (``x:`` matches x only)."""
    best, best_length = None, -1
    for index, (_, patterns) in enumerate(LAYERS):
        for pattern in patterns:
            exact = pattern.endswith(":")
            prefix = pattern.rstrip(":")
            matches = name == prefix if exact else name == prefix or name.startswith(prefix + ".")
            if matches and len(prefix) + exact > best_length:
                best, best_length = index, len(prefix) + exact
    assert best is not None, f"{name} is in no layer: add it to LAYERS in {__file__}"
    return best


def game_folder(name: str) -> str | None:
    """``zelda`` for ``gvgai_pcg.games.zelda.rules``; ``None`` outside the game folders."""
    parts = name.split(".")
    if len(parts) >= 3 and parts[1] == "games" and (ROOT / PACKAGE / "games" / parts[2]).is_dir():
        return parts[2]
    return None


def upward_imports() -> set[tuple[str, str]]:
    return {
        (source, target)
        for source, targets in imports().items()
        for target in targets
        if layer_of(target) > layer_of(source)
    }


def test_every_module_has_a_layer():
    for name in modules():
        layer_of(name)


def test_imports_only_go_downward():
    found = upward_imports()
    new = sorted(found - KNOWN_VIOLATIONS)
    described = [f"{s} ({LAYERS[layer_of(s)][0]}) -> {t} ({LAYERS[layer_of(t)][0]})" for s, t in new]
    assert not new, "imports that go up a layer:\n" + "\n".join(described)
    assert not KNOWN_VIOLATIONS - found, (
        f"fixed, take them out of KNOWN_VIOLATIONS: {KNOWN_VIOLATIONS - found}"
    )


def test_game_folders_do_not_import_each_other():
    crossing = sorted(
        (source, target)
        for source, targets in imports().items()
        for target in targets
        if game_folder(source) and game_folder(target) and game_folder(source) != game_folder(target)
    )
    assert not crossing


def test_no_import_cycles():
    """No module reaches itself through its imports, and no two layers import each other beyond
    the known violations."""
    graph = {name: set(targets) for name, targets in imports().items()}
    cycles = sorted(name for name in graph if name in _reachable(graph, name))
    assert not cycles, f"modules on an import cycle: {cycles}"
    layer_edges = {(layer_of(s), layer_of(t)) for s, t in upward_imports() - KNOWN_VIOLATIONS}
    assert not layer_edges


def test_package_inits_stay_below_their_modules():
    """Importing ``a.b.c`` runs ``a/b/__init__.py`` first: a package's ``__init__`` imports nothing
    above the layer of any module inside it (``generators/__init__`` may read the registry, which
    the generator kit ``generators._common`` lies above, but never a generator)."""
    too_high = sorted(
        (name, package, target)
        for name in modules()
        for package in parents(name)
        for target in imports()[package]
        if layer_of(target) > layer_of(name)
    )
    assert not too_high, f"(module, its package, what the package imports above it): {too_high}"


def _reachable(graph: dict[str, set[str]], start: str) -> set[str]:
    seen, stack = set(), [start]
    while stack:
        for target in graph[stack.pop()]:
            if target not in seen:
                seen.add(target)
                stack.append(target)
    return seen


def test_the_package_root_keeps_few_modules():
    """A module at the root is one of the tree's layers or the entry points; anything else has a
    folder (``bench``, ``config``), so the tree shows its layers at a glance."""
    root = sorted(path.name for path in (ROOT / PACKAGE).glob("*.py"))
    assert len(root) <= MAX_ROOT_MODULES, f"{len(root)} modules at the package root: {root}"


def test_the_graph_sees_lazy_and_relative_imports():
    """The reader finds an import inside a function (render asks the registry for a game)."""
    assert "gvgai_pcg.games.registry" in imports()["gvgai_pcg.games.render"]
    assert "gvgai_pcg.games.zelda.checks" in imports()["gvgai_pcg.games.zelda"]


def test_the_run_directory_needs_no_training_code():
    """evaluation, report and study read and write run directories through ``rundir``: none of
    them imports ``rl`` for a file's I/O, and ``rundir`` imports nothing of ``rl``."""
    io = (
        "gvgai_pcg.rl.atomic_files",
        "gvgai_pcg.rl.checkpoint",
        "gvgai_pcg.rl.run_log",
        "gvgai_pcg.rl.run_lock",
    )
    assert not [name for name in io if name in modules()]
    assert not [
        (source, target)
        for source, targets in imports().items()
        if source.startswith("gvgai_pcg.rundir")
        for target in targets
        if target.startswith("gvgai_pcg.rl")
    ]


def test_the_env_imports_no_curriculum():
    """Curricula build on the env's level sources, never the reverse: ``envs`` imports nothing of
    ``curricula`` nor of the Gymnasium API above it (the layers say so too; this names the rule)."""
    found = sorted(
        (source, target)
        for source, targets in imports().items()
        if source.startswith("gvgai_pcg.envs")
        for target in targets
        if target.startswith(("gvgai_pcg.curricula", "gvgai_pcg.gym"))
    )
    assert not found, f"envs importing curricula or gym: {found}"
    assert "gvgai_pcg.envs.level_sources" in imports()["gvgai_pcg.curricula.plr"]
