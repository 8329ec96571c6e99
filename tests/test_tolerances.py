"""Every tolerance of the tests is named in tests/helpers/tolerances.py (issue 34, item 6; STYLE.md, "Tests").

A tolerance written as a number where it is used says nothing of why it is that number, and the next one who
loosens it cannot see what else rests on it.  These tests read every test file's syntax tree (nothing is
imported or run) and point at the file and line of a tolerance written inline.

What they catch:

* a keyword argument ``rtol``, ``atol``, ``abs`` or ``rel`` (pytest.approx, numpy's isclose / allclose /
  assert_allclose, scipy's solve_ivp) given a number, written any way Python allows (``1e-9``, ``-1e-9``,
  ``1.5e-3``, ``0.01``, ``5``), or a sum or product with a float literal below 1 (``0.35 * dt**2``,
  ``2e-3 * values.max()``).  Zero is allowed: ``rtol=0`` or ``atol=0`` switches that kind of tolerance off, it
  is not a tolerance;
* an ``assert`` bounding an error from above by a number: the smaller side of ``<``, ``<=`` (or the larger of
  ``>``, ``>=``) holds ``abs(...)`` / ``np.abs(...)`` or a name containing "error", and the other side is a
  float literal between 0 and 1, or a sum or product with one (``< 1e-12``, ``< 1e-11 * I0``,
  ``< 1e-3 + 0.01 * abs(x)``, ``<= 1.0 + 1e-9``).

What they do not catch (read the test, or name it anyway): an integer factor on a named tolerance
(``abs=2 * JUMP_XTOL``); an upper bound on a quantity not written as an error (``assert four.delta < 1e-12``,
``t[-1] <= T * (1 + 1e-9)``); lower bounds (``> 0.1`` for "a signal arrives", ``>= 0.5 * accuracy``); literals
of 1 or more and integers (``errors[0] / errors[1] < 13.0``, ``< 10 * eps``); powers (``c * h**6``); positional
tolerances (``np.isclose(a, b, 1e-9)``); and tolerances outside asserts and keywords (a generator picking a line
by ``< 1e-12``).  A literal that is an input of the test (the accuracy asked for, a part's tolerance, a signal's
amplitude) should be a named local variable, so that its check reads as such.
"""

from __future__ import annotations

import ast
from collections.abc import Callable, Iterator
from pathlib import Path

TESTS = Path(__file__).resolve().parent
TOLERANCES = TESTS / "helpers" / "tolerances.py"
KEYWORDS = frozenset({"rtol", "atol", "abs", "rel"})


def _test_files() -> list[Path]:
    return sorted(p for p in TESTS.rglob("*.py") if p != TOLERANCES and "__pycache__" not in p.parts)


def _number(node: ast.expr) -> int | float | None:
    """The value of a numeric literal, signed or not (``1e-9``, ``-1e-9``, ``+0.5``), else None."""
    negative = False
    while isinstance(node, ast.UnaryOp) and isinstance(node.op, ast.USub | ast.UAdd):
        negative ^= isinstance(node.op, ast.USub)
        node = node.operand
    if isinstance(node, ast.Constant) and isinstance(node.value, int | float) and not isinstance(node.value, bool):
        return -node.value if negative else node.value
    return None


def inline_keyword_tolerances(tree: ast.AST) -> Iterator[tuple[int, str]]:
    """(line, text) of each rtol/atol/abs/rel keyword given a non-zero number, or a sum or product with one."""
    for node in ast.walk(tree):
        if isinstance(node, ast.Call):
            for keyword in node.keywords:
                if keyword.arg in KEYWORDS:
                    value = _number(keyword.value)
                    if (value is not None and value != 0) or (value is None and _literal_bound(keyword.value)):
                        yield keyword.value.lineno, f"{keyword.arg}={ast.unparse(keyword.value)}"


def _is_error(node: ast.expr) -> bool:
    """An expression that is an error: it takes an absolute value, or names something an error."""
    for sub in ast.walk(node):
        if isinstance(sub, ast.Call):
            func = sub.func
            name = func.id if isinstance(func, ast.Name) else func.attr if isinstance(func, ast.Attribute) else ""
            if name in ("abs", "absolute"):
                return True
        word = (sub.id if isinstance(sub, ast.Name) else sub.attr if isinstance(sub, ast.Attribute)
                else sub.value if isinstance(sub, ast.Constant) and isinstance(sub.value, str) else "")
        if "error" in word.lower():
            return True
    return False


def _literal_bound(node: ast.expr) -> bool:
    """A bound that is, or is a sum or product with, a float literal of size below 1 (not 0, not a power)."""
    value = _number(node)
    if value is not None:
        return isinstance(value, float) and 0 < abs(value) < 1
    if isinstance(node, ast.BinOp) and isinstance(node.op, ast.Add | ast.Sub | ast.Mult | ast.Div):
        return _literal_bound(node.left) or _literal_bound(node.right)
    return False


def inline_error_bounds(tree: ast.AST) -> Iterator[tuple[int, str]]:
    """(line, text) of each assert that compares an error with a literal bound."""
    for statement in ast.walk(tree):
        if not isinstance(statement, ast.Assert):
            continue
        for node in ast.walk(statement.test):
            if not isinstance(node, ast.Compare):
                continue
            sides = [node.left, *node.comparators]
            for op, left, right in zip(node.ops, sides[:-1], sides[1:], strict=True):
                if isinstance(op, ast.Lt | ast.LtE):
                    error, bound = left, right
                elif isinstance(op, ast.Gt | ast.GtE):
                    error, bound = right, left
                else:
                    continue
                if _is_error(error) and _literal_bound(bound):
                    yield bound.lineno, f"{ast.unparse(error)} <= {ast.unparse(bound)}"


def _found(find: Callable[[ast.AST], Iterator[tuple[int, str]]]) -> list[str]:
    found = []
    for path in _test_files():
        tree = ast.parse(path.read_text(encoding="utf-8"), filename=str(path))
        found += [f"{path.relative_to(TESTS.parent)}:{line}: {text}" for line, text in find(tree)]
    return found


def test_no_tolerance_keyword_is_a_number() -> None:
    found = _found(inline_keyword_tolerances)
    assert not found, "name these in tests/helpers/tolerances.py, with why:\n" + "\n".join(found)


def test_no_error_is_bounded_by_a_number() -> None:
    found = _found(inline_error_bounds)
    assert not found, "name these in tests/helpers/tolerances.py, with why:\n" + "\n".join(found)


def test_the_guards_see_what_they_are_for() -> None:
    """The guards find each form they promise to find, and pass what they promise to pass."""
    bad = ast.parse("pytest.approx(x, rel=1e-9)\nnp.isclose(a, b, atol=-1.5e-3)\nf(abs=+5)\n"
                    "pytest.approx(p, abs=0.35 * dt**2)\n"
                    "assert abs(a - b) < 1e-12\nassert np.max(np.abs(d)) <= 1e-11 * I0\n"
                    "assert r.max_abs_error < 2e-3\nassert 1e-3 + 0.01 * abs(t) > abs(a - t)\n")
    assert [line for line, _ in inline_keyword_tolerances(bad)] == [1, 2, 3, 4]
    assert sorted(line for line, _ in inline_error_bounds(bad)) == [5, 6, 7, 8]
    good = ast.parse("pytest.approx(x, rel=RTOL_X)\nnp.allclose(a, b, rtol=0, atol=ATOL_X)\nf(abs=0.0)\n"
                     "pytest.approx(q, abs=2 * JUMP_XTOL)\n"
                     "assert abs(a - b) < ATOL_X * I0\nassert abs(a - b) <= accuracy\n"
                     "assert n_errors < 3\nassert c4 * h**6 > np.max(np.abs(d))\nassert t < 0.5\n"
                     "assert np.max(np.abs(signal)) > 0.1\nassert abs(alpha) <= 1.0\n")
    assert list(inline_keyword_tolerances(good)) == [] and list(inline_error_bounds(good)) == []
