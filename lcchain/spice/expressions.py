"""``.param`` cards and ``{...}`` expressions of a netlist lcchain did not write: numbers and arithmetic only.

ngspice evaluates an expression in braces (``R1 a b {2*rv}``) and the right-hand side of a ``.param``
(``.param rv = 1k``, ``.param cv = {rv*1n}``) with its numparam library, which also knows functions that read
files (``table``, ``file``...), strings in quotes and ``$`` variables.  So an expression is read here against a
grammar of what it may hold (:func:`check_expression`), never against a list of dangers: SPICE numbers
(``1k``, ``2.5e-3``, ``10meg``), the names the netlist's ``.param`` cards define, the math functions of
:data:`FUNCTIONS`, the constant ``pi``, parentheses, commas, the arithmetic operators ``+ - * / % ^ **`` and the
comparisons and ternary ``< > <= >= == != && || ! ? :``.  Nothing else: no quote, ``$``, backtick, path, brace
inside braces or unknown name.

ngspice 39 reads any dot-command that starts with ``.param`` as one (``.params``, ``.PARAM``, ``.param_x``:
checked), while ``.par`` and ``.para`` stop it with a fatal error; :func:`is_param_card` mirrors that, and a
``.param``-like word is checked by the same grammar.
"""

from __future__ import annotations

import math
import re
from collections.abc import Callable, Iterable, Mapping
from typing import TypeAlias

from ..core.errors import ParameterError
from .text import dot_cards, spice_number

__all__ = ["FUNCTIONS", "MAX_PARAMS", "MAX_EXPRESSION_CHARS", "MAX_FUNCTION_DEPTH", "UserFunctions", "is_param_card",
           "param_assignments", "check_expression", "braced_expressions", "evaluate_expression", "param_values"]

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
                    r"|(?P<op>\*\*|<=|>=|==|!=|&&|\|\||[-+*/%^(),<>!?:]))")
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


def parameter_names(netlist: str) -> frozenset[str]:
    """The names a netlist's ``.param`` cards and ``.subckt ... params:`` define, lower case (read loosely: each
    ``name =`` of those cards): what ngspice may read where an element's value is a bare word."""
    names: set[str] = set()
    for _, _, line in dot_cards(netlist, canonical=False):
        word = line.split(None, 1)[0].lower() if line.strip() else ""
        if is_param_card(word) or word == ".subckt":
            names.update(name.lower() for name in _DEFINED.findall(line))
    return frozenset(names)


_DEFINED = re.compile(r"([A-Za-z_][A-Za-z0-9_]*)\s*=")


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


def _power(x: float, y: float) -> float:
    return float(x ** y) if x >= 0 or float(y).is_integer() else math.nan


# The functions of FUNCTIONS as ngspice 39's numparam computes them (log is the natural logarithm).
_FUNCTION_VALUES: dict[str, Callable[..., float]] = {
    "abs": abs, "sqrt": math.sqrt, "exp": math.exp, "ln": math.log, "log": math.log, "log10": math.log10,
    "sin": math.sin, "cos": math.cos, "tan": math.tan, "asin": math.asin, "acos": math.acos, "atan": math.atan,
    "sinh": math.sinh, "cosh": math.cosh, "tanh": math.tanh, "asinh": math.asinh, "acosh": math.acosh,
    "atanh": math.atanh, "min": min, "max": max, "pow": _power, "pwr": lambda x, y: math.copysign(abs(x) ** y, x),
    "floor": math.floor, "ceil": math.ceil, "sgn": lambda x: float((x > 0) - (x < 0)), "int": math.trunc,
    "nint": round, "u": lambda x: 1.0 if x > 0 else 0.0, "uramp": lambda x: x if x > 0 else 0.0,
}
# Binary operators by precedence, loosest first (the ternary ? : is looser still).
_BINARY: tuple[dict[str, Callable[[float, float], float]], ...] = (
    {"||": lambda a, b: float(bool(a) or bool(b))},
    {"&&": lambda a, b: float(bool(a) and bool(b))},
    {"==": lambda a, b: float(a == b), "!=": lambda a, b: float(a != b), "<": lambda a, b: float(a < b),
     ">": lambda a, b: float(a > b), "<=": lambda a, b: float(a <= b), ">=": lambda a, b: float(a >= b)},
    {"+": lambda a, b: a + b, "-": lambda a, b: a - b},
    # % as ngspice 39 reads it: C's fmod, the sign of the dividend (-7 % 3 is -1, 7.5 % 2 is 1.5), with * and /
    {"*": lambda a, b: a * b, "/": lambda a, b: a / b, "%": math.fmod},
)


#: A netlist's user functions (``.func`` cards): name (lower case) -> (argument names, lower case; the body's
#: expression text).
UserFunctions: TypeAlias = Mapping[str, tuple[tuple[str, ...], str]]
#: How deep user functions may call one another in one evaluation (ngspice 39 crashes on a function that calls
#: itself; the allow-list bounds how far their bodies grow, :data:`lcchain.spice.cards.MAX_FUNCTION_CHARS`).
MAX_FUNCTION_DEPTH = 32


def _tokens(text: str) -> list[tuple[str, str]]:
    """``text``'s tokens (kind, text); a ValueError where something is no token of the grammar."""
    tokens: list[tuple[str, str]] = []
    position = 0
    while text[position:].strip():
        match = _TOKEN.match(text, position)
        if match is None:
            raise ValueError(f"not an expression: {text.strip()[:80]!r}")
        kind = match.lastgroup or ""
        tokens.append((kind, match.group(kind)))
        position = match.end()
    return tokens


class _Evaluator:
    """A recursive-descent reading of the grammar :func:`check_expression` admits; a call of a user function
    evaluates its body with its arguments bound (over the names of the expression that calls it)."""

    def __init__(self, tokens: list[tuple[str, str]], value: Callable[[str], float],
                 functions: UserFunctions | None = None, depth: int = 0):
        self.tokens, self.value, self.k = tokens, value, 0
        self.functions, self.depth = functions or {}, depth

    def call(self, name: str, arguments: list[float]) -> float:
        """A function's value: one of :data:`FUNCTIONS`, else a user function's body."""
        if name in _FUNCTION_VALUES:
            return float(_FUNCTION_VALUES[name](*arguments))
        if name not in self.functions:
            raise ValueError(f"no function {name!r}")
        names, body = self.functions[name]
        if len(arguments) != len(names):
            raise ValueError(f"{name} takes {len(names)} argument{'s' if len(names) != 1 else ''}, not "
                             f"{len(arguments)}")
        if self.depth >= MAX_FUNCTION_DEPTH:
            raise ValueError(f"user functions calling one another more than {MAX_FUNCTION_DEPTH} deep")
        bound = dict(zip(names, arguments, strict=True))
        outer = self.value
        inner = _Evaluator(_tokens(body), lambda n: bound[n] if n in bound else outer(n), self.functions,
                           self.depth + 1)
        value = inner.ternary()
        if inner.k != len(inner.tokens):
            raise ValueError(f"trailing text in the body of {name}")
        return value

    def peek(self) -> str:
        return self.tokens[self.k][1] if self.k < len(self.tokens) else ""

    def take(self, expected: str | None = None) -> tuple[str, str]:
        if self.k >= len(self.tokens) or (expected is not None and self.tokens[self.k][1] != expected):
            raise ValueError(f"expected {expected or 'more'}")
        self.k += 1
        return self.tokens[self.k - 1]

    def ternary(self) -> float:
        condition = self.binary(0)
        if self.peek() != "?":
            return condition
        self.take("?")
        yes = self.ternary()
        self.take(":")
        no = self.ternary()
        return yes if condition else no

    def binary(self, level: int) -> float:
        if level == len(_BINARY):
            return self.unary()
        left = self.binary(level + 1)
        while self.peek() in _BINARY[level]:
            operator = self.take()[1]
            left = _BINARY[level][operator](left, self.binary(level + 1))
        return left

    def unary(self) -> float:
        return self.signed(self.power)

    def signed(self, operand: Callable[[], float]) -> float:
        """``operand()`` after any signs (- + !) before it."""
        if self.peek() in ("-", "+", "!"):
            operator = self.take()[1]
            value = self.signed(operand)
            return -value if operator == "-" else float(not value) if operator == "!" else value
        return operand()

    def power(self) -> float:
        # left-associative as ngspice 39 reads it (2^3^2 is 64), binding tighter than a unary minus on its left
        value = self.atom()
        while self.peek() in ("^", "**"):
            self.take()
            value = _power(value, self.signed(self.atom))  # its exponent's own signs: 2^-1
        return value

    def atom(self) -> float:
        kind, text = self.take()
        if kind == "number":
            number = spice_number(text)
            if number is None:
                raise ValueError(f"not a number: {text}")
            return number
        if kind == "name" and self.peek() == "(":
            self.take("(")
            arguments = [] if self.peek() == ")" else [self.ternary()]  # a .func of no argument: rval()
            while self.peek() == ",":
                self.take(",")
                arguments.append(self.ternary())
            self.take(")")
            return self.call(text.lower(), arguments)
        if kind == "name":
            return math.pi if text.lower() == "pi" else self.value(text.lower())
        if text == "(":
            inner = self.ternary()
            self.take(")")
            return inner
        raise ValueError(f"unexpected {text!r}")


def _reader(values: Mapping[str, float]) -> Callable[[str], float]:
    """A name's value from ``values``; a ValueError for a name it lacks (one a user function's body uses)."""
    def read(name: str) -> float:
        if name not in values:
            raise ValueError(f"no .param defines {name!r}")
        return values[name]
    return read


def evaluate_expression(text: str, values: Mapping[str, float] | Callable[[str], float], where: str = "netlist",
                        line: str = "", functions: UserFunctions | None = None) -> float:
    """The value of an expression :func:`check_expression` admits, its names read from ``values`` (lower case),
    the netlist's user ``functions`` called as ngspice 39 calls them (each argument bound over the caller's names).

    Raises a :class:`ParameterError` naming ``where`` for an expression that does not read as a number (an
    unknown name, a division by zero, a function outside its domain, a result that is not finite)."""
    names = set(values) if isinstance(values, Mapping) else None
    calls: set[str] | None = set() if functions else None
    check_expression(text, names, where, line or text, calls=calls)
    unknown = sorted((calls or set()) - set(functions or {}))
    if unknown:
        raise ParameterError(where, (line or text).strip()[:200], f"{_ALLOWED_EXPRESSION} or a .func, not the "
                             f"function {unknown[0]!r}")
    look = _reader(values) if isinstance(values, Mapping) else values
    try:
        reader = _Evaluator(_tokens(text), look, functions)
        result = reader.ternary()
        if reader.k != len(reader.tokens):
            raise ValueError("trailing text")
        result = float(result)
    except (ArithmeticError, ValueError, TypeError) as error:
        raise ParameterError(where, (line or text).strip()[:200], f"an expression with a finite value ({error})") \
            from None
    if not math.isfinite(result):
        raise ParameterError(where, (line or text).strip()[:200], "an expression with a finite value")
    return result


def param_values(definitions: Mapping[str, tuple[str, str, str]], given: Mapping[str, float] | None = None,
                 outer: Mapping[str, float] | None = None, functions: UserFunctions | None = None
                 ) -> dict[str, float]:
    """Every ``.param`` name's value: ``definitions`` maps a name (lower case) to (expression, where, line), and a
    name may use others defined before or after it (as ngspice reads them); a cycle is refused, naming it.

    A sub-circuit's scope: ``given`` values win over the definitions of the same names (an instance's parameters
    over the ``.subckt`` card's defaults), and a name neither defines is read from ``outer`` (the netlist's own
    ``.param`` values).  Returns the given and defined names' values."""
    found: dict[str, float] = dict(given or {})
    busy: list[str] = []

    def value(name: str) -> float:
        if name in found:
            return found[name]
        if name not in definitions:
            if outer is not None and name in outer:
                return outer[name]
            raise ValueError(f"no .param defines {name!r}")
        expression, where, line = definitions[name]
        if name in busy:
            raise ParameterError(where, line.strip()[:200], f".param values that do not depend on themselves "
                                 f"({' -> '.join(busy + [name])})")
        busy.append(name)
        found[name] = evaluate_expression(expression, value, where, line, functions)
        busy.pop()
        return found[name]

    for name in definitions:
        value(name)
    return found
