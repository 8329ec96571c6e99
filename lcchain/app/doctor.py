"""``lcchain doctor`` as a function: whether ngspice, its shared library and PySpice are there."""

from __future__ import annotations

from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from ..spice.doctor import Check

__all__ = ["doctor"]


def doctor() -> list[Check]:
    """Each check (:class:`lcchain.spice.doctor.Check`: name, ok, required, detail, fix), in order."""
    from ..spice.doctor import doctor as checks

    return list(checks())
