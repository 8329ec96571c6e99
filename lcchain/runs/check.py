"""``lcchain check`` as a unit of work: a linear netlist run in a simulator and compared with its exact response.

The netlist passes the allow-list (:func:`lcchain.spice.foreign.allowed_netlist`), runs in the sandbox like a
batch's, and its element cards are read as numbers (:func:`lcchain.spice.element_values.read_cards`).
When every element is an R, L, C, K or an independent source with a DC value, PULSE, SIN, PWL or EXP function
(AC magnitude and phase for an ``.ac``), :func:`circuit_of` makes it a
:class:`lcchain.circuit.linear.LinearCircuit` with ngspice 39's defaults for what the cards leave out, and
:func:`check_text` compares every saved vector with the exact response at the simulator's own time points or
frequencies (:mod:`lcchain.compare.check`), predicts the trapezoidal rule's error at the run's largest step,
and finds the fixed step an accuracy needs.

An engine that does not run foreign netlists but ``checks_cards`` (gnucap) runs lcchain's own copy of the
netlist, written from the cards' numbers (:mod:`lcchain.spice.gnucap_check`), its vectors read back by the
user's names; what it cannot run exactly (and a netlist with no exact reference) is refused.

Anything else (a behavioural source, a SFFM source, a diode or transistor, a sub-circuit instance, a value that
calls a ``.func``) still runs: the result says "no exact reference" and why, and has no errors.

ngspice 39's defaults, as its manual gives them: PULSE: rise and fall TSTEP, width and period TSTOP; SIN:
frequency 1/TSTOP; EXP: rise delay 0, rise time constant TSTEP, fall delay rise delay + TSTEP, fall time constant
TSTEP; a source without DC value takes its transient function's value at t = 0 for the operating point.
"""

from __future__ import annotations

import math
import time
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from ..core.budget import Budget, Estimate
from ..core.errors import ParameterError
from ..core.json import JSONDict
from ..spice.element_values import (
    ControlledCard,
    CouplingCard,
    ElementCard,
    NetlistCards,
    OtherCard,
    SourceCard,
    read_cards,
)
from ..spice.engines import ENGINES, engine_named, find_engine
from ..spice.foreign import Sweep, Transient, allowed_netlist, analysis_of, foreign_price
from ..spice.pricing import Price, RunLimits
from ..spice.result import read_include
from ..spice.simulator import Simulator
from ..spice.text import canonical_text, canonical_vector_name, saved_names, saved_vectors

if TYPE_CHECKING:  # the exact reference loads where a check uses it (a batch without --check starts without it)
    from ..circuit.linear import LinearCircuit, LinearResponse, Waveform

__all__ = ["VectorCheck", "CheckResult", "CheckOptions", "circuit_of", "check_text", "check_file",
           "reference_measurements", "check_estimate", "CHECK_MEASUREMENT", "DEFAULT_ACCURACY"]

#: The measurement a batch run with ``check`` stores: the largest error of its saved vectors (their own units).
CHECK_MEASUREMENT = "check_max_abs_error"

#: The relative accuracy whose step ``lcchain check`` suggests when none is asked for.
DEFAULT_ACCURACY = 1e-6
#: Methods ngspice integrates with; the prediction is the trapezoidal rule's (gear: a rough factor).
_PREDICTED = {"trap": "the trapezoidal rule's error, predicted from the poles: exact for trap at a fixed step",
              "gear": "gear: 4 x the trapezoidal prediction (a factor measured on ladders only; a rough guide)"}


@dataclass(frozen=True)
class VectorCheck:
    """One saved vector: its error against the exact reference (its own units), its scale (the reference's
    largest magnitude), and the error predicted at the run's largest step (transient, trap model)."""

    name: str
    unit: str
    max_abs_error: float | None
    scale: float | None
    predicted_error: float | None = None

    @property
    def max_rel_error(self) -> float | None:
        if self.max_abs_error is None or not self.scale:
            return None
        return self.max_abs_error / self.scale

    def to_dict(self) -> JSONDict:
        return {"name": self.name, "unit": self.unit, "max_abs_error": self.max_abs_error, "scale": self.scale,
                "max_rel_error": self.max_rel_error, "predicted_error": self.predicted_error}


@dataclass(frozen=True)
class CheckResult:
    """What ``lcchain check`` found (see :func:`check_text`)."""

    netlist: str
    engine: str
    engine_version: str
    analysis: str
    method: str
    points: int
    simulator_seconds: float
    vectors: tuple[VectorCheck, ...]
    accuracy: float
    accuracy_given: bool
    reference: str = ""  # "" or why there is no exact reference
    reference_seconds: float | None = None
    states: int | None = None
    unknowns: int | None = None
    rounding: float | None = None
    run_step: float | None = None
    predicted_error: float | None = None
    suggested_step: float | None = None
    prediction: str = ""
    notes: tuple[str, ...] = field(default=())

    @property
    def max_abs_error(self) -> float | None:
        errors = [v.max_abs_error for v in self.vectors if v.max_abs_error is not None]
        return max(errors) if errors else None

    @property
    def max_rel_error(self) -> float | None:
        errors = [v.max_rel_error for v in self.vectors if v.max_rel_error is not None]
        return max(errors) if errors else None

    @property
    def passed(self) -> bool:
        """False when an accuracy was given and a vector's relative error exceeds it."""
        worst = self.max_rel_error
        return not (self.accuracy_given and worst is not None and worst > self.accuracy)

    def to_dict(self) -> JSONDict:
        return {
            "netlist": self.netlist, "engine": self.engine, "engine_version": self.engine_version,
            "analysis": self.analysis, "method": self.method, "points": self.points,
            "simulator_seconds": self.simulator_seconds,
            "exact_reference": not self.reference, "no_reference_reason": self.reference or None,
            "max_abs_error": self.max_abs_error, "max_rel_error": self.max_rel_error,
            "accuracy": self.accuracy, "accuracy_given": self.accuracy_given,
            "passed": self.passed if self.accuracy_given else None,  # nothing was asked of it
            "reference_seconds": self.reference_seconds, "states": self.states, "unknowns": self.unknowns,
            "rounding": self.rounding, "run_step": self.run_step, "predicted_error": self.predicted_error,
            "suggested_step": self.suggested_step, "prediction": self.prediction or None,
            "vectors": [v.to_dict() for v in self.vectors], "notes": list(self.notes),
        }


# --------------------------------------------------------------------------- cards -> circuit


def _arguments(card: SourceCard, count: int, defaults: list[float | None]) -> list[float] | str:
    values: list[float | None] = [*card.arguments[:count], *defaults[len(card.arguments):count]]
    if len(card.arguments) > count:
        return f"source {card.name.upper()}: {card.function.upper()} with {len(card.arguments)} arguments"
    if any(v is None for v in values):
        return f"source {card.name.upper()}: {card.function.upper()} without its required arguments"
    return [float(v) for v in values if v is not None]


def source_function(card: SourceCard, analysis: Transient | Sweep) -> tuple[str, tuple[float, ...]] | str:
    """The source's transient function and its arguments with ngspice 39's defaults filled in (``("", ())`` for a
    constant, or in an AC sweep), or why it has no exact reference."""
    step, stop = (analysis.step, analysis.stop) if isinstance(analysis, Transient) else (1.0, 1.0)
    name, function = card.name.upper(), card.function
    if not function or isinstance(analysis, Sweep):
        return "", ()
    if function == "pulse":
        values = _arguments(card, 8, [None, None, 0.0, step, step, stop, stop, None])
        if isinstance(values, str):
            values = _arguments(card, 7, [None, None, 0.0, step, step, stop, stop])
            if isinstance(values, str):
                return values
        # a time of 0 is ngspice's default too (vsrcload.c): TR and TF the step, PW and PER the stop time
        for index, default in ((3, step), (4, step), (5, stop), (6, stop)):
            if values[index] == 0:
                values[index] = default
        return "pulse", tuple(values)
    if function == "sin":
        values = _arguments(card, 6, [None, None, 1.0 / stop, 0.0, 0.0, 0.0])
        if isinstance(values, str):
            return values
        if values[2] == 0:  # FREQ 0, as FREQ left out: 1 / TSTOP
            values[2] = 1.0 / stop
        return "sin", tuple(values)
    if function == "exp":
        given = list(card.arguments)
        if not 2 <= len(given) <= 6:
            return f"source {name}: EXP with {len(given)} arguments"

        def time(index: int, default: float) -> float:  # 0 or left out: ngspice's default
            return given[index] if len(given) > index and given[index] != 0 else default

        delay1 = time(2, step)
        return "exp", (given[0], given[1], delay1, time(3, step), time(4, delay1 + step), time(5, step))
    if function == "pwl":
        values = list(card.arguments)
        if len(values) < 2 or len(values) % 2 or any(b < a for a, b in zip(values[0::2], values[2::2],
                                                                               strict=False)):
            return f"source {name}: PWL of (time, value) pairs in ascending time"
        return _pwl_written_out(name, values, dict(card.keywords), stop)
    return f"source {name}: {function.upper()}"


#: The most points a PWL written out up to the stop time may have (its ``R=`` repetitions): beyond, its exact
#: reference would hold more breakpoints than the run has points of any sensible analysis.
MAX_PWL_POINTS = 1_000_000


def _pwl_written_out(name: str, values: list[float], keywords: dict[str, float], stop: float
                     ) -> tuple[str, tuple[float, ...]] | str:
    """A PWL's points as ngspice 39 runs them up to ``stop``: delayed by ``TD=`` (its first value held before), and
    from its last point on, with ``R=``, the part from time R to the last point repeated (jumping back to R's
    value), which R must start at one of its points (ngspice stops the run otherwise)."""
    times, levels = values[0::2], values[1::2]
    delay = keywords.get("td", 0.0)
    points = [(t + delay, v) for t, v in zip(times, levels, strict=True)]
    if delay > 0 and points[0][0] > 0:
        points.insert(0, (0.0, levels[0]))
    if keywords.get("r", -1.0) >= 0:  # R=-1 (or any R < 0): no repetition, as ngspice 39 runs it
        repeat = keywords["r"]
        if repeat not in times:
            return f"source {name}: PWL R={repeat:g}, not one of its time points (ngspice stops the run)"
        start = times.index(repeat)
        shape = [(t - repeat, v) for t, v in zip(times[start:], levels[start:], strict=True)]
        period = times[-1] - repeat
        if period <= 0:
            return f"source {name}: PWL R={repeat:g} at its last time point (nothing to repeat)"
        repeats = max(0.0, (stop - points[-1][0]) / period)
        if len(points) + (math.ceil(repeats) + 1) * len(shape) > MAX_PWL_POINTS:
            return f"source {name}: PWL repeated {repeats:.3g} times before the stop time (more than " \
                   f"{MAX_PWL_POINTS} points)"
        starts = _repetitions(times, keywords, stop)
        for begin, following in zip(starts, starts[1:], strict=False):
            # each repetition ends where the next begins, exactly: a jump at one time (_waveform's jumps_after),
            # never two times one rounding apart (a slope of 1e20, which the modal solution cannot hold)
            points += [(begin + at, v) for at, v in shape[:-1]] + [(following, shape[-1][1])]
    return "pwl", tuple(x for point in points for x in point)


def _repetitions(times: Sequence[float], keywords: dict[str, float], stop: float) -> list[float]:
    """The times a repeated PWL starts again up to ``stop``, and the first after it (where the last repetition
    ends): its delay + its last time + k (its last time - R), each its own sum, not a sum of periods; at each the
    source already is R's value (ngspice, measured).  None without a repetition (R < 0, none of its times, its
    last)."""
    repeat = keywords.get("r", -1.0)
    if repeat < 0 or repeat not in times or times[-1] <= repeat:
        return []
    delay, period = keywords.get("td", 0.0), times[-1] - repeat
    starts = [delay + times[-1]]
    while starts[-1] <= stop:
        starts.append(delay + times[-1] + len(starts) * period)
    return starts


def _waveform(card: SourceCard, analysis: Transient | Sweep) -> Waveform | str:
    """The source's waveform (lcchain.circuit.linear), or why it has no exact reference."""
    from ..circuit.linear import PulseSource, Waveform, exp_waveform, pulse_waveform, pwl_waveform, sin_waveform

    found = source_function(card, analysis)
    if isinstance(found, str):
        return found
    function, values = found
    if not function:
        return Waveform.constant(card.dc or 0.0)
    if function == "pulse":
        v1, v2, delay, rise, fall, width, period = values[:7]
        count = int(values[7]) if len(values) > 7 else None
        stop = analysis.stop if isinstance(analysis, Transient) else 1.0
        return pulse_waveform(PulseSource(v1, v2, delay, rise, fall, width, period, count), stop)
    if function == "sin":
        return sin_waveform(*values)
    if function == "exp":
        return exp_waveform(*values)
    # a repeated PWL jumps back to R's value at each repetition's start and already is it then, as ngspice 39 gives
    # it; a step written in it (two points at one time) is the value before, as everywhere
    return pwl_waveform(list(zip(values[0::2], values[1::2], strict=True)), jumps_after=_repetitions(
        card.arguments[0::2], dict(card.keywords), analysis.stop) if isinstance(analysis, Transient) else ())


def circuit_of(cards: NetlistCards, analysis: Transient | Sweep) -> LinearCircuit | str:
    """The :class:`lcchain.circuit.linear.LinearCircuit` of the cards, or the reason there is none (a string:
    ``"nonlinear: D1"``, ``"source V2: SFFM"``)."""
    from ..circuit.linear import Branch, Controlled, Coupling, LinearCircuit, Source

    branches, sources, couplings, controlled = [], [], [], []
    volts = {card.name for card in cards.elements if isinstance(card, SourceCard) and card.letter == "V"}
    for card in cards.elements:
        if isinstance(card, OtherCard):
            kind = {"B": "behavioural source", "X": "sub-circuit"}.get(card.letter, "nonlinear" if card.letter in
                                                                       "DQMJSWZ" else "controlled source"
                                                                       if card.letter in "EFGH" else "not modelled")
            return f"{kind}: {card.name.upper()}" + (f" ({card.why})" if card.why else "")
        if isinstance(card, ElementCard):
            keywords = dict(card.keywords)
            unknown = sorted(set(keywords) - {"ic", "m"} - ({"tc1", "tc2"} if card.letter == "R" else set()))
            if unknown or any(keywords.get(k, 0.0) for k in ("tc1", "tc2")):
                return f"element {card.name.upper()}: {', '.join(unknown) or 'temperature coefficients'}"
            multiplier = keywords.get("m", 1.0)
            value = card.value / multiplier if card.letter in "RL" else card.value * multiplier
            branches.append(Branch(card.letter, card.name, card.a, card.b, value,  # type: ignore[arg-type]
                                   keywords.get("ic")))
        elif isinstance(card, CouplingCard):
            couplings.append(Coupling(card.name, card.first, card.second, card.k))
        elif isinstance(card, ControlledCard):
            if card.control and card.control not in volts:
                return (f"controlled source {card.name.upper()} ({card.where}): no voltage source "
                        f"{card.control.upper()} whose current controls it")
            controlled.append(Controlled(card.letter, card.name, card.a, card.b,  # type: ignore[arg-type]
                                         card.gain, card.c, card.d, card.control))
        else:
            waveform = _waveform(card, analysis)
            if isinstance(waveform, str):
                return waveform
            phase = math.radians(card.ac[1])
            sources.append(Source(card.letter, card.name, card.a, card.b, waveform,  # type: ignore[arg-type]
                                  card.ac[0] * complex(math.cos(phase), math.sin(phase))))
    return LinearCircuit(tuple(branches), tuple(sources), tuple(couplings), cards.initial, cards.uic,
                         tuple(controlled))


# --------------------------------------------------------------------------- the check


def _unit(name: str) -> str:
    return "V" if name.startswith("v(") else "A" if name.startswith(("i(", "@")) else ""


def _run(text: str, analysis: Transient | Sweep, simulator: Simulator, limits: RunLimits, trusted_in: Path | None
         ) -> tuple[np.ndarray, dict[str, np.ndarray], float, str]:
    """(time or frequency, vectors by canonical name, wall seconds, version) of the simulator's run, within its
    price's ``limits``."""
    if isinstance(analysis, Sweep):
        from ..spice.ac import AcJob, run_ac

        if trusted_in is not None:
            raise ParameterError("--allow-control", True, "a .tran netlist (an .ac one runs through the allow-list)")
        ac = run_ac(AcJob(text, (), analysis.count, timeout=limits.timeout, foreign=True,
                          max_output_bytes=limits.max_output_bytes, max_resident_bytes=limits.max_resident_bytes),
                    simulator)
        return np.asarray(ac.frequency), {k: np.asarray(v) for k, v in ac.vectors.items()}, ac.wall_s, \
            ac.engine_version
    from ..spice.job import RunJob
    from ..spice.ngspice.runner import run

    result = run(RunJob(text, (), analysis.stop, timeout=limits.timeout, foreign=True, trusted=trusted_in is not None,
                        cwd=trusted_in, max_output_bytes=limits.max_output_bytes,
                        max_resident_bytes=limits.max_resident_bytes), simulator)
    return np.asarray(result.time), {k: np.asarray(v) for k, v in result.vectors.items()}, result.wall_s, \
        result.engine_version


def check_estimate(price: Price, text: str, analysis: Transient | Sweep, source: str = "netlist") -> Estimate:
    """The run's price with its exact reference's (:func:`lcchain.circuit.linear.linear_cost`: the dense solution,
    the response at the run's points, the step's search) when the netlist is linear: what ``lcchain check`` and a
    batch's ``--check`` are priced at before anything runs."""
    from ..circuit.linear import circuit_unknowns, linear_cost

    try:
        circuit = circuit_of(read_cards(text, source), analysis)
    except ParameterError:  # a card the reader refuses: the run alone (its check will say why it has no reference)
        return price.estimate
    if isinstance(circuit, str):  # no exact reference: the run alone
        return price.estimate
    unknowns = circuit_unknowns(circuit)
    seconds, memory = linear_cost(unknowns, price.points, max(len(saved_vectors(text)), 1))
    return Estimate(f"{price.what} and its exact reference ({unknowns} unknowns)", price.memory + memory,
                    price.seconds + seconds)


@dataclass(frozen=True)
class CheckOptions:
    """How :func:`check_text` checks a netlist, checked when made.

    Parameters
    ----------
    accuracy : float, optional
        Relative to each vector's scale (its exact reference's largest magnitude): the result does not pass when
        a vector's error exceeds it; the suggested step is the step it needs (default
        :data:`DEFAULT_ACCURACY`, which passes or fails nothing).
    engine : str
        A registered engine that runs foreign netlists (:attr:`lcchain.spice.engine.Engine.runs_foreign`), or
        one that checks their cards (it runs the netlist lcchain writes from their numbers).
    timeout : float
        Seconds before the simulator is stopped (the price's own limit may be smaller).
    allow_control : bool
        Run the netlist as it is (``.control`` blocks, ``.model`` cards, diodes...: ``lcchain batch
        --allow-control``), still in the sandbox; what is not linear then has no exact reference.
    budget : Budget, optional
        The run and the exact reference are priced (:func:`check_estimate`) and refused beyond it; the run is
        stopped at its price's limits (time, raw file, resident memory), as a batch's runs are.

    Raises
    ------
    ParameterError
        An accuracy outside 0 < a < 1, an engine that cannot run netlists lcchain did not write, or
        ``allow_control`` with an engine that only runs lcchain's copy (named as the command line's options).
    """

    accuracy: float | None = None
    engine: str = "ngspice"
    timeout: float = 600.0
    allow_control: bool = False
    budget: Budget | None = None

    def __post_init__(self) -> None:
        if not (math.isfinite(self.accuracy_value) and 0 < self.accuracy_value < 1):
            raise ParameterError("--accuracy", self.accuracy, "a relative accuracy 0 < a < 1")
        found = engine_named(self.engine, "--engine")
        if self.rewritten and not found.checks_cards:
            able = ", ".join(name for name, e in ENGINES.items() if e.runs_foreign or e.checks_cards)
            raise ParameterError("--engine", self.engine, f"an engine that runs netlists lcchain did not write "
                                 f"({able}): {self.engine} runs only lcchain's own ladders")
        if self.rewritten and self.allow_control:
            raise ParameterError("--allow-control", True, f"ngspice ({self.engine} runs only the netlist lcchain "
                                 "writes from a linear netlist's numbers)")

    @property
    def accuracy_value(self) -> float:
        """The accuracy asked for, or :data:`DEFAULT_ACCURACY`."""
        return DEFAULT_ACCURACY if self.accuracy is None else float(self.accuracy)

    @property
    def rewritten(self) -> bool:
        """Whether the engine runs lcchain's copy of the netlist, written from the cards' numbers (it runs no
        foreign netlist)."""
        return not engine_named(self.engine, "--engine").runs_foreign


def check_text(text: str, source: str = "netlist", folder: Path | None = None, options: CheckOptions | None = None,
               *, simulator: Simulator | None = None) -> CheckResult:
    """Run a netlist lcchain did not write and compare every saved vector with its exact response.

    Parameters
    ----------
    text : str
        The netlist (one ``.tran`` or ``.ac``); it must pass the allow-list, its includes in ``folder``.
    source : str
        Its name in messages.
    folder : Path, optional
        Where its includes are (and, with ``allow_control``, where it runs).
    options : CheckOptions, optional
        The accuracy, the engine, the timeout, whether its ``.control`` blocks run, the budget (default
        :class:`CheckOptions`).
    simulator : Simulator, optional
        The engine's simulator, found once by the caller (found here when omitted).

    Raises
    ------
    ParameterError
        Bad input: a line the allow-list refuses, a value that is not a number, a circuit that is not well
        posed (naming its elements), an engine that cannot run it.
    SimulatorMissingError, SimulationError
        From the run.
    """
    if options is None:
        options = CheckOptions()
    elif not isinstance(options, CheckOptions):
        raise ParameterError("options", options, "a CheckOptions")
    given = options.accuracy is not None
    accuracy_value = options.accuracy_value
    engine, timeout, allow_control, budget = options.engine, options.timeout, options.allow_control, options.budget
    found = engine_named(engine, "--engine")
    rewritten = options.rewritten
    allowed = canonical_text(text, source) if allow_control else allowed_netlist(text, source, folder, read_include)
    if simulator is None:
        simulator = find_engine(found.name)
    version_of = simulator.version
    analysis = analysis_of(allowed, source, lambda: version_of)
    cards = read_cards(allowed, source)
    circuit = circuit_of(cards, analysis)
    price = foreign_price(allowed, analysis, len(saved_vectors(allowed)), source)
    budget = budget if budget is not None else Budget()
    check_estimate(price, allowed, analysis, source).check(budget, "FILE", source, analysis.describe())
    limits = price.limits(budget, timeout)
    method = cards.method
    response, seconds = None, 0.0
    if not isinstance(circuit, str):  # solved before the run: what is not well posed is refused before it runs
        from ..circuit.linear import linear_response

        started = time.perf_counter()
        response = linear_response(circuit, ac=isinstance(analysis, Sweep))
        if isinstance(analysis, Transient):
            mismatch = response.initial_mismatch()
            if mismatch > 1e-9:
                raise ParameterError("initial state", f"{mismatch:.1e} of it outside the circuit's modes",
                                     "initial conditions consistent with the circuit's constraints")
        seconds = time.perf_counter() - started
    notes: tuple[str, ...] = ()
    if rewritten:
        if isinstance(circuit, str):
            raise ParameterError("--engine", engine, f"ngspice for a netlist with no exact reference ({circuit}): "
                                 f"{engine} runs only the netlist lcchain writes from a linear netlist's numbers")
        axis, vectors, wall, version, notes = _run_rewritten(allowed, cards, analysis, simulator, limits.timeout)
    else:
        axis, vectors, wall, version = _run(allowed, analysis, simulator, limits, folder if allow_control else None)
    names = [canonical_vector_name(n) for n in vectors]
    # the result without a reference: what the comparison, when there is one, completes
    unchecked = CheckResult(netlist=source, engine=simulator.engine, engine_version=version, analysis=analysis.kind,
                            method=method, points=int(axis.size), simulator_seconds=float(wall),
                            vectors=tuple(VectorCheck(n, _unit(n), None, None) for n in names),
                            accuracy=accuracy_value, accuracy_given=given)
    if isinstance(circuit, str) or response is None:
        return replace(unchecked, reference=str(circuit))
    if isinstance(analysis, Transient) and "interp" in dict(cards.options):
        notes = (*notes, ".options interp: ngspice's output is interpolated onto the TSTEP grid, whose error the "
                 "prediction (from the steps ngspice took) does not hold; without interp the vectors are its own "
                 "time points")
    return _compare(response, seconds, analysis, axis, vectors, names, unchecked, notes)


def _run_rewritten(allowed: str, cards: NetlistCards, analysis: Transient | Sweep, simulator: Simulator,
                   timeout: float) -> tuple[np.ndarray, dict[str, np.ndarray], float, str, tuple[str, ...]]:
    """An engine's run (gnucap's) of the netlist lcchain writes from the cards' numbers
    (:mod:`lcchain.spice.gnucap_check`), its vectors by ngspice's names."""
    from ..spice.gnucap_check import check_netlist, run_check

    functions = {}
    for card in cards.elements:
        if isinstance(card, SourceCard):
            found = source_function(card, analysis)
            if isinstance(found, str):  # the circuit was built, so its sources were read
                raise ParameterError("source", card.name, found)
            functions[card.name] = found
    names = list(dict.fromkeys(key for v in saved_vectors(allowed) for key in saved_names(v)))
    if isinstance(analysis, Sweep):
        count = analysis.count if analysis.spacing == "lin" else analysis.per
        written = check_netlist(cards, functions, 0.0, 0.0, 0.0, names,
                                sweep=(analysis.spacing, count, analysis.start, analysis.stop))
        how = "its AC sweep"
    else:
        written = check_netlist(cards, functions, min(analysis.step, analysis.max_step), analysis.stop,
                                analysis.start, names)
        how = f"at a fixed print step {written.step:.6g} s (dtmax the same), method=trap"
    run = run_check(written, analysis.tstop, simulator=simulator, timeout=timeout)
    renamed = ", ".join(f"{user.upper()}={own}" for user, own in written.names)
    note = (f"{simulator.engine} ran lcchain's copy of the netlist, written from its numbers ({renamed}; nodes "
            f"n1, n2...), {how}")
    return np.asarray(run.time), {k: np.asarray(v) for k, v in run.vectors.items()}, run.wall_s, \
        run.engine_version, (note,)


def _compare(response: LinearResponse, solve_seconds: float, analysis: Transient | Sweep, axis: np.ndarray,
             vectors: dict[str, np.ndarray], names: list[str], unchecked: CheckResult,
             notes_before: tuple[str, ...] = ()) -> CheckResult:
    """The result's comparison of the run's ``vectors`` with the exact ``response``: ``unchecked`` (the result
    without a reference, the accuracy and the method among its fields) completed."""
    from ..compare.check import predicted_errors, step_for_accuracy, vector_errors

    accuracy, method = unchecked.accuracy, unchecked.method

    started = time.perf_counter()
    found = {n: response.output(n) for n in names}
    outputs = {n: output for n, output in found.items() if output is not None}
    known = list(outputs)
    notes = [*notes_before, *(f"no exact reference for the vector {n} (not a node voltage or a branch current "
                              "lcchain models)" for n in names if n not in outputs)]
    if isinstance(analysis, Sweep):
        exact = response.ac([outputs[n] for n in known], axis)
        rounding = None
    else:
        exact, rounding_abs = response.transient([outputs[n] for n in known], axis, analysis.stop)
        rounding = rounding_abs
    seconds = solve_seconds + time.perf_counter() - started
    errors, scales = vector_errors([vectors[n] for n in known], exact)
    scales = _floored(scales, [_unit(n) for n in known])
    run_step = predicted = suggested = None
    predicted_each = np.full(len(known), np.nan)
    prediction = ""
    if isinstance(analysis, Transient) and known:
        steps = np.diff(axis)
        run_step = float(np.max(steps)) if steps.size else analysis.max_step
        selected = [outputs[n] for n in known]
        predicted_each = predicted_errors(response, selected, analysis.stop, run_step, method=method)
        predicted = float(np.max(predicted_each))
        largest = min(analysis.step, (analysis.stop - analysis.start) / 50)  # ngspice's own, without TMAX
        suggested = step_for_accuracy(response, selected, scales, analysis.stop, accuracy, method=method,
                                      largest=largest)
        prediction = _PREDICTED.get(method, f"{method}: no model of its error (the trapezoidal rule's is shown)")
        if rounding is not None and np.any(scales > 0) and rounding > accuracy * float(np.min(scales[scales > 0])):
            notes.append(f"the exact reference's rounding ({rounding:.1e}) is above the accuracy asked for")
    by_name = {n: k for k, n in enumerate(known)}
    checks = []
    for n in names:
        if n in by_name:
            k = by_name[n]
            checks.append(VectorCheck(n, _unit(n), float(errors[k]), float(scales[k]),
                                      None if np.isnan(predicted_each[k]) else float(predicted_each[k])))
        else:
            checks.append(VectorCheck(n, _unit(n), None, None))
    return replace(unchecked, vectors=tuple(checks), reference_seconds=seconds, states=response.states,
                   unknowns=response.unknowns, rounding=rounding, run_step=run_step, predicted_error=predicted,
                   suggested_step=suggested, prediction=prediction, notes=tuple(notes))


#: A vector's scale is at least this fraction of the largest of its unit: one that is zero by symmetry (a balanced
#: bridge's current, 1e-20 A of rounding) has no relative error of its own, nor a step to ask for.
SCALE_FLOOR = 1e-6


def _floored(scales: np.ndarray, units: Sequence[str]) -> np.ndarray:
    """Each vector's scale, at least :data:`SCALE_FLOOR` times the largest scale of its unit."""
    scales = np.asarray(scales, dtype=float).copy()
    for unit in set(units):
        same = np.array([u == unit for u in units])
        scales[same] = np.maximum(scales[same], SCALE_FLOOR * float(np.max(scales[same], initial=0.0)))
    return scales


def check_file(path: str | Path, options: CheckOptions | None = None) -> CheckResult:
    """:func:`check_text` of a netlist file (its includes inside its folder)."""
    path = Path(path)
    text = read_include(path, "NETLIST")
    return check_text(text, str(path), path.resolve().parent, options)


def reference_measurements(netlist: str, axis: np.ndarray, vectors: Mapping[str, np.ndarray], version: str, *,
                           trusted: bool = False, cwd: str | None = None) -> dict[str, tuple[float | None, str]]:
    """A batch run's check (:attr:`lcchain.runs.spec.RunSpec.check`): ``{CHECK_MEASUREMENT: (the largest error of
    its saved vectors against the exact response, "")}``, or (None, why there is none) -- a measurement, as a
    ``.meas`` card's, so that it is stored and shown with them."""
    try:
        text = canonical_text(netlist, "netlist") if trusted else \
            allowed_netlist(netlist, "netlist", Path(cwd) if cwd is not None else None, read_include)
        analysis = analysis_of(text, "netlist", lambda: version)
        circuit = circuit_of(read_cards(text, "netlist"), analysis)
        if isinstance(circuit, str):
            return {CHECK_MEASUREMENT: (None, f"no exact reference ({circuit})")}
        from ..circuit.linear import linear_response
        from ..compare.check import vector_errors

        response = linear_response(circuit, ac=isinstance(analysis, Sweep))
        found = {n: response.output(n) for n in vectors}
        modelled = {n: output for n, output in found.items() if output is not None}
        if not modelled:
            return {CHECK_MEASUREMENT: (None, "no saved vector lcchain models")}
        names, outputs = list(modelled), list(modelled.values())
        if isinstance(analysis, Sweep):
            exact = response.ac(outputs, axis)
        else:
            exact, _ = response.transient(outputs, axis, analysis.stop)
        errors, _ = vector_errors([np.asarray(vectors[n]) for n in names], exact)
        return {CHECK_MEASUREMENT: (float(np.max(errors)), "")}
    except ParameterError as error:  # not well posed: the run stands, its check says why
        return {CHECK_MEASUREMENT: (None, f"no exact reference ({error})")}
