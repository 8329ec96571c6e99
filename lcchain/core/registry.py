"""Registries: names to implementations, lcchain's own and those other packages install (pure).

A :class:`Registry` is the mapping each kind of part is looked up in (effects by scene key, engines by name),
as scipy's ``METHODS`` dict is for ``solve_ivp``.  Beside lcchain's own parts it holds those a separately
installed package declares in the registry's entry-point group (``lcchain.effects``, ``lcchain.engines``),
as xarray finds its backends through ``xarray.backends``: no edit to lcchain.  The group is read once, the
first time the registry is read for a name it does not hold yet, or listed, so ``import lcchain`` reads no
package metadata, and neither does a command that looks up lcchain's own parts only (a plugin cannot take an
own part's name: ``lcchain batch`` finds ngspice without reading every installed package's entry points, 30 ms).

A plugin that cannot be loaded, or that is not what its group holds, is a :class:`PluginError` naming the
entry point (one line; exit status 2 on the command line), never a traceback.

A registry is open: where lcchain takes a part by name, it also takes the part itself
(:meth:`Registry.accept`), as ``solve_ivp(method=MyOdeSolver)`` does; the part is added under its own name the
first time, so that what lcchain keeps (a spec, a record, a store's row) is the name as always.
"""

from __future__ import annotations

import dataclasses
import threading
import types
from collections.abc import Callable, Iterator, Mapping, MutableMapping
from typing import TYPE_CHECKING, TypeVar

from .errors import ParameterError

if TYPE_CHECKING:  # importlib.metadata and the email package: 30 ms, imported when a group is read
    from importlib.metadata import EntryPoint

__all__ = ["Registry", "PluginError", "entry_point_names"]

V = TypeVar("V")


class PluginError(ParameterError):
    """An entry point of an lcchain group that cannot be used.

    ``field`` is ``"entry point <group> <name>"``, ``value`` what it points to (``module:attribute``) and
    ``allowed`` what the group holds, with the reason it was refused.
    """


def entry_point_names(group: str) -> tuple[str, ...]:
    """The names the installed packages give parts in ``group``, sorted, without loading any (a ``--help`` lists
    them beside lcchain's own without importing the registry's module)."""
    from importlib.metadata import entry_points

    return tuple(sorted({point.name for point in entry_points(group=group)}))


def _one_line(text: str) -> str:
    return " ".join(text.split())


class Registry(MutableMapping[str, V]):
    """A name -> implementation mapping whose entry-point group is loaded on first read.

    Parameters
    ----------
    group : str
        The entry-point group other packages add to (``"lcchain.effects"``).
    own : Mapping
        lcchain's own parts, in order; the plugins follow them, sorted by name.
    admit : callable
        ``admit(name, loaded) -> value``: what the registry holds for an entry point's loaded object; raises
        (any exception) when it is not a part of this kind.
    what : str
        What the group holds, in words, for errors (``"an lcchain Effect subclass"``).
    name_of : callable, optional
        ``name_of(part) -> str``: the name a part given as itself is registered under (an engine's ``name``, an
        effect's ``key``); without it the registry takes names only.
    """

    def __init__(self, group: str, own: Mapping[str, V], admit: Callable[[str, object], V], what: str,
                 name_of: Callable[[object], str] | None = None):
        self.group = group
        self.what = what
        self._admit = admit
        self._name_of = name_of
        self._items: dict[str, V] = dict(own)
        self._loaded = False
        self._loading = threading.Lock()  # threads reading the registry first (a study's runners) load it once

    def _entry(self, point: EntryPoint, reason: str) -> PluginError:
        return PluginError(f"entry point {self.group} {point.name}", point.value, f"{self.what} ({_one_line(reason)})")

    def _load(self) -> dict[str, V]:
        if self._loaded:
            return self._items
        with self._loading:
            if not self._loaded:
                self._read_group()
        return self._items

    def _read_group(self) -> None:
        from importlib.metadata import entry_points

        added: dict[str, V] = {}
        for point in sorted(entry_points(group=self.group), key=lambda p: p.name):
            if point.name in self._items or point.name in added:
                raise self._entry(point, f"a name no other part has: {point.name!r} is taken")
            try:
                added[point.name] = self._admit(point.name, point.load())
            except PluginError:
                raise
            except Exception as error:  # whatever a broken plugin raises, the user sees which one
                raise self._entry(point, f"{type(error).__name__}: {error}") from None
        self._items.update(added)
        self._loaded = True

    def accept(self, field: str, value: object) -> V:
        """The part ``value`` names, or ``value`` itself when it is a part of this kind (what an entry point may
        hold), added under its own name the first time it is given.

        Raises
        ------
        ParameterError
            Naming ``field``: a name the registry does not hold, an object that is not a part of this kind, or
            a part whose name another part already holds.
        """
        if isinstance(value, str) and value in self._items:  # held (an own part's name no plugin can take)
            return self._items[value]  # no entry point read for it
        allowed = " | ".join(self._load())
        if isinstance(value, str):
            if value in self._items:
                return self._items[value]
            raise ParameterError(field, value, allowed)
        if self._name_of is None:
            raise ParameterError(field, value, allowed)
        try:
            name = self._name_of(value)
            part = self._admit(name, value)
        except Exception as error:  # whatever a foreign object raises, the user sees the field and why
            raise ParameterError(field, value, f"{allowed}, or {self.what} ({_one_line(str(error))})") from None
        with self._loading:
            held = self._items.setdefault(name, part)
        # the same part again (an engine made twice, an equal frozen record) is the one held; another is refused
        same = not isinstance(part, (type, types.FunctionType)) and type(held) is type(part) \
            and (not dataclasses.is_dataclass(part) or held == part)
        if held is not part and not same:
            raise ParameterError(field, value, f"a part under a name no other part has: {name!r} is taken")
        return held

    @property
    def held(self) -> frozenset[str]:
        """The names held without reading the entry points (lcchain's own parts, those set here, and the plugins'
        once read): looking one up reads no entry point (``importlib.metadata`` and every installed package's
        metadata, about 15 ms of a batch's start)."""
        return frozenset(self._items)

    def __getitem__(self, name: str) -> V:
        if name in self._items:  # an own part (or one set here): no plugin can have its name
            return self._items[name]
        return self._load()[name]

    def __contains__(self, name: object) -> bool:
        return name in self._items or name in self._load()

    def __iter__(self) -> Iterator[str]:
        return iter(list(self._load()))

    def __len__(self) -> int:
        return len(self._load())

    def __setitem__(self, name: str, value: V) -> None:
        self._load()[name] = value

    def __delitem__(self, name: str) -> None:
        del self._load()[name]

    def __repr__(self) -> str:
        loaded = "" if self._loaded else ", plugins not read yet"
        return f"Registry({self.group!r}: {', '.join(self._items)}{loaded})"
