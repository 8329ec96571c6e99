"""Exceptions raised by lcchain.

Every user mistake raises :class:`ParameterError`, whose message names the
field, the offending value and the allowed range, so that the command line can
print it as one line (exit status 2) instead of a traceback.

Every error keeps its fields as attributes and pickles: ``__reduce__`` returns
the class and its constructor arguments (as pint's errors do), so an error
raised in a worker process or on a Dask worker reaches the user as itself.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from .frozen import Reduced

__all__ = [
    "LcchainError",
    "ParameterError",
    "SimulationError",
    "SimulatorMissingError",
    "ExtraMissingError",
    "DesignError",
    "Interrupted",
    "clipped",
]


class LcchainError(Exception):
    """Base class of every error lcchain raises on purpose."""


class ParameterError(LcchainError, ValueError):
    """A parameter is out of its allowed range.

    Parameters
    ----------
    field : str
        Name of the parameter, as the user wrote it (``"N"``, ``"masses[2]"``,
        ``"--dt"``, ``"analysis.dt"``).
    value : object
        The rejected value.
    allowed : str
        The allowed range, in words (``"an integer >= 3"``).
    where : str, optional
        Where the value came from (a file name), prefixed to the message.
    """

    def __init__(self, field: str, value: object, allowed: str, where: str | None = None):
        self.field = field
        self.value = value
        self.allowed = allowed
        self.where = where
        prefix = f"{where}: " if where else ""
        super().__init__(f"{prefix}{field} = {show_value(value)} is not allowed: expected {allowed}")

    def __reduce__(self) -> Reduced:
        return (type(self), (self.field, self.value, self.allowed, self.where))

    def located(self, where: str | None) -> ParameterError:
        """The same error with ``where`` (a file) set, unless it already has one."""
        if self.where is not None or where is None:
            return self
        return type(self)(self.field, self.value, self.allowed, where)

    def renamed(self, field: str) -> ParameterError:
        """The same error under the name the user typed (``"--L0"`` for ``"L0"``)."""
        return type(self)(field, self.value, self.allowed, self.where)


class SimulationError(LcchainError):
    """The simulator (ngspice, or another engine) ran but did not produce a valid result.

    Parameters
    ----------
    reason : str
        What went wrong, in one line where possible (the simulator's own words).
    log_tail : str
        The useful end of the simulator's output ("" when it printed nothing useful).
    status : {"failed", "timeout"}
        ``"timeout"`` when the simulator was killed for running too long.
    engine : str
        Which simulator said it (``"ngspice"`` by default).
    """

    def __init__(self, reason: str, log_tail: str = "", status: str = "failed", engine: str = "ngspice"):
        self.reason = reason
        self.log_tail = log_tail
        self.status = status
        self.engine = engine
        said = f"\n{engine} said:\n{log_tail}" if log_tail else ""
        super().__init__(f"{reason}{said}")

    def __reduce__(self) -> Reduced:
        return (type(self), (self.reason, self.log_tail, self.status, self.engine))


class SimulatorMissingError(LcchainError):
    """ngspice (or its shared library, or PySpice) cannot be found on this machine."""


class ExtraMissingError(LcchainError):
    """An optional extra of lcchain is not installed (pandas, xarray, Dask, PySpice): exit status 2 naming the
    extra, not 3 (the simulator).

    Parameters
    ----------
    module : str
        The missing importable package (``"pandas"``).
    extra : str
        The extra of lcchain that installs it (``"data"``): ``pip install 'lcchain[data]'``.
    purpose : str
        What needs it, in a few words (``"Store.to_dataframe"``, ``"the dask executor"``).
    more : tuple of str
        Packages the extra does not hold, installed beside it (``("pyarrow",)`` for ``--parquet``).
    """

    def __init__(self, module: str, extra: str, purpose: str = "this", more: tuple[str, ...] = ()):
        self.module = module
        self.extra = extra
        self.purpose = purpose
        self.more = tuple(more)
        super().__init__(f"{purpose} needs {module}, which is not installed (an optional extra of lcchain); "
                         f"install it with: {self.command}")

    @property
    def command(self) -> str:
        """The command that installs it."""
        return " ".join([f"pip install 'lcchain[{self.extra}]'", *self.more])

    def __reduce__(self) -> Reduced:
        return (type(self), (self.module, self.extra, self.purpose, self.more))


class DesignError(LcchainError):
    """A design that was asked for correctly but cannot be computed in float64 (its values would overflow)."""


class Interrupted(BaseException):
    """The process received SIGTERM or SIGHUP (SIGINT stays KeyboardInterrupt).

    A BaseException, like KeyboardInterrupt, so that ``except Exception`` blocks
    never swallow it and every ``finally`` (killing ngspice, removing files)
    runs on the way out.

    Parameters
    ----------
    signum : int
        The signal number.
    """

    def __init__(self, signum: int):
        self.signum = signum
        super().__init__(f"signal {signum}")

    def __reduce__(self) -> Reduced:
        return (type(self), (self.signum,))


#: Longest repr an error message shows whole; a path (a string with a ``/``) may be longer, up to _MAX_PATH: a
#: path cut in the middle names no file (a store's path in a test's folder under xdist ran past 80).
_MAX_SHOWN, _MAX_PATH = 80, 400


def show_value(value: object) -> str:
    """A value as an error message shows it: repr, cut to 80 characters (a path to 400)."""
    if isinstance(value, float):
        return repr(value)
    text = repr(value)
    path = isinstance(value, str) or hasattr(value, "__fspath__")
    most = _MAX_PATH if path and "/" in str(value) and "\n" not in str(value) else _MAX_SHOWN
    return clipped(text, most)


def clipped(text: str, most: int) -> str:
    """``text`` cut to ``most`` characters, ``...`` ending what was cut."""
    return text if len(text) <= most else text[:most - 3] + "..."
