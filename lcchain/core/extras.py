"""Optional extras, imported on first use: a result's ``to_xarray`` needs xarray, a table pandas.

``import lcchain`` never imports them; a method that needs one imports it by name here, and a missing one is an
:class:`~lcchain.core.errors.ExtraMissingError` naming the extra that installs it (exit status 2 on the command
line), not an ``ImportError`` traceback.
"""

from __future__ import annotations

import importlib
import math
from collections.abc import Mapping
from types import ModuleType

from .errors import ExtraMissingError

__all__ = ["optional_module", "dataset_attrs"]


def optional_module(module: str, extra: str = "data",
                    purpose: str = "a result as a table (pandas, xarray)") -> ModuleType:
    """The module ``module`` of the optional extra ``extra``, or an :class:`ExtraMissingError` saying how to install
    it (``purpose``: what needs it, in a few words)."""
    try:
        return importlib.import_module(module)
    except ImportError:
        raise ExtraMissingError(module, extra, purpose) from None


def dataset_attrs(values: Mapping[str, object]) -> dict[str, str | int | float]:
    """The scalar entries of ``values`` as a Dataset's attributes a netCDF file can hold: strings and finite
    numbers as they are, booleans as "true"/"false"; None, NaN, lists and mappings left out (they are variables,
    or :meth:`to_dict`'s)."""
    attrs: dict[str, str | int | float] = {}
    for name, value in values.items():
        if isinstance(value, bool):
            attrs[name] = "true" if value else "false"
        elif isinstance(value, int | str):
            attrs[name] = value
        elif isinstance(value, float) and math.isfinite(value):
            attrs[name] = value
    return attrs
