"""``.param`` cards and ``{...}`` expressions of a netlist lcchain did not write: numbers and arithmetic only.

ngspice evaluates an expression in braces (``R1 a b {2*rv}``) and the right-hand side of a ``.param``
(``.param rv = 1k``, ``.param cv = {rv*1n}``) with its numparam library, which also knows functions that read
files (``table``, ``file``...), strings in quotes and ``$`` variables.  So an expression is read here against a
grammar of what it may hold (:func:`check_expression`), never against a list of dangers: SPICE numbers
(``1k``, ``2.5e-3``, ``10meg``), the names the netlist's ``.param`` cards define, the math functions of
:data:`FUNCTIONS`, the constant ``pi``, parentheses, commas, the arithmetic operators ``+ - * / ^ **`` and the
comparisons and ternary ``< > <= >= == != && || ! ? :``.  Nothing else: no quote, ``$``, backtick, path, brace
inside braces or unknown name.

ngspice 39 reads any dot-command that starts with ``.param`` as one (``.params``, ``.PARAM``, ``.param_x``:
checked), while ``.par`` and ``.para`` stop it with a fatal error; :func:`is_param_card` mirrors that, and a
``.param``-like word is checked by the same grammar.
"""

from __future__ import annotations

import re
from collections.abc import Iterable

from ..core.errors import ParameterError

__all__ = ["FUNCTIONS", "MAX_PARAMS", "MAX_EXPRESSION_CHARS", "is_param_card", "param_assignments",
           "check_expression", "braced_expressions"]

#: The math functions an expression may call: ngspice's deterministic ones (no random draw, no table or file).
FUNCTIONS = frozenset({
    "abs", "sqrt", "exp", "ln", "log", "log10", "sin", "cos", "tan", "asin", "acos", "atan", "sinh", "cosh",
    "tanh", "asinh", "acosh", "atanh", "min", "max", "pow", "pwr", "floor", "ceil", "sgn", "int", "nint", "u",
    "uramp",
})
#: Constants an expression may name without a ``.param``.
CONSTANTS = frozenset({"pi"})
#: Most ``.param`` names a netlist (includes inlined) may define.
MAX_PARAMS = 1000
#: Longest expression (one brace group, or one ``.param`` right-hand side), characters.
MAX_EXPRESSION_CHARS = 500

# One token of an expression: a SPICE number (suffix and unit letters included), a name, an operator.
_TOKEN = re.compile(r"\s*(?:(?P<number>(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?[A-Za-z]*)"
                    r"|(?P<name>[A-Za-z_][A-Za-z0-9_]*)"
                    r"|(?P<op>\*\*|<=|>=|==|!=|&&|\|\||[-+*/^(),<>!?:]))")
_NAME = re.compile(r"[A-Za-z_][A-Za-z0-9_]*")
_PARAM_WORD = re.compile(r"\.param[A-Za-z0-9_]*", re.IGNORECASE)
# "name =" (not "==", "<=", ">=", "!=") where an assignment starts: at the start or after a space
_ASSIGNMENT = re.compile(r"(?:^|(?<=\s))([A-Za-z_][A-Za-z0-9_]*)\s*=(?!=)")
_BRACED = re.compile(r"\{([^{}]*)\}")


_ALLOWED_EXPRESSION = (f"an expression of at most {MAX_EXPRESSION_CHARS} characters of numbers, .param names, "
                       f"parentheses, operators and the functions {', '.join(sorted(FUNCTIONS))}")


def is_param_card(word: str) -> bool:
    """Whether ngspice 39 reads a card whose first word is ``word`` as a ``.param`` (any word that starts with
    ``.param``, in any case)."""
    return _PARAM_WORD.fullmatch(word) is not None


def check_expression(text: str, names: Iterable[str] | None, where: str, line: str, *,
                     calls: set[str] | None = None) -> set[str]:
    """Refuse an expression that holds anything but numbers, the given parameter names, :data:`FUNCTIONS`,
    ``pi`` and operators, or is longer than :data:`MAX_EXPRESSION_CHARS` (``where``: ``"<source>: line <n>"``).

    Returns the parameter names it uses (lower case); with ``names`` None any name passes here, and the caller
    checks the names returned once it knows every ``.param`` of the netlist.  With ``calls`` (a set), a call of
    a function not in :data:`FUNCTIONS` is added to it (lower case) instead of refused: the caller checks them
    against the netlist's ``.func`` cards once it has read them all."""
    known = None if names is None else {n.lower() for n in names}
    used: set[str] = set()
    allowed = _ALLOWED_EXPRESSION
    if len(text) > MAX_EXPRESSION_CHARS or not text.strip():
        raise ParameterError(where, line.strip()[:200], allowed)
    position, depth = 0, 0
    tokens: list[tuple[str, str]] = []
    while position < len(text):
        if not text[position:].strip():
            break
        match = _TOKEN.match(text, position)
        if match is None:
            bad = text[position:].lstrip()[:1]
            raise ParameterError(where, line.strip()[:200], f"{allowed}, not {bad!r}")
        kind = match.lastgroup or ""
        tokens.append((kind, match.group(kind)))
        position = match.end()
    for k, (kind, value) in enumerate(tokens):
        if kind == "name":
            word = value.lower()
            follows = tokens[k + 1][1] if k + 1 < len(tokens) else ""
            if follows == "(":
                if word not in FUNCTIONS and calls is not None:
                    calls.add(word)
                elif word not in FUNCTIONS:
                    raise ParameterError(where, line.strip()[:200], f"{allowed}, not the function {value!r}")
            elif word not in CONSTANTS:
                used.add(word)
            if follows != "(" and known is not None and word not in known and word not in CONSTANTS:
                raise ParameterError(where, line.strip()[:200], f"{allowed}, not the name {value!r} (a name "
                                     "must be defined by a .param card)")
        elif value == "(":
            depth += 1
        elif value == ")":
            depth -= 1
            if depth < 0:
                break
    if depth != 0:
        raise ParameterError(where, line.strip()[:200], f"{allowed}, with balanced parentheses")
    return used


def param_assignments(body: str, where: str, line: str) -> list[tuple[str, str]]:
    """(name, right-hand side) of a ``.param`` card's text after its first word, or a refusal: one or more
    ``name = value`` with plain names (no function definitions such as ``f(x) = ...``)."""
    starts = list(_ASSIGNMENT.finditer(body))
    allowed = ".param name = value [name = value ...] (a name of letters, digits and _; a value a number or an " \
              "expression)"
    if not starts or body[:starts[0].start()].strip():
        raise ParameterError(where, line.strip()[:200], allowed)
    found = []
    for k, match in enumerate(starts):
        end = starts[k + 1].start() if k + 1 < len(starts) else len(body)
        value = body[match.end():end].strip()
        if value.startswith("{") and value.endswith("}"):
            value = value[1:-1]
        if not value or "{" in value or "}" in value:
            raise ParameterError(where, line.strip()[:200], allowed)
        found.append((match.group(1).lower(), value))
    return found


def braced_expressions(text: str) -> tuple[list[str], str]:
    """The ``{...}`` groups of a card, and the card with each replaced by ``{}`` (unmatched braces are left)."""
    return _BRACED.findall(text), _BRACED.sub("{}", text)


def valid_name(name: str) -> bool:
    return _NAME.fullmatch(name) is not None
