"""Exceptions raised by lcchain.

Every user mistake raises :class:`ParameterError`, whose message names the
field, the offending value and the allowed range, so that the command line can
print it as one line (exit status 2) instead of a traceback.
"""

from __future__ import annotations

__all__ = [
    "LcchainError",
    "ParameterError",
    "SimulationError",
    "SimulatorMissingError",
]


class LcchainError(Exception):
    """Base class of every error lcchain raises on purpose."""


class ParameterError(LcchainError, ValueError):
    """A parameter is out of its allowed range.

    Parameters
    ----------
    field : str
        Name of the parameter, as the user wrote it (``"N"``, ``"masses[2]"``).
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
        super().__init__(f"{prefix}{field} = {_show(value)} is not allowed: expected {allowed}")


class SimulationError(LcchainError):
    """ngspice ran but did not produce a valid result (the message says why)."""


class SimulatorMissingError(LcchainError):
    """ngspice (or its shared library) cannot be found on this machine."""


def _show(value: object) -> str:
    if isinstance(value, float):
        return repr(value)
    text = repr(value)
    return text if len(text) <= 80 else text[:77] + "..."
