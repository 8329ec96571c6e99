"""What each kind of analysis is, as the rest of lcchain asks it: one registry, :data:`ANALYSIS_KINDS_DATA` (pure).

An analysis kind (:data:`lcchain.core.types.AnalysisKind`) describes itself here: the vector it runs along, whether
it sweeps frequencies (complex phasors, a count of points, no stop time), what its points are called, and whether
a run's key names it.  Code elsewhere asks these attributes, never the kind's name; what an analysis *does* (its
check, its plan, its run and its comparison) is its type in :mod:`lcchain.runs.request.types`, its planner (a
module of :mod:`lcchain.runs.request`, a line in ``PLANNERS``) and its line in
:data:`lcchain.runs.execute.ANALYSIS_RUNS`.
"""

from __future__ import annotations

from dataclasses import dataclass

from .registry import Registry
from .types import AnalysisKind

__all__ = ["AnalysisKindData", "ANALYSIS_KINDS_DATA", "analysis_kind"]


@dataclass(frozen=True)
class AnalysisKindData:
    """One kind of analysis, described.

    Attributes
    ----------
    name : str
        Its name (``[analysis] kind``, ``RunSpec.analysis``).
    axis : str
        The name of the vector it runs along: ``"time"`` (seconds) or ``"frequency"`` (hertz).
    axis_units : str
        That vector's unit.
    swept : bool
        It sweeps frequencies: its vectors are complex phasors, it has a count of points and no stop time, and its
        theory is a spectrum's.
    count : str
        What its points are called in a record's table (``"points"``, ``"frequencies"``).
    keyed : bool
        Whether a run's key names the analysis (the transient's keys were made before there were analyses).
    """

    name: AnalysisKind
    axis: str
    axis_units: str
    swept: bool
    count: str
    keyed: bool


def _admit(name: str, loaded: object) -> AnalysisKindData:
    if not isinstance(loaded, AnalysisKindData) or loaded.name != name:
        raise TypeError(f"{loaded!r} is not an AnalysisKindData named {name!r}")
    return loaded


#: Analysis kind -> what it is; the first is the default.
ANALYSIS_KINDS_DATA: Registry[AnalysisKindData] = Registry(
    "lcchain.analyses",
    {"transient": AnalysisKindData("transient", "time", "s", swept=False, count="points", keyed=False),
     "ac": AnalysisKindData("ac", "frequency", "Hz", swept=True, count="frequencies", keyed=True)},
    _admit, "an lcchain.core.analyses.AnalysisKindData, named as the entry point",
    name_of=lambda part: str(getattr(part, "name", "")))


def analysis_kind(name: str) -> AnalysisKindData:
    """What the analysis kind of that name is (a KeyError for a name no registry holds: callers pass checked
    names)."""
    return ANALYSIS_KINDS_DATA[name]
