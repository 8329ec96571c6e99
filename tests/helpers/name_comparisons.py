"""Comparisons on part names in lcchain's source, found by reading its AST (issue 34, item 1).

A part (an engine, a transport, an analysis, an executor, a case, a mode method, an effect) describes itself;
code outside the registries asks a part's attributes, never its name.  :func:`name_comparisons` lists every
place that does otherwise:

- an ``==``, ``!=``, ``in`` or ``not in`` comparison, or a ``match`` statement, with a name-like attribute or
  variable (``engine``, ``simulator.engine``, ``spec.backend``, ``meta["analysis"]``, ``kind`` ...) on one side
  and a registered part name (a string, or a tuple/list/set of strings) on the other;
- an ``isinstance`` check against an effect class (a registered effect type).

Run it as a script (``python tests/helpers/name_comparisons.py``) to print the places and their count.
"""

from __future__ import annotations

import ast
import re
import sys
from dataclasses import dataclass
from pathlib import Path

PACKAGE = Path(__file__).resolve().parents[2] / "lcchain"

#: Identifiers that hold a part's name (the last part of an attribute, a variable, a subscript's key).
NAME_LIKE = re.compile(r"(^|_)(name|engine|engines|backend|backends|transport|transports|analysis|analyses|kind|"
                       r"executor|method|case|effect|key|plot)s?$", re.IGNORECASE)

#: The modules that are registries (where a name is looked up, which is their job).
REGISTRIES = {"core/registry.py", "core/types.py", "core/parts.py", "spice/engines.py"}


def part_names() -> dict[str, str]:
    """Every registered part name -> the kind of part it names, read from the registries themselves."""
    from lcchain.circuit.effects import EFFECTS
    from lcchain.core.types import ANALYSIS_KINDS, CASES, EXECUTORS, MODE_METHODS, TRANSPORTS
    from lcchain.spice.engines import ENGINES

    names: dict[str, str] = {}
    for kind, keys in (("engine", ENGINES), ("transport", TRANSPORTS), ("analysis", (*ANALYSIS_KINDS, "tran")),
                       ("executor", EXECUTORS), ("case", CASES), ("mode method", MODE_METHODS),
                       ("effect", EFFECTS)):
        for key in keys:
            names.setdefault(str(key), kind)
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


def _name_like(node: ast.expr) -> bool:
    ident = _identifier(node)
    return ident is not None and NAME_LIKE.search(ident) is not None


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


def _scan(tree: ast.AST, source: str, path: str, names: dict[str, str], effects: set[str]) -> list[Place]:
    found: list[Place] = []

    def add(node: ast.AST, hit: str) -> None:
        line = source.splitlines()[node.lineno - 1].strip()  # type: ignore[attr-defined]
        found.append(Place(path, node.lineno, line, hit))  # type: ignore[attr-defined]

    for node in ast.walk(tree):
        if isinstance(node, ast.Compare):
            operands = [node.left, *node.comparators]
            for op, left, right in zip(node.ops, operands, operands[1:], strict=False):
                if not isinstance(op, (ast.Eq, ast.NotEq, ast.In, ast.NotIn)):
                    continue
                for subject, other in ((left, right), (right, left)):
                    if not _name_like(subject):
                        continue
                    hits = [s for s in _strings(other) if s in names]
                    if hits:
                        add(node, f"{names[hits[0]]} {hits[0]!r}")
                        break
        elif isinstance(node, ast.Match) and _name_like(node.subject):
            hits = [s for case in node.cases for s in _pattern_strings(case.pattern) if s in names]
            if hits:
                add(node, f"match on {names[hits[0]]} {hits[0]!r}")
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
    places = name_comparisons()
    for place in places:
        print(place)
    print(f"{len(places)} comparisons on part names")
    sys.exit(0)
