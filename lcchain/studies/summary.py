"""A Monte Carlo's results by group: the transmitted peak's distribution for every combination of the axes.

A study's tasks share everything but their parameters; the tolerance samples
of one combination (same parameters but ``sample``) form a group, and each
group's first-arrival peaks (max I_N / I_1(0) near the arrival, from ngspice)
or, after a kick, the energy fraction the last inductor holds at that peak
(``metric="energy"``: peak^2 L_N / L_1, at most 1, blind to a mismatch of the
end inductors) are summarised: how many, mean, standard deviation, worst, 5th
percentile, median, best.  ``lcchain results STORE --summary`` prints these; the study's
figure draws the same groups.
"""

from __future__ import annotations

from collections import Counter
from dataclasses import dataclass

import numpy as np

from ..core.checks import choice
from ..core.errors import ParameterError
from ..core.json import JSONDict, LooseJSONObject
from ..core.types import STUDY_METRICS, StudyMetric
from .stored import StoredRun, study_axes, study_constants

__all__ = ["Group", "peak_groups", "METRICS", "available_metrics", "measurement_names", "study_axes", "study_constants",
           "check_metric", "is_measurement"]

#: What a group summarises, by name: a transient's first arrival's current peak, its energy fraction (kick only),
#: or the energy lost on the way, 1 - energy fraction (best on a log scale: it spans decades between designs);
#: an AC run's worst relative error of omega_n, worst absolute error of P_n, or the spread of its spacings
#: (max - min) / mean of delta omega_n (what real parts do to the equal spacing).  Each reads a stored run's
#: metrics: (field, where) with where "arrival" (the first arrival's) or "run" (the run's own).
METRICS: dict[StudyMetric, tuple[str, str]] = {
    "peak": ("peak_sim", "arrival"), "energy": ("energy_sim", "arrival"), "loss": ("energy_sim", "arrival"),
    "omega": ("max_rel_error_omega", "run"), "P": ("max_abs_error_P", "run"), "spacing": ("spacing_spread", "run"),
}


@dataclass(frozen=True)
class Group:
    """The runs of one combination of a study's axes.

    Attributes
    ----------
    params : dict
        The combination (every parameter but ``sample``), in the plan's order.
    peaks : ndarray
        First-arrival peaks of the runs that finished, in task order.
    failed : int
        Runs that failed, timed out or were refused (a batch's netlist lcchain would not run): they gave no value
        (pending ones are not counted).
    """

    params: LooseJSONObject
    peaks: np.ndarray
    failed: int

    def stats(self) -> dict[str, float | None]:
        """n, failed, mean, std (ddof 1: None for a single value, which has no spread to estimate), min, p05,
        median, max of the peaks (None when there are none)."""
        p = self.peaks
        if p.size == 0:
            return {"n": 0, "failed": self.failed, "mean": None, "std": None, "min": None, "p05": None,
                    "median": None, "max": None}
        return {"n": int(p.size), "failed": self.failed, "mean": float(p.mean()),
                "std": float(p.std(ddof=1)) if p.size > 1 else None, "min": float(p.min()),
                "p05": float(np.percentile(p, 5)), "median": float(np.median(p)), "max": float(p.max())}

    def to_dict(self) -> JSONDict:
        return {"params": self.params, **self.stats()}


def measurement_names(runs: list[StoredRun]) -> list[str]:
    """The ``.meas`` names the store's finished runs measured (a value, or a missing one), in order."""
    return list(dict.fromkeys(name for run in runs if run.status == "ok" and not run.member
                              for name in run.measurements))


def _value(run: StoredRun, metric: str, measured: bool = False) -> float | None:
    """The run's value of a metric (None where it has none: a pulse's energy, a transient's spacing, a
    measurement ngspice could not make); a name not in :data:`METRICS`, or any with ``measured``, is one of the
    netlist's measurements."""
    if measured or metric not in METRICS:
        value = run.measurements.get(metric)
        return None if value is None else float(value)
    field, where = METRICS[metric]
    metrics = run.metrics or {}
    if where == "arrival":
        arrivals = metrics.get("arrivals") or []
        metrics = arrivals[0] if arrivals else {}
    value = metrics.get(field)
    # NaN: nothing compared (an AC run whose every mode merged), no value; an unseen mode's infinity stays
    return None if value is None or value != value else float(value)


def available_metrics(runs: list[StoredRun]) -> list[str]:
    """The metrics the store's finished runs give (an energy fraction needs a kick: a pulse's is undefined; a
    spectral metric an AC run)."""
    finished = [run for run in runs if run.status == "ok" and not run.member]
    return [metric for metric in METRICS if any(_value(run, metric) is not None for run in finished)]


def is_measurement(metric: str, runs: list[StoredRun]) -> bool:
    """Whether ``metric`` names one of the netlists' ``.meas`` in this store: a name that is none of :data:`METRICS`,
    or one that is (a ``.meas peak``) in a store whose runs give no metric of their own (a batch of netlists)."""
    return _measures(metric, measurement_names(runs), available_metrics(runs))


def _measures(metric: str, measured: list[str], available: list[str]) -> bool:
    """:func:`is_measurement` of the store's measurement names and available metrics, read once by the caller."""
    return metric in measured and (metric not in METRICS or not available)


def check_metric(metric: str, runs: list[StoredRun], option: str = "--metric") -> None:
    """Refuse a metric the store's runs cannot give, before anything is printed or drawn.

    Raises
    ------
    ParameterError
        Naming ``option``, the metric and the ones available; or, when none is, why: no run finished yet, or
        the runs have no theory to give one (a batch of netlists).
    """
    measured, available = measurement_names(runs), available_metrics(runs)
    if _measures(metric, measured, available):
        return
    choice(option, metric, (*METRICS, *measured))
    if metric in available:
        return
    if available:
        raise ParameterError(option, metric, f"a metric this store's runs give: {' | '.join(available)} (an "
                             "energy fraction needs a kicked first loop; a pulse's is undefined; omega, P and "
                             "spacing are an AC analysis's)")
    finished = [run for run in runs if run.status == "ok" and not run.member]
    if not finished:
        ended = Counter(run.status for run in runs if run.status not in ("ok", "pending") and not run.member)
        if ended:  # the same command would not run them again: say so, and where to read why
            counts = ", ".join(f"{count} {status}" for status, count in sorted(ended.items()))
            raise ParameterError(option, metric, f"a store with runs that finished ok (none did: {counts}; "
                                 "`lcchain results STORE` says why, and the study's command with --retry-failed "
                                 "runs the failed ones again)")
        raise ParameterError(option, metric, "a store with finished runs (none has finished yet: run the study's "
                             "command again to resume it)")
    # AC runs (their spectral metrics) that compared nothing: their losses merged every mode
    if metric in METRICS and any("modes_seen" in (run.metrics or {}) for run in finished):
        raise ParameterError(option, metric, f"a metric with a value in this store: its {len(finished)} finished "
                             "runs compared no mode (their losses merged every one: `lcchain results STORE --json` "
                             "holds each run's Y_11 against the exact admittance, max_rel_error_Y11)")
    measures = f": --metric {' | '.join(measured)}, a .meas of the netlists" if measured else \
        " (a batch of netlists: `lcchain results STORE` shows each one's vectors, points and time)"
    raise ParameterError(option, metric, f"a store of runs with a theory to compare with; its {len(finished)} "
                         f"finished runs have none{measures}")


def _drawn(runs: list[StoredRun], axes: list[str]) -> set[str]:
    """The axes whose value the sample number alone fixes: the values a sweep of a netlist drew (one per sample,
    the same at every point of its other axes, :func:`lcchain.studies.vary.variant_points`) belong to the samples
    of a group, not to a group of their own.  No other study has such an axis (a scene's axes take several
    values at one sample number)."""
    if "sample" not in axes:
        return set()
    drawn = set()
    for key in axes:
        if key == "sample":
            continue
        by_sample: dict[str, str] = {}
        if all(by_sample.setdefault(repr(run.params.get("sample")), repr(run.params.get(key)))
               == repr(run.params.get(key)) for run in runs):
            drawn.add(key)
    return drawn


def peak_groups(runs: list[StoredRun], metric: str = "peak") -> list[Group]:
    """The runs grouped by the study's axes without ``sample`` (:func:`study_axes`) and the values drawn per
    sample (a netlist's ``--vary`` distributions), groups in the order of their first task (an extrapolation
    counts once, by its combined result).

    Parameters
    ----------
    runs : list of StoredRun
    metric : {"peak", "energy", "loss", "omega", "P", "spacing"} or str
        The first arrival's current peak, its energy fraction, or 1 - that fraction (runs without one, i.e.
        not kicked, are left out of the groups' values); or an AC run's spectral metric (:data:`METRICS`); or
        the name of a netlist's ``.meas`` (a batch: its runs that could not measure it are left out of the
        values; a name of :data:`METRICS` means that metric, unless the runs give none and measured it:
        :func:`is_measurement`).
    """
    measured = is_measurement(metric, runs)
    name = metric if measured else choice("metric", metric, STUDY_METRICS)
    results = [run for run in runs if not run.member]
    every = study_axes(results)
    drawn = _drawn(results, every)
    axes = [key for key in every if key != "sample" and key not in drawn]
    order: dict[str, LooseJSONObject] = {}
    peaks: dict[str, list[float]] = {}
    failed: dict[str, int] = {}
    for run in runs:
        if run.member:  # an extrapolation's ingredient: its combination is the result
            continue
        params = {k: run.params[k] for k in axes if k in run.params}
        key = repr(sorted(params.items()))
        order.setdefault(key, params)
        peaks.setdefault(key, [])
        failed.setdefault(key, 0)
        if run.status in ("failed", "timeout", "refused"):
            failed[key] += 1
        elif run.status == "ok":
            peak = _value(run, name, measured)
            if peak is not None and metric == "loss" and not measured:
                peak = 1.0 - peak
            if peak is not None:
                peaks[key].append(peak)
    return [Group(params, np.array(peaks[key]), failed[key]) for key, params in order.items()]
