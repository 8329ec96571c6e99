"""The option sets of lcchain, and the definition of its pulse, in one place.

Every set of allowed strings is a ``Literal`` alias here; the tuples of
allowed values are derived from them (``get_args``), never written again.
"""

from __future__ import annotations

from typing import Literal, get_args

#: Families of chains lcchain can build by name.
Case = Literal["one-mass", "two-mass", "uniform-free", "uniform-bounded", "perfect", "custom"]
#: How loop 1 (mass 1) is set in motion: an initial current (velocity) or charge (position).
Excitation = Literal["kick", "displacement"]
#: How ngspice is driven: ``ngspice -b`` subprocess, or the shared library through PySpice.
Backend = Literal["batch", "shared"]
#: How a simulator runs a netlist: a backend, or the warm shared-library workers a study may choose
#: (lcchain.spice.ngspice.warm); never part of a run's key.
Transport = Literal["batch", "shared", "warm"]
#: How normal modes are computed: exact diagonalisation or the paper's closed form.
ModeMethod = Literal["auto", "exact", "closed-form"]
#: The two optimised designs of the paper (Tables I and II).
DesignCase = Literal["one-mass", "two-mass"]
#: What sets loop 1 in motion in a scene or a response: the two initial conditions, or a voltage pulse.
ExcitationKind = Literal["kick", "displacement", "pulse"]
#: The pulse's shape g(t), of unit area: gaussian (standard deviation ``width``, centred at 4 width)
#: or rect on [0, width).
PulseShape = Literal["gaussian", "rect"]
#: Which loop currents are saved (and which loops a response returns): loops 1 and N, or every loop.
Probes = Literal["ends", "all"]
#: ngspice's integration method.
Method = Literal["trap", "gear"]
#: How ngspice chooses its steps: a fixed maximum step dt, or its own control up to tstop/50.
Stepping = Literal["fixed", "adaptive"]
#: The end of a chain whose loop current is compared: loop 1 or loop N.
End = Literal["first", "last"]
#: How a run ended: ngspice's waveforms passed validation, or not, or ngspice ran out of time; or, for a netlist
#: lcchain did not write, that it was refused before it ran (``lcchain batch``: the reason says why).
RunStatus = Literal["ok", "failed", "timeout", "refused"]
#: The IEC 60063 preferred-number series every L and C can be rounded to.
ESeries = Literal["E12", "E24", "E96"]
#: What of the first arrival a sensitivity or a worst case is about: the current peak max I_N / I_1(0), or the
#: energy fraction the last inductor holds there, peak^2 L_N / L_1 (not moved by a mismatch of the end inductors).
ArrivalMetric = Literal["peak", "energy"]
#: How ``sweep SCENE --worst-case`` finds the worst: a search over the whole tolerance box in exact theory (with
#: a certificate), or only the corners of the K parts that move the metric most (a quick look, not a search).
WorstCaseMethod = Literal["search", "corners"]
#: The pictures a scene can ask for: a transient's (overlay, spacetime, histogram of the transmitted peak) or an AC
#: analysis's (spectrum: Fig. Pk20-100's panels; spacing: the samples' delta omega_n against the nominal theory).
PlotKind = Literal["overlay", "spacetime", "histogram", "spectrum", "spacing"]
#: What a study's summary groups (``lcchain results --metric``): a transient's first arrival (peak, energy, loss) or
#: an AC run's spectrum (omega, P, spacing); :data:`lcchain.studies.summary.METRICS` says where each is read.
StudyMetric = Literal["peak", "energy", "loss", "omega", "P", "spacing"]
#: What a run's simulator computes: loop currents against time, or complex phasors against frequency.
AnalysisKind = Literal["transient", "ac"]
#: How an ``.ac`` card spaces its frequencies: evenly, or so many per decade or per octave.
AcSpacing = Literal["lin", "dec", "oct"]

CASES: tuple[Case, ...] = get_args(Case)
NAMED_CASES: tuple[Case, ...] = tuple(c for c in CASES if c != "custom")
EXCITATIONS: tuple[Excitation, ...] = get_args(Excitation)
WORST_CASE_METHODS: tuple[WorstCaseMethod, ...] = get_args(WorstCaseMethod)
BACKENDS: tuple[Backend, ...] = get_args(Backend)
TRANSPORTS: tuple[Transport, ...] = get_args(Transport)
#: How a study chooses each run's transport: by its predicted cost, a process per run, or warm workers.
TransportChoice = Literal["auto", "process", "warm"]
TRANSPORT_CHOICES: tuple[TransportChoice, ...] = get_args(TransportChoice)
MODE_METHODS: tuple[ModeMethod, ...] = get_args(ModeMethod)
DESIGN_CASES: tuple[DesignCase, ...] = get_args(DesignCase)
EXCITATION_KINDS: tuple[ExcitationKind, ...] = get_args(ExcitationKind)
PULSE_SHAPES: tuple[PulseShape, ...] = get_args(PulseShape)
PROBES: tuple[Probes, ...] = get_args(Probes)
METHODS: tuple[Method, ...] = get_args(Method)
STEPPINGS: tuple[Stepping, ...] = get_args(Stepping)
RUN_STATUSES: tuple[RunStatus, ...] = get_args(RunStatus)
E_SERIES_NAMES: tuple[ESeries, ...] = get_args(ESeries)
PLOT_KINDS: tuple[PlotKind, ...] = get_args(PlotKind)
ARRIVAL_METRICS: tuple[ArrivalMetric, ...] = get_args(ArrivalMetric)
ANALYSIS_KINDS: tuple[AnalysisKind, ...] = get_args(AnalysisKind)
AC_SPACINGS: tuple[AcSpacing, ...] = get_args(AcSpacing)
STUDY_METRICS: tuple[StudyMetric, ...] = get_args(StudyMetric)

#: The gaussian pulse g(t) is centred at GAUSSIAN_CENTRE standard deviations (netlist, theory and scenes).
GAUSSIAN_CENTRE = 4.0
#: The engine every run uses unless told otherwise (lcchain.spice.engines.ENGINES holds it first); records made
#: before there were engines hold its version alone.
DEFAULT_ENGINE = "ngspice"
#: Where a study's runs execute (lcchain.studies.executors).
ExecutorName = Literal["serial", "process", "dask"]
EXECUTORS: tuple[ExecutorName, ...] = get_args(ExecutorName)

#: The bulk inductance (henry) and capacitance (farad) of a ladder when none is given: 10 uH and 10 nF
#: (time unit sqrt(L0 C0) = 0.316 us, impedance sqrt(L0/C0) = 31.6 ohm), and the excitation's current (ampere).
DEFAULT_L0 = 10e-6
DEFAULT_C0 = 10e-9
DEFAULT_I0 = 1e-3

