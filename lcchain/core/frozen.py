"""Immutable values that stay immutable across pickling.

numpy does not keep ``writeable = False`` through a pickle round trip, and
``types.MappingProxyType`` cannot be pickled at all.  lcchain's frozen
dataclasses therefore hold arrays made by :func:`readonly` and mappings of
type :class:`FrozenMap`, and re-freeze their arrays when unpickled
(:class:`FrozenArrays`).
"""

from __future__ import annotations

import dataclasses
import sys
from collections.abc import Callable, Iterator, Mapping
from typing import TYPE_CHECKING, Generic, TypeAlias, TypeGuard, TypeVar

if TYPE_CHECKING:
    import numpy as np
    import numpy.typing as npt

__all__ = ["readonly", "FrozenMap", "FrozenArrays", "is_array", "Reduced"]

#: What ``__reduce__`` returns: a callable that rebuilds the object, and the arguments it is called with.
Reduced: TypeAlias = tuple[Callable[..., object], tuple[object, ...]]

K = TypeVar("K")
V = TypeVar("V")


def is_array(value: object) -> TypeGuard[np.ndarray]:
    """``value`` is a numpy array.  Asked without importing numpy: no array exists before numpy is imported, so a
    process that never imports it (a batch's start) pays nothing for the question.  A numpy another thread is
    still importing (in ``sys.modules``, without its ``ndarray`` yet: a batch imports it beside its first run) has
    made no array for lcchain's code, whose own ``import numpy`` waits for the import to end."""
    ndarray = getattr(sys.modules.get("numpy"), "ndarray", None)
    return ndarray is not None and isinstance(value, ndarray)


def readonly(values: npt.ArrayLike, dtype: npt.DTypeLike = float) -> np.ndarray:
    """A contiguous copy of ``values`` that cannot be written to."""
    import numpy as np

    array = np.array(values, dtype=dtype)
    array.flags.writeable = False
    return array


class FrozenMap(Mapping[K, V], Generic[K, V]):
    """A read-only mapping that pickles, compares equal to dicts and keeps its order.

    Array values are made read-only (a copy when they are writable).
    """

    __slots__ = ("_data",)
    _data: dict[K, V]

    def __init__(self, data: Mapping[K, V] | None = None):
        items: dict[K, V] = dict(data) if data is not None else {}
        for key, value in items.items():
            if is_array(value) and value.flags.writeable:
                items[key] = readonly(value, value.dtype)  # type: ignore[assignment]
        object.__setattr__(self, "_data", items)

    def __getitem__(self, key: K) -> V:
        return self._data[key]

    def __iter__(self) -> Iterator[K]:
        return iter(self._data)

    def __len__(self) -> int:
        return len(self._data)

    def __repr__(self) -> str:
        return f"FrozenMap({self._data!r})"

    def __setattr__(self, name: str, value: object) -> None:
        raise AttributeError("FrozenMap is read-only")

    def __reduce__(self) -> Reduced:
        return (type(self), (dict(self._data),))

    def __hash__(self) -> int:
        return hash(tuple(self._data.items()))


class FrozenArrays:
    """Mixin for frozen dataclasses holding numpy arrays: read-only from construction, and when unpickled.

    An array field is replaced by a read-only view of itself (no copy of a
    large waveform); a class with a ``__post_init__`` of its own calls
    :meth:`_freeze_arrays` from it.
    """

    def __post_init__(self) -> None:
        self._freeze_arrays()

    def _freeze_arrays(self) -> None:
        for f in dataclasses.fields(self):  # type: ignore[arg-type]
            value = getattr(self, f.name)
            if is_array(value) and value.flags.writeable:
                view = value.view()
                view.flags.writeable = False
                object.__setattr__(self, f.name, view)

    def __setstate__(self, state: dict[str, object]) -> None:
        for key, value in state.items():
            if is_array(value):
                value.flags.writeable = False
            object.__setattr__(self, key, value)

    def __getstate__(self) -> dict[str, object]:
        return {f.name: getattr(self, f.name) for f in dataclasses.fields(self)}  # type: ignore[arg-type]
