"""The types of values that really are arbitrary JSON (a store's description, a report as written).

Where a value has a shape lcchain knows, it gets that type (a dataclass, a ``TypedDict``); these are for what is
read from, or written to, a JSON file as it is.

* :data:`JSON` is a JSON value as ``json.loads`` makes it (dicts and lists all the way down), and
  :data:`JSONObject` one of its objects;
* :data:`JSONValue` is a value ``json.dumps`` can write as lcchain makes them: any mapping or sequence of such
  values (a ``dict[str, float]`` is one, a tuple too), read-only, so that a ``dict[str, float]`` may be given
  where one is expected; :data:`JSONDict` is the dict a ``to_dict()`` returns.

:data:`LooseJSON` is ``Any`` under a name that says why: a document the command layer reads by key where it knows
the document's shape (a record's ``to_dict``, a command's ``--json``), the one place its types say Any;
:data:`LooseJSONObject` is one of its objects.  The others are checked: a value of them is narrowed
(``isinstance``) before it is used as a number or a table.
"""

from __future__ import annotations

import json
import math
from collections.abc import Mapping, Sequence
from typing import Any, TypeAlias

__all__ = ["JSON", "JSONObject", "JSONValue", "JSONDict", "LooseJSON", "LooseJSONObject", "json_text", "finite"]

#: A JSON value: an object, an array, a string, a number, a boolean or null.
JSON: TypeAlias = dict[str, "JSON"] | list["JSON"] | str | int | float | bool | None
#: A JSON object (the top of a report or a store's description).
JSONObject: TypeAlias = dict[str, JSON]
#: A value ``json.dumps`` writes as JSON, as lcchain makes them (mappings and sequences of such values).
JSONValue: TypeAlias = Mapping[str, "JSONValue"] | Sequence["JSONValue"] | str | int | float | bool | None
#: A JSON object as a ``to_dict()`` returns it.
JSONDict: TypeAlias = dict[str, JSONValue]
#: A JSON value read by key where the code knows the document's shape: ``Any``, named.
LooseJSON: TypeAlias = Any
#: A JSON object of :data:`LooseJSON` values.
LooseJSONObject: TypeAlias = dict[str, LooseJSON]


def json_text(data: object, indent: int | None = 2) -> str:
    """``data`` as valid JSON text: a number that is not finite (an error not compared, NaN; a mode unseen, an
    infinite error; a mean that overflows) is ``null``, as JSON has neither (``json.dumps`` alone writes ``NaN``
    and ``Infinity``, which JSON readers refuse)."""
    try:
        return json.dumps(data, indent=indent, allow_nan=False)
    except ValueError:  # a NaN or an infinity somewhere: those are null
        return json.dumps(finite(data), indent=indent, allow_nan=False)


def finite(data: object) -> object:
    """``data`` with each float that is not finite replaced by None, through dicts, lists and tuples."""
    if isinstance(data, float):
        return data if math.isfinite(data) else None
    if isinstance(data, dict):
        return {key: finite(value) for key, value in data.items()}
    if isinstance(data, list | tuple):
        return [finite(value) for value in data]
    return data
