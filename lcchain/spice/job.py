"""What one engine run is asked to do: a frozen job, checked once, handed to every engine and transport.

A transient is a :class:`RunJob`, an AC analysis an :class:`AcJob`: the netlist text, the vectors to read back,
the analysis's extent (``tstop``, or the frequencies' count), and what the run may spend (``timeout``,
``max_output_bytes``, ``max_resident_bytes``) and where it may run (``foreign``, ``trusted``, ``cwd``).  Each is
checked in its ``__post_init__`` (a :class:`~lcchain.core.errors.ParameterError` naming the field, its value and
the allowed range), so an engine's :meth:`~lcchain.spice.engine.Engine.run` receives arguments already checked,
and nothing downstream checks them again.

What a transport runs is a :class:`TransportJob`: the text the allow-list (or lcchain's writer) gave, made once
from a checked job (:meth:`TransportJob.checked`), with the digest of its lines split as every reader splits them
(:func:`lcchain.spice.text.circuit_lines`).  A transport reads ``job.text`` and compares a worker's digest with
``job.lines``: the text the allow-list checked is, by construction, the text every transport runs.
"""

from __future__ import annotations

import os
import re
from collections.abc import Callable, Sequence
from dataclasses import KW_ONLY, dataclass
from functools import cached_property
from typing import ClassVar, Literal

from ..core.checks import integer, real
from ..core.errors import ParameterError
from .text import circuit_lines, require_canonical, saved_names, text_digest

__all__ = ["RunJob", "AcJob", "TransportJob", "Progress", "DEFAULT_TIMEOUT"]

#: A run's progress callback: called with the fraction of the analysis done (0.0 ... 1.0); an exception it raises
#: stops the run (its process group is killed) and propagates.
Progress = Callable[[float], None]

#: Seconds after which a run's process group is killed, unless the job says otherwise.
DEFAULT_TIMEOUT = 600.0


def _vectors(vectors: object, axis: str) -> tuple[str, ...]:
    """Canonical vector names (:func:`lcchain.spice.text.canonical_vector_name`), each once, without ``axis``."""
    if isinstance(vectors, str) or not isinstance(vectors, Sequence):
        raise ParameterError("vectors", vectors, "a sequence of vector names, not one string")
    names: list[str] = []
    for name in vectors:
        if not isinstance(name, str) or not name.strip() or re.search(r"\s", name.strip()):
            raise ParameterError("vectors", name, "an ngspice vector name such as 'i(l1)' or 'v(n3)'")
        for key in saved_names(name):  # v(a,b) is v(a) and v(b), as ngspice saves it
            if key != axis and key not in names:
                names.append(key)
    return tuple(names)


def _limit(name: str, value: float | None) -> float | None:
    return None if value is None else real(name, value, above=0.0, unit="bytes")


def _flag(name: str, value: object) -> None:
    if not isinstance(value, bool):
        raise ParameterError(name, value, "True or False")


@dataclass(frozen=True)
class RunJob:
    """A transient run, checked.

    Attributes
    ----------
    netlist : str
        Complete netlist text with one ``.tran`` analysis ending at ``tstop`` and ``.save`` lines for the wanted
        vectors.  Unless ``trusted``, an engine that ``runs_foreign`` runs it through the allow-list
        (:func:`lcchain.spice.foreign.allowed_netlist`, its includes in ``cwd`` inlined).
    vectors : tuple of str
        Canonical vector names (``"i(l1)"``, ``"v(n3)"``; given as saved, ``l1#branch`` too), each once, without
        ``time``; empty: every vector the engine saved.
    tstop : float
        End of the ``.tran`` analysis, seconds: the last time point must equal it.
    timeout : float
        Seconds after which the engine's process group is killed (keyword).
    max_output_bytes : float, optional
        Stop the run (a failure) when its raw file (the vectors, on the warm and shared transports) grows past
        this many bytes, or its output past ``lcchain.spice.processes.MAX_LOG_BYTES``.
    max_resident_bytes : float, optional
        Stop the run (a failure) when the simulator's processes hold more than this many bytes resident.
    foreign : bool
        The netlist was not written by lcchain: it runs in the sandbox (:mod:`lcchain.spice.sandbox`), in an
        engine that ``runs_foreign`` only.
    trusted : bool
        Skip the allow-list and run the netlist as it is, in ``cwd`` (the user said so: ``lcchain batch
        --allow-control``); it still runs in the sandbox when ``foreign``.
    cwd : str, optional
        The netlist's own folder: its ``.include`` files must lie inside it; None for a netlist that includes
        nothing.
    """

    netlist: str
    vectors: Sequence[str]
    tstop: float
    _: KW_ONLY
    timeout: float = DEFAULT_TIMEOUT
    max_output_bytes: float | None = None
    max_resident_bytes: float | None = None
    foreign: bool = True
    trusted: bool = False
    cwd: str | os.PathLike[str] | None = None

    analysis: ClassVar[Literal["transient"]] = "transient"
    #: A transient's run writes one plot.
    joins_plots: ClassVar[bool] = False

    def __post_init__(self) -> None:
        if not isinstance(self.netlist, str) or not self.netlist.strip():
            raise ParameterError("netlist", self.netlist, "non-empty netlist text")
        object.__setattr__(self, "vectors", _vectors(self.vectors, "time"))
        object.__setattr__(self, "tstop", real("tstop", self.tstop, above=0.0, unit="seconds"))
        object.__setattr__(self, "timeout", real("timeout", self.timeout, above=0.0, unit="seconds"))
        object.__setattr__(self, "max_output_bytes", _limit("max_output_bytes", self.max_output_bytes))
        object.__setattr__(self, "max_resident_bytes", _limit("max_resident_bytes", self.max_resident_bytes))
        _flag("foreign", self.foreign)
        _flag("trusted", self.trusted)
        if self.cwd is not None:
            if not isinstance(self.cwd, (str, os.PathLike)):
                raise ParameterError("cwd", self.cwd, "a folder's path, or None")
            object.__setattr__(self, "cwd", os.fspath(self.cwd))


@dataclass(frozen=True)
class AcJob:
    """An AC analysis of lcchain's own ladder, checked.

    Attributes
    ----------
    netlist : str
        Written by :func:`lcchain.circuit.netlist.ac_netlist_text` (ngspice's dialect), with ``.ac`` cards.
    vectors : tuple of str
        Canonical vector names, each once, without ``frequency``; empty: every vector the engine saved.
    points : int
        The frequencies its ``.ac`` cards ask for (at least 1).
    timeout, max_output_bytes, max_resident_bytes
        As :class:`RunJob`'s (keywords).
    foreign : bool
        A netlist lcchain did not write, already through :func:`lcchain.spice.foreign.allowed_netlist`: it runs
        in the sandbox of an engine that ``runs_foreign`` (default False: lcchain's own text).
    """

    netlist: str
    vectors: Sequence[str]
    points: int
    _: KW_ONLY
    timeout: float = DEFAULT_TIMEOUT
    max_output_bytes: float | None = None
    max_resident_bytes: float | None = None
    foreign: bool = False

    analysis: ClassVar[Literal["ac"]] = "ac"
    #: A sweep in several ``.ac`` cards writes one plot a card: read one after the other.
    joins_plots: ClassVar[bool] = True

    def __post_init__(self) -> None:
        if not isinstance(self.netlist, str) or ".ac " not in self.netlist.lower():
            raise ParameterError("netlist", type(self.netlist).__name__, "an AC netlist written by lcchain")
        object.__setattr__(self, "vectors", _vectors(self.vectors, "frequency"))
        object.__setattr__(self, "points", integer("points", self.points, at_least=1))
        object.__setattr__(self, "timeout", real("timeout", self.timeout, above=0.0, unit="seconds"))
        object.__setattr__(self, "max_output_bytes", _limit("max_output_bytes", self.max_output_bytes))
        object.__setattr__(self, "max_resident_bytes", _limit("max_resident_bytes", self.max_resident_bytes))
        _flag("foreign", self.foreign)


@dataclass(frozen=True)
class TransportJob:
    """What a transport runs: a checked text, the plot to read, the limits.

    Made by :meth:`checked` from a checked job and the text its check returned (or, for gnucap's child, the
    text of its dialect); a transport runs ``text`` as it is and holds a worker to ``lines``.

    Attributes
    ----------
    text : str
        The canonical text the allow-list (or lcchain's writer) gave: what every transport runs.
    tstop : float
        The transient's end (s; 0: another analysis), the scale of its progress.
    timeout, max_output_bytes, max_resident_bytes
        As :class:`RunJob`'s.
    plot : str
        The raw file's plot to read (:func:`lcchain.spice.ngspice.raw.read_raw`: ``"transient"``, ``"ac"``).
    joined : bool
        Every plot of that analysis one after the other (a sweep in several ``.ac`` cards), not only the last.
    """

    text: str
    tstop: float
    timeout: float
    max_output_bytes: float | None
    max_resident_bytes: float | None
    plot: str = "transient"
    joined: bool = False

    def __post_init__(self) -> None:
        require_canonical(self.text)  # a text no check made canonical never reaches a transport

    @classmethod
    def checked(cls, text: str, job: RunJob | AcJob, plot: str = "transient") -> TransportJob:
        """The transport's job for ``job``'s checked ``text`` (refused if it is not canonical), reading ``plot``
        (every plot of an ``"ac"`` analysis one after the other: a sweep in several ``.ac`` cards)."""
        return cls(text, job.tstop if isinstance(job, RunJob) else 0.0, job.timeout,
                   job.max_output_bytes, job.max_resident_bytes, plot, job.joins_plots)

    @cached_property
    def lines(self) -> str:
        """SHA-256 of ``text`` split at LF alone (:func:`lcchain.spice.text.circuit_lines`, as the check split
        it): a worker reports the digest of the lines it handed its engine, and the transport compares the two
        (computed once, by the transports that hand lines to a worker)."""
        return text_digest(circuit_lines(self.text))
