"""Argument checks, written once for every module (as scipy's ``_ivp/common.py``).

Each check returns the value in its canonical type or raises
:class:`~lcchain.core.errors.ParameterError` naming the field, the value and
the allowed range.  Numbers are numbers: Python and numpy ints and floats
pass; booleans, strings and None do not (``"1.5"`` is not 1.5 and ``True`` is
not 1).  Every real number must be finite.
"""

from __future__ import annotations

import math
import numbers
import re
from collections.abc import Callable, Mapping, Sequence
from typing import TYPE_CHECKING, Literal, SupportsFloat, SupportsIndex, SupportsInt, TypeVar, cast, overload

from .errors import ParameterError
from .frozen import is_array
from .limits import MAX_PULSE_WIDTH, MAX_TITLE_BYTES, MIN_PULSE_WIDTH

if TYPE_CHECKING:
    import numpy as np
    import numpy.typing as npt

#: A dot followed by a letter at the start of a line: ngspice may read it as a command.
# A title ngspice would read as a command: a dot-command, "*#" (a command line), or "*ng_script", which makes
# the whole file a script (the same rule as lcchain.spice.foreign's for a netlist's first line).
#: A choice from a set of allowed strings (a Literal alias).
_Option = TypeVar("_Option", bound=str)
#: The class an :func:`instance` check asks for.
_Instance = TypeVar("_Instance")

_DOT_COMMAND = re.compile(r"^\s*(\.[A-Za-z]|\*\s*(#|ng_script))", re.IGNORECASE)

__all__ = [
    "is_number",
    "is_integer",
    "real",
    "integer",
    "choice",
    "text_line",
    "numbers_list",
    "instance",
    "callback",
    "strings",
    "time_array",
    "pulse",
]


def is_number(value: object) -> bool:
    """A real number (int, float, numpy scalar), not a boolean (numpy's booleans are no ``numbers.Real``)."""
    return isinstance(value, numbers.Real) and not isinstance(value, bool)


def is_integer(value: object) -> bool:
    """An integer (int, numpy integer), not a boolean (numpy's booleans are no ``numbers.Integral``)."""
    return isinstance(value, numbers.Integral) and not isinstance(value, bool)


def _range_text(what: str, above: float | None, at_least: float | None, below: float | None,
                at_most: float | None) -> str:
    def fmt(x: float) -> str:
        return f"{x:g}"

    low = f"> {fmt(above)}" if above is not None else (f">= {fmt(at_least)}" if at_least is not None else "")
    high = f"< {fmt(below)}" if below is not None else (f"<= {fmt(at_most)}" if at_most is not None else "")
    if low and high:
        lo_sym = "<" if above is not None else "<="
        hi_sym = "<" if below is not None else "<="
        lo_val = fmt(above if above is not None else at_least)  # type: ignore[arg-type]
        hi_val = fmt(below if below is not None else at_most)  # type: ignore[arg-type]
        return f"{what}, {lo_val} {lo_sym} x {hi_sym} {hi_val}"
    return f"{what} {low or high}".strip()


def real(name: str, value: object, *, above: float | None = None, at_least: float | None = None,
         below: float | None = None, at_most: float | None = None, unit: str = "",
         allowed: str | None = None) -> float:
    """A finite real number within the given bounds, as a float.

    Parameters
    ----------
    name : str
        The field, as the user knows it.
    value : object
        What was given.
    above, at_least, below, at_most : float, optional
        Open (above, below) or closed (at_least, at_most) bounds.
    unit : str
        Appended to the message, e.g. ``"henry"``.
    allowed : str, optional
        The whole allowed-range text, replacing the generated one.
    """
    text = allowed or _range_text("a finite number", above, at_least, below, at_most) + (
        f" ({unit})" if unit else "")
    if not is_number(value):
        raise ParameterError(name, value, text)
    try:
        number = float(value)  # type: ignore[arg-type]
    except OverflowError:
        raise ParameterError(name, value, text) from None
    if not math.isfinite(number):
        raise ParameterError(name, value, text)
    if ((above is not None and not number > above) or (at_least is not None and not number >= at_least)
            or (below is not None and not number < below) or (at_most is not None and not number <= at_most)):
        raise ParameterError(name, value, text)
    return number


def integer(name: str, value: object, *, at_least: int | None = None, at_most: int | None = None,
            allowed: str | None = None) -> int:
    """An integer (not a float, not a boolean) within the given bounds, as an int."""
    if allowed is None:
        if at_least is not None and at_most is not None:
            allowed = f"an integer from {at_least} to {at_most}"
        elif at_least is not None:
            allowed = f"an integer >= {at_least}"
        elif at_most is not None:
            allowed = f"an integer <= {at_most}"
        else:
            allowed = "an integer"
    if not is_integer(value):
        raise ParameterError(name, value, allowed)
    number: int = int(value)  # type: ignore[call-overload]
    if (at_least is not None and number < at_least) or (at_most is not None and number > at_most):
        raise ParameterError(name, value, allowed)
    return number


def choice(name: str, value: object, options: Sequence[_Option], note: str = "") -> _Option:
    """One of the allowed strings, typed as the option set (a ``Literal`` alias's tuple gives that Literal)."""
    if not isinstance(value, str) or value not in options:
        raise ParameterError(name, value, " | ".join(options) + note)
    return cast(_Option, value)


def text_line(name: str, value: object, max_length: int, *, title: bool = False) -> str:
    """One printable line: what a user may put in a netlist's title or a ``*`` comment.

    Measured with ngspice 39: a comment line executes nothing, and neither does
    a title such as "shell model of a chain" or ".5 uH ladder"; but a title line
    that starts with a dot-command (``.include``, ``.lib``, ``.param``,
    ``.control``, ``.endc``, ``.title``) is read as that command, and a first
    line that starts with ``*ng_script`` makes the whole file a script.  So a line
    may not break (newline, carriage return or any other control character
    would start a new netlist line), and a title may not start with a dot
    followed by a letter.
    """
    allowed = (f"one line of at most {max_length} printable characters (a newline or control character "
               "would start a new netlist line that ngspice could execute)")
    if not isinstance(value, str):
        raise ParameterError(name, value, allowed)
    if len(value) > max_length or any(ord(ch) < 32 or 127 <= ord(ch) < 160 or ch in "\u2028\u2029\ufeff"
                                       for ch in value):
        raise ParameterError(name, value, allowed)
    if title and len(value.encode("utf-8")) > MAX_TITLE_BYTES:
        raise ParameterError(name, value, f"a title of at most {MAX_TITLE_BYTES} bytes in UTF-8 (this one has "
                             f"{len(value.encode('utf-8'))}: ngspice 39 reads the title into a fixed buffer)")
    if title and _DOT_COMMAND.match(value):
        raise ParameterError(name, value, "a title that does not start with a dot-command such as .include or "
                             ".control, nor with *# or *ng_script (ngspice reads those on the title line)")
    return value


def pulse(excitation: object, value: object, kinds: Sequence[str], shapes: Sequence[str]) -> tuple[str, float] | None:
    """The (shape, width) of a pulse, given exactly when the excitation is ``"pulse"`` (else None).

    Parameters
    ----------
    excitation : str
        One of ``kinds``.
    value : (shape, width) or None
        ``shape`` one of ``shapes``; ``width`` in units of sqrt(L0*C0), from
        :data:`~lcchain.core.limits.MIN_PULSE_WIDTH` to :data:`~lcchain.core.limits.MAX_PULSE_WIDTH`.
    """
    choice("excitation", excitation, kinds)
    if (excitation == "pulse") != (value is not None):
        raise ParameterError("pulse", value, "(shape, width) exactly when excitation is 'pulse'")
    if value is None:
        return None
    if not isinstance(value, (tuple, list)) or len(value) != 2:
        raise ParameterError("pulse", value, "(shape, width)")
    return choice("pulse shape", value[0], shapes), real("pulse width", value[1], at_least=MIN_PULSE_WIDTH,
                                                          at_most=MAX_PULSE_WIDTH, unit="units of sqrt(L0*C0)")


def numbers_list(name: str, values: object, allowed: str) -> tuple[SupportsFloat, ...]:
    """A list or tuple (or 1-d numpy array) of real numbers, as given (unconverted, unchecked for range)."""
    if is_array(values):
        if values.ndim != 1:
            raise ParameterError(name, f"an array of shape {values.shape}", allowed)
        values = values.tolist()
    if isinstance(values, (str, bytes, Mapping)) or not isinstance(values, Sequence):
        raise ParameterError(name, values, allowed)
    for i, value in enumerate(values):
        if not is_number(value):
            raise ParameterError(f"{name}[{i}]", value, "a number")
    # every value is a numbers.Real (checked just above), and a numbers.Real has __float__
    return cast(tuple[SupportsFloat, ...], tuple(values))


@overload
def instance(name: str, value: object, cls: type[_Instance], optional: Literal[False] = False) -> _Instance: ...
@overload
def instance(name: str, value: object, cls: type[_Instance], optional: Literal[True]) -> _Instance | None: ...
@overload
def instance(name: str, value: object, cls: tuple[type, ...], optional: bool = False) -> object: ...
def instance(name: str, value: object, cls: type | tuple[type, ...], optional: bool = False) -> object:
    """``value`` itself if it is an instance of ``cls`` (one class or a tuple of them; or None when optional)."""
    if (value is None and optional) or isinstance(value, cls):
        return value
    names = " or ".join(c.__name__ for c in (cls if isinstance(cls, tuple) else (cls,)))
    raise ParameterError(name, type(value).__name__, f"a {names}" + (" or None" if optional else ""))


def callback(name: str, value: object) -> Callable[..., object] | None:
    """A function to call (a progress report, say), or None."""
    if value is None or callable(value):
        return value
    raise ParameterError(name, type(value).__name__, "a function or None")


def strings(name: str, values: object, allowed: str = "a list or tuple of strings") -> tuple[str, ...]:
    """A list or tuple of strings (not one string, which would be read letter by letter), as a tuple."""
    if isinstance(values, (str, bytes, Mapping)) or not isinstance(values, Sequence):
        raise ParameterError(name, values, allowed)
    for i, value in enumerate(values):
        if not isinstance(value, str):
            raise ParameterError(f"{name}[{i}]", value, "a string")
    return tuple(values)


def time_array(name: str, t: npt.ArrayLike) -> np.ndarray:
    """A one-dimensional array of finite times >= 0 (units of sqrt(L0*C0))."""
    import numpy as np  # here, not at the top: a command that checks no times (a batch) starts without numpy

    if type(t) is np.ndarray and t.dtype == np.float64 and t.ndim == 1 and bool(np.isfinite(t).all()) \
            and bool((t >= 0).all()):
        return t  # what the checks below return for it (a peak search asks some 40 times, one time a call)
    allowed = "an array of finite times >= 0 (units of sqrt(L0*C0))"
    if isinstance(t, (str, bytes)) or (np.ndim(t) == 0 and not is_number(t)):
        raise ParameterError(name, t, allowed)
    try:
        times = np.asarray(t, dtype=float)
    except (TypeError, ValueError):
        raise ParameterError(name, t, allowed) from None
    if times.ndim > 1:
        raise ParameterError(name, f"an array of shape {times.shape}", "a one-dimensional array of times")
    times = np.atleast_1d(times)
    bad = np.flatnonzero(~(np.isfinite(times) & (times >= 0)))
    if bad.size:
        raise ParameterError(f"{name}[{bad[0]}]", float(times[bad[0]]), allowed)
    return times


def as_float(value: object) -> float:
    """``float(value)`` of a value read from a document or an object by name: float's own TypeError for what it
    cannot convert (a checked conversion, where the value's type is not known)."""
    if isinstance(value, (str, bytes, bytearray, SupportsFloat, SupportsIndex)):
        return float(value)
    raise TypeError(f"float() argument must be a string or a real number, not '{type(value).__name__}'")


def as_int(value: object) -> int:
    """``int(value)`` of a value read from a document or an object by name: int's own TypeError for what it
    cannot convert."""
    if isinstance(value, (str, bytes, bytearray, SupportsInt, SupportsIndex)):
        return int(value)
    raise TypeError(f"int() argument must be a string, a bytes-like object or a real number, not "
                    f"'{type(value).__name__}'")
