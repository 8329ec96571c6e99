"""Comparisons on part names in lcchain's source, found by reading its AST (issue 34, item 1).

A part (an engine, a transport, an analysis, an executor, a case, a mode method, an effect) describes itself;
code outside the registries asks a part's attributes, never its name.  :func:`name_comparisons` lists every
place that does otherwise:

- an ``==``, ``!=``, ``in`` or ``not in`` comparison, or a ``match`` statement, with a name-like attribute or
  variable (``engine``, ``simulator.engine``, ``spec.backend``, ``meta["analysis"]``, ``kind`` ...) on one side
  and a registered part name (a string, or a tuple/list/set of strings) on the other;
- an ``isinstance`` check against an effect class (a registered effect type).

Run it as a script (``python tests/helpers/name_comparisons.py [PACKAGE_FOLDER]``) to print the places and
their count (another checkout's ``lcchain`` folder: its count before a change).
"""

from __future__ import annotations

import ast
import re
import sys
from dataclasses import dataclass
from pathlib import Path

PACKAGE = Path(__file__).resolve().parents[2] / "lcchain"

#: Identifiers that hold a part's name (the last part of an attribute, a variable, a subscript's key), each with
#: the kinds of part whose names it is compared with; a generic one (``name``, ``kind``, ``key``) with any kind.
NAME_LIKE: tuple[tuple[re.Pattern[str], tuple[str, ...] | None], ...] = tuple(
    (re.compile(rf"(^|_){word}$", re.IGNORECASE), kinds) for word, kinds in (
        (r"engines?", ("engine",)),
        (r"(backend|transport)s?", ("transport",)),
        (r"(analysis|analyses)", ("analysis",)),
        (r"executors?", ("executor",)),
        (r"cases?", ("case",)),
        (r"(mode_)?methods?", ("mode method",)),
        (r"effects?", ("effect",)),
        (r"(name|kind|key|plot)s?", None),
    ))

#: The modules that are registries (where a name is looked up, which is their job).
REGISTRIES = {"core/registry.py", "core/types.py", "core/parts.py", "spice/engines.py"}


def part_names() -> dict[str, tuple[str, ...]]:
    """Every registered part name -> the kinds of part it names, read from the registries themselves."""
    from lcchain.circuit.effects import EFFECTS
    from lcchain.core.types import ANALYSIS_KINDS, CASES, EXECUTORS, MODE_METHODS, TRANSPORTS
    from lcchain.spice.engines import ENGINES

    names: dict[str, tuple[str, ...]] = {}
    for kind, keys in (("engine", ENGINES), ("transport", TRANSPORTS), ("analysis", (*ANALYSIS_KINDS, "tran")),
                       ("executor", EXECUTORS), ("case", CASES), ("mode method", MODE_METHODS),
                       ("effect", EFFECTS)):
        for key in keys:
            names[str(key)] = (*names.get(str(key), ()), kind)
    return names


def effect_classes() -> set[str]:
    from lcchain.circuit.effects import EFFECTS

    return {cls.__name__ for cls in EFFECTS.values()}


@dataclass(frozen=True)
class Place:
    path: str
    line: int
    text: str
    part: str

    def __str__(self) -> str:
        return f"{self.path}:{self.line}: {self.part}: {self.text}"


def _identifier(node: ast.expr) -> str | None:
    if isinstance(node, ast.Name):
        return node.id
    if isinstance(node, ast.Attribute):
        return node.attr
    if isinstance(node, ast.Subscript) and isinstance(node.slice, ast.Constant) and isinstance(node.slice.value, str):
        return node.slice.value
    if isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute) and node.func.attr == "get" \
            and node.args and isinstance(node.args[0], ast.Constant) and isinstance(node.args[0].value, str):
        return node.args[0].value
    return None


def _kinds(node: ast.expr) -> tuple[str, ...] | None | bool:
    """The kinds of part a name-like operand's name is compared with (None: any), or False: not name-like."""
    ident = _identifier(node)
    if ident is None:
        return False
    for pattern, kinds in NAME_LIKE:
        if pattern.search(ident):
            return kinds
    return False


def _strings(node: ast.expr) -> list[str]:
    if isinstance(node, ast.Constant) and isinstance(node.value, str):
        return [node.value]
    if isinstance(node, (ast.Tuple, ast.List, ast.Set)):
        return [e.value for e in node.elts if isinstance(e, ast.Constant) and isinstance(e.value, str)]
    return []


def _pattern_strings(pattern: ast.pattern) -> list[str]:
    if isinstance(pattern, ast.MatchValue):
        return _strings(pattern.value)
    if isinstance(pattern, ast.MatchOr):
        return [s for p in pattern.patterns for s in _pattern_strings(p)]
    if isinstance(pattern, ast.MatchAs) and pattern.pattern is not None:
        return _pattern_strings(pattern.pattern)
    return []


def _scan(tree: ast.AST, source: str, path: str, names: dict[str, tuple[str, ...]],
          effects: set[str]) -> list[Place]:
    found: list[Place] = []

    def add(node: ast.expr | ast.stmt, hit: str) -> None:
        found.append(Place(path, node.lineno, source.splitlines()[node.lineno - 1].strip(), hit))

    for node in ast.walk(tree):
        if isinstance(node, ast.Compare):
            operands = [node.left, *node.comparators]
            for op, left, right in zip(node.ops, operands, operands[1:], strict=False):
                if not isinstance(op, (ast.Eq, ast.NotEq, ast.In, ast.NotIn)):
                    continue
                for subject, other in ((left, right), (right, left)):
                    kinds = _kinds(subject)
                    if kinds is False:
                        continue
                    hits = [s for s in _strings(other) if any(kinds is None or kind in kinds for kind in names.get(s, ()))]
                    if hits:
                        add(node, f"{'/'.join(names[hits[0]])} {hits[0]!r}")
                        break
        elif isinstance(node, ast.Match) and _kinds(node.subject) is not False:
            kinds = _kinds(node.subject)
            hits = [s for case in node.cases for s in _pattern_strings(case.pattern)
                    if any(kinds is None or kind in kinds for kind in names.get(s, ()))]
            if hits:
                add(node, f"match on {'/'.join(names[hits[0]])} {hits[0]!r}")
        elif isinstance(node, ast.Call) and isinstance(node.func, ast.Name) and node.func.id == "isinstance" \
                and len(node.args) == 2:
            kinds = node.args[1].elts if isinstance(node.args[1], ast.Tuple) else [node.args[1]]
            hit = [k.id for k in kinds if isinstance(k, ast.Name) and k.id in effects]
            if hit:
                add(node, f"isinstance on effect {hit[0]}")
    return found


def name_comparisons(package: Path = PACKAGE) -> list[Place]:
    """Every comparison on a part name in the package's modules outside :data:`REGISTRIES`, in file order."""
    names = part_names()
    effects = effect_classes()
    found: list[Place] = []
    for file in sorted(package.rglob("*.py")):
        path = file.relative_to(package).as_posix()
        if path in REGISTRIES:
            continue
        source = file.read_text(encoding="utf-8")
        found += sorted(_scan(ast.parse(source), source, path, names, effects), key=lambda p: p.line)
    return found


if __name__ == "__main__":
    places = name_comparisons(Path(sys.argv[1]) if len(sys.argv) > 1 else PACKAGE)
    for place in places:
        print(place)
    print(f"{len(places)} comparisons on part names")
    sys.exit(0)
