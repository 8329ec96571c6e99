"""``Any`` only where a value really is arbitrary JSON (issue 34): the one alias of :mod:`lcchain.core.json` that
says so (``LooseJSON``), and the few places below where a library's own signature is passed on as it is.  Read
from the syntax tree, so a docstring's "Any chain" is not counted and a new ``Any`` in a signature is."""

from __future__ import annotations

import ast
from pathlib import Path

PACKAGE = Path(__file__).resolve().parent.parent / "lcchain"

#: Where ``Any`` may stand, and why: module (relative to lcchain/) -> the number of uses.
ALLOWED = {
    "core/json.py": 1,  # LooseJSON: a JSON document read by key, named so that its readers say why
    "cli/common.py": 3,  # argparse's Action.__call__ values and ArgumentParser.__init__'s arguments, passed on
    "studies/spectrum_checks.py": 1,  # Effect.response()'s keywords unpacked into SpectrumOptions' typed fields
}


def uses_of_any(tree: ast.AST) -> int:
    """``Any`` and ``typing.Any`` as a name in code or an annotation (strings and docstrings are not code)."""
    count = 0
    for node in ast.walk(tree):
        if isinstance(node, ast.Name) and node.id == "Any":
            count += 1
        elif isinstance(node, ast.Attribute) and node.attr == "Any" and isinstance(node.value, ast.Name) \
                and node.value.id in ("typing", "t"):
            count += 1
    return count


def test_any_only_where_a_value_is_arbitrary() -> None:
    found = {}
    for path in sorted(PACKAGE.rglob("*.py")):
        count = uses_of_any(ast.parse(path.read_text(), str(path)))
        if count:
            found[path.relative_to(PACKAGE).as_posix()] = count
    assert found == ALLOWED


def test_the_count_sees_an_annotation() -> None:
    code = "from typing import Any\nimport typing\ndef f(x: Any) -> typing.Any:\n    '''Any chain.'''\n"
    assert uses_of_any(ast.parse(code)) == 2


def test_every_lazy_public_name_is_typed_as_itself() -> None:
    """``lcchain/__init__.py`` loads its public names on first use (``_PUBLIC``: name -> module) and, for a type
    checker, imports each under ``TYPE_CHECKING`` from the same module: the two lists must agree, or a new name
    would be typed ``object`` by the module's ``__getattr__``."""
    import lcchain

    tree = ast.parse((PACKAGE / "__init__.py").read_text())
    typed: dict[str, str] = {}
    for node in ast.walk(tree):
        if isinstance(node, ast.If) and isinstance(node.test, ast.Name) and node.test.id == "TYPE_CHECKING":
            for statement in node.body:
                if isinstance(statement, ast.ImportFrom) and statement.level == 1 and statement.module:
                    typed.update({alias.asname or alias.name: statement.module for alias in statement.names})
    typed.pop("plots")  # lcchain.plots: a module of its own, loaded by __getattr__'s first branch
    assert typed == lcchain._PUBLIC
