"""Named tolerances shared by the tests, in one place (STYLE.md, "Tests").

A plain module of constants: import what you need, add what you must, and say
in a comment why each value is what it is.  Absolute tolerances (ATOL_*) apply
to dimensionless quantities of order one (masses and springs in bulk units,
mode densities, amplitudes, frequencies in units of sqrt(K/m)).

Mind the callers' defaults: pytest.approx(x, rel=R) also accepts |error| <= 1e-12 unless abs= is given, and
np.isclose / np.allclose add rtol=1e-5 and atol=1e-8 to whichever of the two is not given.  A tight RTOL_* on a
quantity in SI units (seconds, henries of order 1e-5 .. 1e-8) or an ATOL_* passed alone to np.allclose is
then looser than its value reads.
"""

# A handful of floating-point operations on parameters of order one (the
# formulas of Eqs. e.mKxyz and e.m1m2K12-rw) compared with exact fractions.
RTOL_ARITHMETIC = 1e-14

# The (x, y, z) and (r, w) views recomputed from masses and springs (square
# roots and quotients of O(1) numbers) against the parameters they came from.
ATOL_ROUND_TRIP = 1e-12

# sum_n P_n = 1 (Eq. e.Pn, orthogonality of U): LAPACK eigenvectors and the
# closed form of Eq. e.Pk are normalised to rounding, summed over <= 5000 modes.
ATOL_NORMALISATION = 1e-13

# alpha_N = 1 at the arrival time of a perfect chain (Sec. II.C), and the
# equal spacing of its frequencies: exact up to the rounding of a 5 x 5
# eigenproblem.
ATOL_PERFECT = 1e-12

# Paper's closed form (Eqs. e.kn1, e.psik, e.Pk) against exact diagonalisation
# for P_n, omega_n and alpha_N(t) on t in [0, 3N], N <= 5000: both are exact to
# rounding; the phases omega_n t reach ~1e4 rad at N = 5000 (observed ~2e-11).
ATOL_CLOSED_FORM = 1e-10

# cosine_sum's split-grid path against a direct sum of cosines: phases up to
# ~6e3 rad carry ~1e-12 absolute rounding in either evaluation.
ATOL_COSINE_SUM = 1e-12

# Modal transmission amplitude against a DOP853 integration with rtol 1e-11,
# atol 1e-13 over a few transits of a short chain (observed ~2e-12).
ATOL_ODE = 1e-9

# Arrival time of a perfect chain found by arrivals(): a bounded Brent search
# near a flat maximum (alpha - 1 ~ -(dt)^2), so the time is only determined to
# ~sqrt(rounding) of the peak value.
ATOL_ARRIVAL_TIME = 1e-6

# Table II prints s* to two decimals; the paper located s* by scanning the
# delay, so one unit of the last printed digit.
ATOL_TABLE_DELAY = 0.01

# Largest change of the phase shift psi_k between adjacent points of a
# 20001-point grid on [0, pi] that still counts as continuous (a branch jump of
# atan2 is 2 pi; the true slope moves psi by < 0.01 per step here).
MAX_PSI_STEP = 0.5

# psi'_k against a centred difference of psi_k with step 1e-6: truncation
# ~1e-12 psi''' and rounding ~1e-10, relative to the largest |psi'|.
RTOL_CENTRED_DIFFERENCE = 1e-6

# Table II prints delta* to five decimals: half a unit of the last digit (the
# optimum is flat, so the printed, rounded (r*, w*) do not move it further).
ATOL_TABLE_LOSS = 5e-6

# A fixed-point iteration counts as converged when its last step is below
# CONVERGED_STEP, and as failed when after many iterations its last step or its
# distance from the true root still exceeds NOT_CONVERGED_STEP.
CONVERGED_STEP = 1e-12
NOT_CONVERGED_STEP = 1e-3


# ------------------------------------------------------------ ngspice against theory (issue 3)
#: Perfect chains, dt = 0.005: the first arrival reaches 1 within this (issue: 1e-4).
ATOL_PERFECT_PEAK = 1e-4
#: Trapezoidal rule, fixed maximum step dt: measured max |I_N/I0 - alpha_N| over the
#: first transit of optimal two-mass chains is about 0.28 dt^2 (N = 20..1000);
#: the tests allow this factor times dt^2.
TRAP_ERROR_COEFFICIENT_FIRST_TRANSIT = 0.35
#: Same dimensionless waveform at any component scale (1 H/1 F, 10 uH/10 nF, 1 nH/1 pF).
ATOL_SCALE_INVARIANCE = 1e-6
#: A conserved quantity of the ideal ladder (sum L_i I_i of a free chain), relative.
RTOL_CONSERVED = 1e-9
#: Peak times from samples (parabola through 3 points at dt = 0.05) at different scales:
#: the peak is flat, so its time is known less well than its value.
ATOL_SCALE_INVARIANCE_TIME = 1e-5


# ------------------------------------------------------------ accuracy model and hard cases (issue 4)
#: Uniform warp alone (no start-up steps), N = 20 two-mass, one transit: ngspice's
#: start-up leaves a phase offset ~ dt^3 (measured 5.5e-5 at dt = 0.1, 3.9e-8 at dt = 0.01).
ATOL_WARPED_DT_0_1 = 1e-4
ATOL_WARPED_DT_0_01 = 1e-7
#: With ngspice's own steps and its backward-Euler start-up steps
#: (lcchain.accuracy.trap_response): measured 2e-14 .. 6e-13 (rounding).
ATOL_TRAP_MODEL = 1e-10
#: predicted_error against the achieved error (measured ratio 1.00 - 1.09 at dt <= 0.3).
PREDICTION_FACTOR = 1.5
#: Gear over trap error at the same step: issue 4 says 4 (measured 3.8 - 4.1 at dt <= 0.1).
GEAR_FACTOR_RANGE = (3.0, 5.0)
#: Trapezoidal rule keeps the ladder's energy (issue 4: to 1e-5 over 10 transits).
RTOL_ENERGY_TRAP = 1e-5
#: Gear at dt = 0.3 loses energy (issue 4: 12% over 10 transits); at least this much.
MIN_ENERGY_LOSS_GEAR = 0.02
#: A chain 1e-3 off the theory's chain shows at least this in the integration error.
MIN_INTEGRATION_ERROR_OF_A_BUG = 1e-5
#: Closed form against exact diagonalisation at extreme (r, w) (frequencies, mode densities).
ATOL_CLOSED_FORM_EXTREME = 1e-9
#: Sum of the mode densities.
ATOL_DENSITY_SUM = 1e-9
#: The same over ~2e5 steps (200 transits of the N = 4 chain at dt = 0.005): rounding of
#: ngspice's time accumulates (measured 1.3e-9).
ATOL_TRAP_MODEL_LONG = 1e-8


# ------------------------------------------------------------ scenes (issue 5)
#: analysis.accuracy of most scene tests: max |simulation - exact theory| allowed.
ACCURACY_COARSE = 1e-3
#: analysis.accuracy of the test with every effect combined.
ACCURACY_FINE = 1e-5
#: A theory with Q off by 20% (60 for 50) must miss by more than this: the comparison can fail.
MIN_ERROR_WRONG_THEORY = 1e-2


# ------------------------------------------------------------ exact linear response (issue 5)
#: Lossless kick/displacement through the same modes and cosine sums as
#: lcchain.modes (ends), or a second diagonalisation (all loops): rounding only.
ATOL_MODAL = 1e-12
#: Against DOP853 with rtol 1e-12, atol 1e-14 over ~20 time units of a
#: 5-mass chain: the integrator's global error (observed ~1e-11) dominates.
ATOL_RESPONSE_ODE = 1e-8
#: Momentum of a free chain against exp(-t/Q): one mode's closed form,
#: rounding only.
ATOL_MOMENTUM = 1e-12
#: A pulse of width 1e-3 (the narrowest lcchain takes) against the kick delayed to its centre and scaled by its
#: area: second order in the width, (w^2/2) |d^2 velocity / dt^2| with omega_max ~ 2 and losses as low as Q = 0.3
#: (observed 5.7e-8 lossless, 4.0e-6 at Q = 0.3).
ATOL_SHORT_PULSE = 1e-5
#: Rows 1 and N of loops="all" against loops="ends": two diagonalisations,
#: rounding only.
ATOL_LOOPS = 1e-12


# ------------------------------------------------------------ perfect cradles (issue 13)
#: A designed chain's frequencies, recomputed by an independent solver (numpy's dense SVD of the chain's
#: scaled incidence matrix), against the prescribed ones: the issue's 1e-10 relative (observed <= 2.4e-12 up
#: to N = 5000 with walls; the SVD resolves each to ~eps omega_max absolute).
RTOL_PERFECT_SPECTRUM = 1e-10
#: alpha_N(T) = 1 of a designed chain, from lcchain's exact diagonalisation (not the design's own check):
#: the issue's 1e-10 (observed ~1e-15 to 1e-12 up to N = 2000).
ATOL_PERFECT_TRANSFER = 1e-10
#: The algorithm's masses and springs for N = 3, 4, 5 against the paper's exact fractions: logs, exponentials
#: and square roots of O(1) numbers (observed ~2e-16).
RTOL_PERFECT_FRACTIONS = 1e-13


# ------------------------------------------------------------ coupled coils (issue 20)
#: The coupled chain's exact response against a DOP853 integration of M Q'' = -K Q (+ force) with rtol 1e-12,
#: atol 1e-13 over three transits of a short chain (observed 2e-13 .. 5e-12).
ATOL_COUPLED_ODE = 1e-9
#: A coupled chain's effect on the first arrival must be visible at k = 0.05 (the test's theory is not the
#: uncoupled one): the peak moves by more than this (measured ~1e-3 and more on the two-mass and perfect chains).
MIN_COUPLING_EFFECT = 1e-4


# ------------------------------------------------------------ the spectrum from an AC analysis (issue 21)
#: omega_n (relative) and P_n (absolute) from ngspice's AC response against an independent dense eigen-solution:
#: the issue's targets (measured 2e-10 .. 4e-15 for omega_n of the modes weighing |P_n| >= 1e-6, 2e-12 .. 2e-15 for P_n).
RTOL_SPECTRUM_OMEGA = 1e-9
ATOL_SPECTRUM_P = 1e-9
#: ngspice and gnucap on the same AC netlist: frequencies, and the median relative difference of the currents (both
#: solve the same complex linear system in double precision: measured 1e-15 and 2e-15 .. 4e-14).
RTOL_ENGINES_AC = 1e-12
#: With losses (Q = 10 .. 1e4 at N = 20, walls included): each decay rate gamma_n against 1/Q (absolute, units of
#: 1/sqrt(L0 C0): measured 3e-15 .. 3e-13, so Q_n = omega_n / gamma_n is good to about Q x 1e-13 relative), Q_n
#: (relative) against omega_n Q up to Q = 1000 (measured 3e-12 .. 3e-13), the poles (relative) against
#: -1/(2Q) + j sqrt(omega_n^2 - 1/(4Q^2)) (measured 1e-13 .. 5e-15); the fitted alpha_N(t) against the exact lossy
#: response over the first transit (absolute, measured 3e-15 .. 8e-14).  At N = 100 the fit reaches 1e-6 at
#: Q = 100 (benchmarks/spectrum.md).
ATOL_SPECTRUM_GAMMA = 1e-12
RTOL_SPECTRUM_Q = 1e-9
RTOL_SPECTRUM_POLE = 1e-9
ATOL_SPECTRUM_RESPONSE = 1e-9
#: The loop-1 fit from theory's poles (issue 32 item 5), started 1e-3 of a quarter gap off, against the dense
#: eigen-solution: omega_n (relative) of the modes weighing |P_n| >= 1e-6, and P_n (absolute) of every mode, on exact
#: samples and ngspice's (measured: omega <= 3.1e-14, P <= 1.7e-14): far inside the issue's targets above.
RTOL_SPECTRUM_FROM_THEORY_OMEGA = 1e-12
ATOL_SPECTRUM_FROM_THEORY_P = 1e-12
#: ... with losses (the fit from theory's lossy poles, started off in omega_n and Q), Q_n = omega_n / gamma_n (relative)
#: of the modes weighing |P_n| >= 1e-6 and at least 3 widths 1/Q from both neighbours: the issue's target (measured
#: 1e-12 .. 2e-10 on exact samples and ngspice's, N = 40 to 200, Q = 100 to 1e4); P_n (absolute) likewise (measured
#: up to 3e-13); omega_n is held to RTOL_SPECTRUM_OMEGA (measured up to 1.4e-10: a perfect cradle's modes near
#: |P_n| = 1e-6 at Q = 1e4, whose sharp resonances the samples place less well than lossless poles).
RTOL_SPECTRUM_FROM_THEORY_Q = 1e-8
ATOL_SPECTRUM_FROM_THEORY_LOSSY_P = 1e-11

# ------------------------------------------------------------ the circuit theory's hard cases (issue 30, item 6)
#: A well-conditioned hard case (self-resonance 1.001x the band top, ESL resonance at it, Q = 1 .. 1e6, coupling
#: 0.999 of its limit) at N <= 12 against expm of the state matrix or the uniform ladder's closed form: rounding
#: only (measured 2e-16 .. 9e-14 of I0).
ATOL_HARD_WELL_CONDITIONED = 1e-11
#: What the circuit theory promises where it accepts a case: its modal rounding is at most
#: lcchain.circuit.exact.MAX_MODAL_ROUNDING = 5e-10 and the error measured at most 0.98 times that estimate
#: (near-critical damping), and the N = 2000 ladder at k -> 1/2 is within 1e-9 (measured 2 eps cond(L) ~ 7e-10).
ATOL_HARD_ACCEPTED = 1e-9

# ------------------------------------------------------------ every effect exact (issue 30)
#: max |simulation - the circuit's exact theory| of a kicked N = 10 ladder at dt = 0.02 over its first transit,
#: whatever elements its effects add: the trapezoid's error, about TRAP_ERROR_COEFFICIENT_FIRST_TRANSIT dt^2 t
#: (~2e-3 at t = 12), with room for the extra elements' own (faster) time constants.
ATOL_EFFECT_RUN = 1e-2

# ------------------------------------------------------------ a circuit's own spectrum (issue 30, item 5)
#: The circuit's exact admittances (poles and residues) against the nodal equations solved at complex frequencies,
#: relative (measured 6e-13 .. 4e-12 at N = 4 .. 5, every real part, coupled, lossy; the nodal solve's own
#: conditioning near a pole is most of it).
RTOL_CIRCUIT_ADMITTANCE = 1e-10
#: An engine's AC run of a circuit with real parts against the circuit's exact poles and residues
#: (:func:`lcchain.compare.poles.fit_poles`): omega_n relative, P_n absolute, as a chain's (RTOL_SPECTRUM_OMEGA,
#: ATOL_SPECTRUM_P), and each mode's own Q_n = omega_n / gamma_n relative (measured: omega 1e-15 .. 2e-13, P and
#: the sections' coefficients 1e-16 .. 1e-13, gamma 4e-15 .. 9e-13 absolute at gamma ~ 0.2, N = 6 .. 8).
RTOL_CIRCUIT_SPECTRUM_OMEGA = 1e-9
ATOL_CIRCUIT_SPECTRUM_P = 1e-9
RTOL_CIRCUIT_SPECTRUM_Q = 1e-9
#: The chain's driven modes must miss the same circuit by more than this (relative omega): the comparison is
#: really against the circuit's poles (coil capacitance 0.05 C0 moves omega_n by 0.5 % .. 10 %).
CHAIN_MISSES_CIRCUIT = 1e-4

# ------------------------------------------------------------ the ladder as a two-port (issue 33, item 3)
#: S-parameters of a Touchstone file from two ngspice AC runs (written with 17 digits, read by scikit-rf) against
#: S from the circuit's exact phasors at the same frequencies: both are nodal solves exact to rounding (observed
#: 3e-14 for N = 8, 1.5e-13 with a coil capacitance, z0 = 50 and 75 ohm).
ATOL_TWO_PORT_S = 1e-9
#: The sparse phasor solve's currents against another exact theory of them, relative: the modal sum of a coil's
#: admittance times (1 + s^2 L C_p) (a coil capacitance across it), a closed form (a series RLC, a transformer):
#: both rounding (observed 5e-13 at most).
RTOL_PORT_CURRENT = 1e-9
#: A lossless ladder's S is unitary (S S^H = 1) to rounding (observed ~4e-15).
ATOL_UNITARY = 1e-12

# ------------------------------------------------------------ a foreign netlist's .meas results (issue 31)
#: An RC's .meas tran results against their closed forms, relative: ngspice prints 7 significant digits (5e-7),
#: the trapezoid at steps of 1/2000 of the time constant errs by ~(dt/RC)^2/12 = 2e-8, the measure's linear
#: interpolation between points as little, and the source's 1 ns edge shifts the response by 0.5 ns in 2 ms
#: (measured: 4e-8 and 9e-8).
RTOL_MEASURE_TRAN = 1e-5
#: An RC's .meas ac results against their closed forms, relative: linear interpolation in frequency (and in dB)
#: between the points of a sweep of 1000 per decade (each 0.23 % above the last) misses the -3 dB corner by
#: about (0.23 %)^2 / 8 of the curvature, well below this; 7 printed digits (measured: 5e-7 and 1e-7).
RTOL_MEASURE_AC = 1e-5
#: An RC low-pass's AC phasor, run from a sub-circuit, against 1 / (1 + j w RC): one complex solve per frequency,
#: stored as doubles; ngspice's gmin (1e-12 S) at each node shifts it by about R gmin = 2e-9.
RTOL_AC_LOWPASS = 1e-8

# The free perfect cradle's binomial end weights C(2N-2, N-n) / 2^(2N-3) (math.comb, one correctly rounded
# division) against LAPACK's m_1 u_1n u_Nn for N <= 20: the eigenvectors' rounding, a few eps (observed 3e-15).
ATOL_PERFECT_WEIGHTS = 1e-13

# The same binomials against 2^-(2N-3), the smallest of them: one rounding of an exact quotient.
RTOL_PERFECT_TAIL = 1e-12

#: The AC theory's own frequencies (lcchain.theory.exact.driven_modes, refined in extended precision) against an
#: independent 40-digit Sturm bisection, relative, every mode (measured 6e-17 .. 1.1e-16: float64's rounding).
RTOL_SHARP_REFERENCE = 1e-15
#: An AC run's omega_n against that reference, relative, lossless one-mass N = 150 and two-mass N = 37 in ngspice
#: (measured 5.3e-16 and 2.4e-16; LAPACK's frequencies alone read 2.5e-13 and 5.8e-15).
RTOL_SHARP_SPECTRUM = 2e-15

# ------------------------------------------------------------ worst case over the tolerance box (issue 32)
#: The search's worst against the test's own brute force over every corner: both evaluate the same exact
#: first-arrival peak (lcchain: eigenvectors and Newton on the peak time; the test: numpy.linalg.eigh of the
#: mass-spring matrices and Newton from a 200-point grid), which agree to ~1e-12; 1e-9 leaves room for the
#: eigensolvers' rounding of nearly degenerate chains without hiding a corner worse by 1e-6 (the closest
#: competing local optima of these chains differ by ~1e-5).
ATOL_WORST_CASE = 1e-9
#: The Hessian by central differences of the exact gradient at h = 1e-3 against h = 5e-4, relative to max |H|:
#: truncation ~ h^2 f''''/6 of O(1e-7) and rounding ~ 1e-13/h of O(1e-10).
RTOL_HESSIAN_STEP = 1e-5
#: A Hessian entry against second differences of the metric's values at step 1e-2 (truncation ~1e-4 f'''' h^2,
#: rounding ~1e-16/h^2 = 1e-12), relative to max |H|.
RTOL_HESSIAN_VALUES = 1e-3

# ================================================================== tolerances that were written inline (issue 34, item 6)
# Each of these was a literal in one test; the number is unchanged, the comment says what it compares.

# ------------------------------------------------------------ settings of the tests' own reference integrations
# Not tolerances of a comparison but what the comparison's tolerance rests on: scipy's DOP853, asked for far more
# accuracy than the tolerance it serves, so that the integrator's global error stays below that tolerance.
#: Modal transmission amplitude (ATOL_ODE): a few transits of a short chain in bulk units.
RTOL_DOP853_TRANSMISSION = 1e-11
ATOL_DOP853_TRANSMISSION = 1e-13
#: Kick and pulse responses of the lossy chain (ATOL_RESPONSE_ODE); states of order one.
RTOL_DOP853_RESPONSE = 1e-12
ATOL_DOP853_RESPONSE = 1e-14
#: The coupled chain's M Q'' = -K Q (ATOL_COUPLED_ODE); states of order one.
RTOL_DOP853_COUPLED = 1e-12
ATOL_DOP853_COUPLED = 1e-13
#: helpers/state_space.py integrates the cards' own state equations in SI units (coil currents of ~1e-3 A, far
#: smaller capacitor charges), so the absolute floor is put far below any state and the relative one governs.
RTOL_DOP853_CARDS = 1e-12
ATOL_DOP853_CARDS = 1e-20

#: An absolute floor far below every value compared, so that only the relative tolerance counts: pytest.approx's
#: default floor (1e-12) would otherwise accept any error of values that are themselves ~1e-15, and
#: assert_allclose states it so the reader need not remember that its default is 0.
ATOL_NO_FLOOR = 1e-300

# ------------------------------------------------------------ the same arithmetic done twice
#: A value against the same one or two multiplications or quotients written out in the test (L0 m_i, C0 / K_i,
#: t sqrt(L0 C0), a function called twice): at most a rounding or two of eps = 2.2e-16.
RTOL_ONE_OPERATION = 1e-15
#: A number lcchain wrote into a netlist in SI units (repr: exact round trip) against the test's product of the
#: bulk value and its unit: the same few multiplications in another order, a few eps.
RTOL_NETLIST_VALUE = 1e-14
#: The netlist's .tran TMAX against 0.05 sqrt(L0 C0): one product and a square root, repr round trip exact.
RTOL_NETLIST_TMAX = 1e-15
#: A step halved by lcchain (TMAX of the second run of an extrapolation) against the first run's over two, read
#: back from the two netlists: both pass through the bulk-to-SI conversion.
RTOL_HALVED_STEP = 1e-12
#: A report's SI units (time unit sqrt(L0 C0), frequency unit 1 / (2 pi sqrt(L0 C0))) against the test's own
#: formula on the report's L0 and C0 after a JSON round trip: a few roundings.
RTOL_SI_UNITS = 1e-12
#: omega_1 t_arrival = pi of a designed perfect chain, read from `lcchain perfect --json`: the design's own
#: frequencies and arrival time, a few roundings apart.
RTOL_ARRIVAL_TIMES_OMEGA = 1e-12
#: A figure's plotted line data (k = 2 arcsin(omega / 2), N P_n, (N / pi) delta omega_n) against the same
#: formulas on the check's modes after a JSON round trip: rounding of arcsin and of differences of nearby
#: frequencies (absolute floor for k near 0).
RTOL_PLOTTED = 1e-12
ATOL_PLOTTED = 1e-15
#: A check's largest error recomputed in the test from the modes it lists (max over modes of |value - theory|,
#: relative for omega) against the one the check stored: the same numbers, computed in another order.
RTOL_RECOMPUTED_ERROR = 1e-9
#: The mean of a few samples' peaks from a summary (or a stored spread) against numpy's mean of the same peaks:
#: a sum of a few O(1) numbers in another order.
RTOL_MEAN_OF_SAMPLES = 1e-12
#: Their standard deviation against numpy's: the spread is small against the mean, so subtracting the mean
#: cancels digits and the rounding of the sums grows by as much.
RTOL_STD_OF_SAMPLES = 1e-9
#: relative sensitivity = derivative x value, recomputed in the test from the part's derivative and value.
RTOL_RELATIVE_SENSITIVITY = 1e-12
#: The peak that peak_sensitivity reports against first_arrival's peak of the same chain: the same search,
#: possibly on separately computed modes (rounding).
ATOL_SAME_PEAK = 1e-12
#: response(t) of a CircuitResponse in units of I0 against the exact circuit's currents in amperes divided by
#: I0 (currents of order one after the division): one division.
ATOL_RESPONSE_IN_I0 = 1e-15
#: A DC sweep's and an operating point's currents from ngspice's binary raw file against -V / R: one linear solve
#: per point, stored as doubles (the absolute floor for the sweep's 0 V points).
RTOL_DC_SOLVE = 1e-12
ATOL_DC_SOLVE = 1e-15
#: Two unconnected ports each loaded by 1 / z0 give S = 0 and open ports S = 1: one 2 x 2 solve of exact numbers.
ATOL_S_EXACT_PORTS = 1e-15
#: The exact BOM's inductances against the chain's L0 m_i: the BOM groups parts by their value printed to
#: 12 significant digits (lcchain.circuit.bom), a rounding of 5e-13.
RTOL_BOM_VALUE = 1e-11
#: A value lcchain rounded to the E12 series, scaled by L0, found again on the series by preferred_value:
#: the scaling's rounding only.
RTOL_E_SERIES_VALUE = 1e-12
#: A sampled part's mantissa (value / 10^floor(log10 value)) against the E24 table: the division by a power of
#: ten rounds (np.isclose's default atol of 1e-8 also applies).
RTOL_E24_MANTISSA = 1e-9
#: dt given as np.float32(0.05) reaches the options as a float: float32 holds 0.05 only to 1.5e-8 relative
#: (float32's eps is 1.2e-7, so any float32 value is within 6e-8 of the decimal it was written as).
RTOL_FLOAT32 = 1e-7
#: The last frequency of an ngspice 39 .ac dec sweep against FSTOP: ngspice computes its frequencies from the
#: start and the step ratio, so the last one can miss FSTOP by a few roundings.
RTOL_AC_SWEEP_STOP = 1e-12
#: gnucap's last time point against tstop: gnucap reaches tstop by its own steps and prints its times as text.
RTOL_GNUCAP_TSTOP = 1e-9
#: tstop / h a whole number for gnucap's shortened step h read back from its netlist text.
ATOL_WHOLE_STEPS = 1e-9
#: A scene's kept CSV: its last time against the plan's tstop, the CSV's numbers being written as text.
RTOL_CSV_TIME = 1e-9
#: A transient's point count grows a thousandfold with a thousandfold smaller step, up to the fence post
#: (10001 against 10000001 points, 9e-4).
RTOL_POINTS_RATIO = 1e-3

# ------------------------------------------------------------ circuits and their closed forms
#: Two series coils, only the first carrying a current: both carry L1 I0 / (L1 + L2) at once (flux conserved),
#: from the circuit theory's projection of the initial state: rounding.
RTOL_FLUX_SHARING = 1e-12
#: Coupled initial currents (flux over inductance, k sqrt(L1 L2) I1 / L2) against the formula written out: a
#: few multiplications.
RTOL_COUPLED_INITIAL_CURRENT = 1e-15
#: A diode's reverse-biased output against (gmin x 5 V + IS) x R: the test's estimate keeps only gmin and IS
#: through the load; a part in a thousand is left for what it leaves out.
RTOL_REVERSE_LEAKAGE = 1e-3

# ------------------------------------------------------------ the accuracy model
#: The warped frequencies (2/dt) atan(omega dt / 2) against their series omega - omega^3 dt^2 / 12 for
#: omega <= 2, dt = 0.01.  The next term, omega^5 dt^4 / 80, is 4e-9 at omega = 2 (observed 4.0e-9), above this
#: value: the test passes through np.allclose's default rtol of 1e-5, which it does not state.
ATOL_WARP_SERIES = 1e-9
#: trap_response against its closed form (two backward-Euler start-up steps, each shrinking a mode by
#: 1 / sqrt(1 + (omega dt)^2), then the warped frequencies) over 2000 steps: rounding only (observed 2.7e-15
#: for the two-mass N = 20 chain at dt = 0.05).
ATOL_TRAP_STARTUP_CLOSED_FORM = 1e-12
#: Once ngspice equals its trapezoidal model to ATOL_TRAP_MODEL, the model's own (physics) error equals the run's
#: error against the theory: they differ by at most the integration error, far below the errors themselves.
RTOL_PHYSICS_ERROR_IS_TOTAL = 1e-6
#: A chain 1e-3 off the theory's chain: the error of the step (model against its own chain) hardly moves.
RTOL_STEP_ERROR_OF_A_BUG = 0.05

# ------------------------------------------------------------ arrivals and peaks
#: The perfect N = 4 chain's later arrivals (up to the 200th transit) from arrivals(): a Brent search near a flat
#: maximum resolves the time to ~sqrt(eps) |t| (ATOL_ARRIVAL_TIME is the first arrival's), and the peak to ~eps.
ATOL_LATER_ARRIVAL_TIME = 1e-5
ATOL_LATER_ARRIVAL_PEAK = 1e-9
#: A designed perfect chain's first arrival time from arrivals() against the design's t_arrival: the same flat
#: maximum, relative.
RTOL_DESIGNED_ARRIVAL_TIME = 1e-6
#: maximum_in_window's time against scipy's bounded search with xatol 1e-10 x the window: both near a flat
#: maximum, so the times agree only to ~sqrt(eps).
ATOL_PEAK_TIME_SEARCH = 1e-9
#: A perfect cradle's peak read from `lcchain sensitivity --json` (Sec. II.C: 1).
ATOL_SENSITIVITY_PERFECT_PEAK = 1e-9
#: The simulated first arrival time of a perfect chain (samples at dt = 0.005, a flat maximum) against Sec. II.C's.
ATOL_SIMULATED_ARRIVAL_TIME = 0.01
#: A scene's CSV near t* = sqrt(3) pi at dt = 0.01: the largest sample (within 0.05 of t*) of the perfect N = 4
#: chain's far-end current against 1: the trapezoid's error and the sampling of the peak.
ATOL_CSV_PEAK = 1e-3
#: A rectangular pulse of width 0.02 arrives width / 2 after the kick: two simulated peak times, each from
#: samples near a flat maximum.
ATOL_PULSE_DELAY = 0.05
#: The far end of a free N = 20 chain over one transit oscillates about its DC level I0 m_1 / M = I0 / 20; the
#: oscillation does not average out in one transit.
ATOL_DC_LEVEL = 0.02
#: A plot's marker at (t, peak) of an arrival, in data units of order one: the tolerance only picks the
#: marker out among the lines.
ATOL_MARKER_POSITION = 0.02

# ------------------------------------------------------------ sensitivities
#: The peak's change at a tolerance corner (5 % coils, 2 % capacitors) against the first-order prediction: the
#: second-order terms are ~tol^2 / tol = a few per cent of it.
RTOL_FIRST_ORDER_CORNER = 0.05

# ------------------------------------------------------------ the lossy response's basis (Eqs. of lcchain.theory.response)
#: The critically damped mode's second basis function against -expm1(-2t) / 2: the same expm1, a rounding or two.
RTOL_EXPM1_BASIS = 1e-15
#: The overdamped mode's basis against (e^(s1 t) -+ e^(s2 t)) / (s1 - s2) or / 2: different formulas for the
#: same exponentials, exponents up to ~4 t, relative.
RTOL_OVERDAMPED_BASIS = 1e-13

# ------------------------------------------------------------ asymptotics (Sec. IV, V)
#: The analytic integrand against g cos(phase): the phase reaches 1.2e4 rad at xi = 50, where rounding alone
#: costs ~1e-12.
ATOL_INTEGRAND_PHASE = 1e-12
#: The asymptotic amplitude at tau = +-1e-9 against its tau = 0 branch: continuity, with room for the two
#: evaluations' own numerical error (the shift itself moves the amplitude by ~1e-9).
ATOL_CONTINUITY_AT_TAU_ZERO = 1e-5
#: The asymptotic optimum against the stored regression values (OURS in test_asymptotic.py): BFGS stops at a
#: gradient of 1e-6; alpha sits at the maximum (error quadratic in the position), sigma and tau only linearly.
ATOL_OPTIMUM_ALPHA_REGRESSION = 1e-13
ATOL_OPTIMUM_SIGMA_REGRESSION = 1e-9
ATOL_OPTIMUM_TAU_REGRESSION = 1e-10

# ------------------------------------------------------------ the design algorithms (Sec. II.C, issue 13)
#: spectrum_of (lcchain's eigen-solution) against an SVD of the chain's incidence matrix, N = 40: rounding of two
#: dense solvers.
RTOL_SPECTRUM_OF_AGAINST_SVD = 1e-12
#: The Stieltjes recursion against Newton continuation for the same frequencies: two algorithms, each to
#: rounding amplified by the recursion.
RTOL_STIELTJES_NEWTON = 1e-11
#: The 4-mass cradle's masses and springs (perfect_design(4)) against 5/3, 1, 5/6: a rounding or two.
RTOL_CRADLE4_FRACTIONS = 1e-15
#: Its arrival time against sqrt(3) pi.
RTOL_CRADLE4_ARRIVAL = 1e-13
#: Its velocities at t = 0 against the unit kick of mass 1: the modal sum at t = 0 (sum of P_n), rounding.
ATOL_KICK_AT_ZERO = 1e-13
#: T lies on the figure's time grid (np.linspace to transits T): linspace's rounding.
RTOL_GRID_POINT = 1e-14

# ------------------------------------------------------------ the paper's tables and figures
#: Table I / II optima found by lcchain's optimisers against the perfect chains' exact x = sqrt(2/3) and
#: (r, w) = (10/11, 6/11): the optimisers stop at xatol ~1e-7 (lcchain.theory.design) at a flat optimum.
ATOL_OPTIMISER_X = 1e-7
ATOL_OPTIMISER_RW = 1e-6
#: Table II prints r* to four decimals: half a unit of the last digit.
ATOL_TABLE_R = 5e-5
#: Sec. V.A prints alpha = 0.987153: half a unit of the sixth decimal.
ATOL_PRINTED_ALPHA = 5e-7
#: sum_n P_n = 1 of a figure's panels (Figs. vk, pk, N <= 100): the densities are normalised to rounding.
ATOL_FIGURE_DENSITY_SUM = 1e-12
#: Fig. pk's P_n against normal_modes(method="exact") of the same chain, N = 20 and 100: rounding.
ATOL_FIGURE_DENSITY = 1e-12
#: Fig. rw: w(r*) is almost w* for N >= 20 (the quartic mode density); not equal, the figure shows the gap.
RTOL_W_OF_R_STAR = 0.03
#: The fitted r* ~ c N^p law against c = 4.387 (printed to four digits) and p = -1/3.
RTOL_POWER_LAW_FIT = 1e-3
#: The trapezoid area of the asymptotic weight on the figure's zeta grid against 1: the grid's truncation.
ATOL_WEIGHT_AREA = 1e-6
#: theta / xi^3 of the printed pair at small xi against its cubic coefficient 4 sqrt2 / 3: the next term is
#: O(xi^2) smaller.
RTOL_CUBIC_COEFFICIENT = 1e-4
#: The flat-dispersion Delta found by a root finder: its left side against 1/8 at the root.
RTOL_ROOT_RESIDUAL = 1e-12
#: That Delta against the finding's quoted 0.325 (three decimals).
ATOL_QUOTED_FLAT_DELTA = 1e-3
#: Fig. minimiz: the minimum of delta over tau at a given sigma, found by two searches (the figure's against
#: asymptotic_optimum, or its quick against its full path): at a flat minimum the values agree to ~the square
#: of the positions', which agree only to ATOL_MINIMIZ_TAU and ATOL_MINIMIZ_TAU_QUICK.
ATOL_MINIMUM_DELTA = 1e-9
ATOL_MINIMIZ_TAU = 1e-5
ATOL_MINIMIZ_TAU_QUICK = 1e-4
#: The smallest end weight of the perfect N = 100 chain, -2^-197 = -4.98e-60, against -5.0e-60 written to two
#: digits (the test checks the sign).
RTOL_TWO_DIGITS = 1e-2

# ------------------------------------------------------------ random draws
#: The sample standard deviation of 4000 normal draws against the distribution's: its own relative standard
#: error is 1 / sqrt(2 (n - 1)) = 1.1 %, so this is ~9 standard errors (a seeded draw, never flaky).
RTOL_SAMPLE_STD = 0.1


# ================================================================== bounds that were written inline in asserts (issue 34, item 6)
# ------------------------------------------------------------ perfect chains
#: delta = 1 - alpha_N(T) of a designed perfect N = 40 chain, from `lcchain design --json`: exact diagonalisation,
#: rounding only (ATOL_PERFECT_TRANSFER allows 1e-10 for N up to 2000).
ATOL_DESIGNED_LOSS = 1e-12
#: Table II, N = 4: the two-mass optimiser's optimum is the perfect chain, so its loss is 0 to rounding.
ATOL_PERFECT_OPTIMUM_LOSS = 1e-12
#: The spread of the normalised spacings of a perfect chain's AC frequencies (equally spaced, Sec. II.C): the AC
#: fit's omega_n are good to RTOL_SPECTRUM_OMEGA, so the spread of ~N of them is far below this.
ATOL_PERFECT_SPACING_SPREAD = 1e-6
#: A perfect chain's simulated run ends at the end of its last arrival's window (3.5 transits), not later: the
#: window end is a product of doubles, so ngspice's last time may sit a rounding beyond it.
RTOL_WINDOW_END = 1e-9

# ------------------------------------------------------------ simulations against theory
#: ngspice's far-end current before the pulse can reach it (N = 2000): zero in the ideal ladder, and the
#: simulator's solution holds only rounding there.
ATOL_BEFORE_ARRIVAL = 1e-12
#: The first samples of a run: the far end starts at 0 and the near end at 1 (a swapped probe would be O(1));
#: the first sample is at most a step into the run.
ATOL_PROBES_AT_START = 1e-3
#: A simulated two-mass N = 20 run at dt = 0.05 against transmission_amplitude over its default window: a probe
#: or sign bug would be O(1); the trapezoid's error is ~TRAP_ERROR_COEFFICIENT_FIRST_TRANSIT dt^2 per transit.
ATOL_RUN_AGAINST_MODES = 0.01
#: A pulse run whose step resolves the pulse (dt = width / 8) against the exact theory: no model predicts this
#: error; the trapezoid's error over one transit at that step is ~1e-3.
MAX_PULSE_RUN_ERROR = 2e-3
#: The sweep's default runs (two-mass, N = 20, its default step), each against its exact theory.
MAX_SWEEP_RUN_ERROR = 2e-3
#: gnucap's two-mass N = 20 run at dt = 0.05 against theory: the trapezoid's error, about
#: TRAP_ERROR_COEFFICIENT_FIRST_TRANSIT dt^2 times the transits (8.75e-4 per transit).
MAX_GNUCAP_ERROR_DT_0_05 = 2e-3
#: Two engines integrating one circuit with the same rule differ by far less than either differs from theory.
MAX_ENGINE_DIFFERENCE_FRACTION = 0.1
#: A circuit's trapezoidal run (N = 8 two-mass, real parts, dt = 0.01) against the circuit's exact theory,
#: in units of I0: the trapezoid's error over 16 time units, well under a percent.
MAX_FINE_CIRCUIT_RUN_ERROR = 2e-3

# ------------------------------------------------------------ the circuit's exact theory (issue 30)
#: CircuitTheory against expm of the state matrix (small ladders, coupled, lossy, coil capacitance), in units of
#: I0: two exact methods, rounding of a modal sum and of a matrix exponential over ~4 N time units.
RTOL_CIRCUIT_AGAINST_EXPM = 1e-11
#: CircuitTheory's currents or charges (in I0, I0 sqrt(L0 C0)) against the chain's own exact response, lossless or
#: with losses: rounding.
ATOL_CIRCUIT_AGAINST_CHAIN = 1e-12
#: A coil split into two halves in series against the whole coil: the same circuit, rounding (units of I0).
RTOL_SPLIT_COIL = 1e-12
#: CircuitTheory driven by a gaussian source against DOP853 on the cards' state equations (RTOL_DOP853_CARDS)
#: over 15 time units, in units of I0: the integrator's global error.
RTOL_CIRCUIT_AGAINST_DOP853 = 1e-9
#: A floating group of capacitors grounded through eps C0 (eps = 1e-6): the reference moves first order in eps,
#: so it is within ~10 eps of the circuit theory (units of I0).
MAX_GROUNDED_GROUP_ERROR = 1e-5
#: The response at t = 0 in units of I0: the kick puts I0 in L1 exactly, the modal sum returns it to rounding.
ATOL_CIRCUIT_KICK_AT_ZERO = 1e-12
#: The effect cost's peak_circuit against the first arrival's peak of the same circuit theory: the same search on
#: the same theory, to its resolution.
ATOL_CIRCUIT_PEAK_IS_THEORY = 1e-9
#: peak_ideal (a search for alpha_N's maximum) against the maximum of alpha_N on a 4001-point grid over
#: +-20 % of t_ideal: a grid misses a flat maximum by about its spacing squared.
ATOL_IDEAL_PEAK_ON_GRID = 1e-6

# ------------------------------------------------------------ extrapolation (issue 23)
#: ngspice against its trapezoidal model for each member of an extrapolation (N = 100 .. 1000, steps down to
#: ~1e-3): rounding accumulated over the members' many steps (ATOL_TRAP_MODEL is one short run's).
ATOL_TRAP_MODEL_MEMBERS = 1e-9
#: Putting the members on one grid costs under a thousandth of the accuracy asked for.
RTOL_INTERPOLATION_OF_ACCURACY = 1e-3
#: lcchain's own theory against the test's independent exact solution: their difference is under a thousandth
#: of the accuracy asked for, so the achieved error is the run's.
RTOL_THEORY_OF_ACCURACY = 1e-3
#: A member's time points against the aligned grid, relative to tstop: the grid is written to the netlist as
#: doubles and ngspice's times accumulate rounding.
RTOL_ALIGNED_GRID = 1e-9

# ------------------------------------------------------------ sensitivities, requirements
#: Scaling every mass (or every spring) only rescales time, so the relative sensitivities sum to zero: rounding
#: of N terms of size up to the largest.
RTOL_SCALING_IDENTITY = 1e-12
#: `lcchain requirements --check`: the simulated loss against the theory's, at the found tolerance of a part:
#: a small absolute part for the run's own error plus a per cent of the loss for the first-order model.
ATOL_REQUIREMENT_LOSS = 1e-3
RTOL_REQUIREMENT_LOSS = 0.01
#: A finite-difference check's error bar, relative to the sensitivity itself: tight enough that a wrong sign
#: or factor fails.
MAX_ERROR_BAR_FRACTION = 1e-3

# ------------------------------------------------------------ figures
#: (N/pi)(omega_(n+1) - omega_n) at mid-k against v_k (Eq. e.vk), from the closed-form modes (Fig. vk) or from
#: ngspice's AC frequencies (the report's spectrum figure): a centred difference of omega(n), O(1/N^2)
#: (observed 4e-3 at N = 50).
ATOL_GROUP_VELOCITY = 1e-2
#: Fig. pk: the N = 100 panel's first ten normalised spacings against 0.95, flat near k = 0 (the caption's point).
ATOL_FLAT_SPACING = 0.03
#: theta / xi^5 of the pair that cancels the linear and cubic terms stays bounded as xi halves: its spread is
#: within a per cent of its size, plus a floor where it is near zero.
RTOL_THETA_RATIO = 1e-2
ATOL_THETA_RATIO = 1e-3
#: A law drawn on a figure picked out among its lines by matching c x^p on its own points: the same formula,
#: rounding only.
ATOL_LAW_ON_PLOT = 1e-12
#: The perfect chains' simulated first-arrival loss in a study's summary: positive (the trapezoid's error) and small.
MAX_PERFECT_RUN_LOSS = 1e-3
#: The paper's printed optimum (tau, sigma to four or five digits) lies below ours: rounding the position of a
#: flat maximum costs alpha about the square of the rounding (observed 4.1e-8 one-mass, 5.1e-9 two-mass).
PAPER_OPTIMUM_SHORTFALL_RANGE = (1e-9, 1e-7)
#: A drawn part within its tolerance (a capacitor C = C0 / K inverting the drawn factor, a study's part against
#: its nominal E24 value): the quotient's rounding may cross the bound.
RTOL_TOLERANCE_BOUND = 1e-12
#: The trapezoidal rule's error coefficient (max error / dt^2 over one transit of optimal two-mass chains, issue 4:
#: 0.28), predicted or fitted, is at least this (TRAP_ERROR_COEFFICIENT_FIRST_TRANSIT is its upper bound).
MIN_TRAP_ERROR_COEFFICIENT_FIRST_TRANSIT = 0.2
#: |alpha_N(t)| <= 1 (energy) of the closed form on hard cases near the arrival: 1 plus the closed form's
#: rounding at extreme (r, w) (ATOL_CLOSED_FORM_EXTREME).
ATOL_AMPLITUDE_BOUND = 1e-9
#: An asymmetric 5-mass chain at dt = 0.01 over two transits against its exact modal theory: the trapezoid's
#: error (~TRAP_ERROR_COEFFICIENT_FIRST_TRANSIT dt^2 a transit); symmetric-chain formulas would miss by O(1).
MAX_ASYMMETRIC_RUN_ERROR = 5e-4
#: The mean of n seeded random draws lies within this many standard errors (sigma / sqrt(n)) of the
#: distribution's mean: a 4-sigma miss has probability 6e-5, and the draws are seeded, so never flaky.
MAX_STANDARD_ERRORS = 4

# ------------------------------------------------------------ `lcchain check` of a foreign netlist (issue 34)
#: The check's linear response of a series RLC band-pass in AC against the impedance written out by hand,
#: 10 / (60 + s L + 1 / (s C)): one complex solve per frequency against one complex quotient, rounding.
RTOL_CHECK_AC_BY_HAND = 1e-12
#: `lcchain check --json` of that AC sweep: ngspice's phasors against the check's linear response of the same
#: cards, largest relative error: both solve the same complex linear system in double precision.
RTOL_CHECK_AC = 1e-12
#: The check's error stored by `lcchain batch --check` (a measurement in the store) against a direct check of the
#: same netlist: two ngspice runs of one file, the same largest error.
RTOL_STORED_CHECK_ERROR = 1e-6
#: The check's reference at t = 0 against the elements' IC= (0.5 V on the capacitor, 1 mA in the coil) under
#: uic: the initial state itself, rounding in volts and in amperes.
ATOL_IC_VOLTAGE = 1e-12
ATOL_IC_CURRENT = 1e-15

# ------------------------------------------------------------ figures (continued)
#: Fig. delta's spline through a case's points, read back by linear interpolation in log N between the curve's
#: own samples, against the points it passes through, relative to the largest: the interpolation's error.
RTOL_SPLINE_AT_POINTS = 2e-3
#: gnucap's AC phasors of the same band-pass (read back at numdgt=20: the doubles gnucap holds) against the
#: impedance written out by hand, and `lcchain check --engine gnucap`'s largest relative error against the
#: check's linear response: gnucap's own complex solve in double precision.
RTOL_CHECK_AC_GNUCAP = 1e-11

# The paper's relations among (x, y, z), the masses and the springs (Eqs. e.BN, e.xyz, e.mKxyz), evaluated by hand
# both ways on O(1) parameters: a dozen operations each, so agreement to rounding; K01 = 0 at z = z0 is a
# difference of O(1) terms, zero to the same rounding (tests/test_paper_reading.py).
RTOL_PAPER_ALGEBRA = 1e-12
ATOL_PAPER_ALGEBRA = 1e-12

# Issue 32's targets for a survey of every loop (lcchain.runs.survey): each omega_n relative, each M-orthonormal
# shape's largest error over the loops relative to its largest entry, each Q_n relative (modes at least 3 widths
# apart).  Measured well inside them (omega ~1e-14, shapes ~1e-12 .. 1e-8 at N <= 1000: benchmarks/spectrum.md).
RTOL_SURVEY_OMEGA = 1e-9
RTOL_SURVEY_SHAPE = 1e-7
RTOL_SURVEY_Q = 1e-8
# Every loop's current against the chain's exact one over a survey's sweep, max_w max_k |g_k - exact| / max_k |exact|
# (lcchain.theory.spectrum.loop_currents, float64): what modes merged by the losses are measured by.  Measured
# 1e-14 .. 1.1e-12 at N <= 100 on ngspice; the float64 reference alone is off by 2.9e-12 / 3.6e-11 / 1.1e-10 from a
# long double one at two-mass N = 100 / 400 / 1000, Q = 1000 (benchmarks/spectrum.md), so a survey of N <= 40 sits
# two decades inside this.
RTOL_SURVEY_CURRENTS = 1e-10
# lcchain.theory.spectrum.loop_currents (the tridiagonal eliminated from loop 1) against numpy.linalg.solve of the
# dense K - omega^2 M + j omega M / Q, with losses (Q <= 1000, N <= 16, 3001 frequencies across the band): both are
# float64 solves of the same matrices, measured 1.4e-13 .. 2.4e-13 apart (largest over the loops relative to the
# largest); a hundredfold of headroom for the peaks' conditioning.
RTOL_LOOP_CURRENTS = 1e-11

#: Issue 32 item 2: each AC comparison's reference is at least this many times sharper (its own stated bound) than
#: the error it lets be measured (measured: omega 5.4x10^1 .. 1.6x10^2, P 2.6x10^1 .. 1.2x10^1 on one-mass N = 150
#: and two-mass N = 37).
REFERENCE_MARGIN = 10.0
#: Digits of the test's own decimal reference (Sturm bisection and the eigenvector's three-term recurrence): far
#: beyond the bounds it checks (about 1e-18 relative on omega_n, 1e-16 absolute on P_n).
DECIMAL_DIGITS = 50
#: A lossy AC run's Y_11 against the chain's exact admittance (lcchain.theory.spectrum.driving_admittance, a
#: continued fraction in extended precision), relative, every frequency of the sweep: what is measured however
#: the modes merge (measured 1.3e-14 .. 1.7e-14, two-mass N = 37, Q = 3 and 15; ngspice's complex solve).
RTOL_ENVELOPE_Y11 = 1e-11
#: The double-double admittance's running bound against long double's, before either is rounded to float64: at
#: most this fraction (the units' ratio 2^-102 / 2^-64 = 3.6e-12 with the same sum; measured 4.8e-12 .. 6.3e-12,
#: two-mass N = 30 and 40, one-mass N = 20, Q = 10 .. 1e4).
DOUBLE_DOUBLE_SHARPER = 1e-10
#: A designed perfect cradle's reference end weights (the residue product on its float masses and springs) against
#: the closed form of its prescribed spectrum (lcchain.theory.exact.perfect_weights): the design's own rounding,
#: absolute and relative (measured 1.7e-15 and 3.6e-14 on N = 12 to 60 with 0 to 2 walls, weights down to 2e-33).
ATOL_PERFECT_CLOSED_FORM = 1e-13
RTOL_PERFECT_CLOSED_FORM = 1e-11

# Bytes of Python memory a batch's driver keeps a run while it runs (tests/test_batch_memory.py: traced by
# tracemalloc, the growth from a batch of 80 listed netlists to one of 400, over the 320 runs more; each the least
# seen at the same few runs' starts, one worker).  A streamed batch keeps about a byte a run (the warm transport's
# RunMask), and caches that fill up to a bound (sqlite3's cursor references, the regular expressions' and the
# allocator's) showed as 15 to 21 bytes a run; the plan that held every name's copies, its list in the
# description and the spool's arrays showed 196.
MAX_BATCH_BYTES_PER_RUN = 64

# A warm worker's resident memory between runs, as the driver counts it (what the worker said after its last run,
# plus its launcher's and sandbox's, read once) against /proc's walk of its whole tree: the reply's write and the
# interpreter's reading loop touch a few more pages after the worker measures itself (measured up to 70 KB, 0.3 %).
RTOL_WORKER_RESIDENT = 0.02

#: A value ngspice prints (7 significant digits, as `.meas` results are) read back against the one lcchain computes
#: from the same expression: a power 2^3^2 read the other way round is 8 times off.
RTOL_PRINTED = 1e-6
#: A .meas through a 1 us source edge at a 2 us step, against the RC's closed form (1.7e-5 measured): the test is
#: that the measurement is made, of the right node.
RTOL_MEASURE_COARSE = 1e-4
#: A warned-of run's .meas against the same netlist written without the warning (a braced parameter, the capacitive
#: divider 1/2): the same circuit, the same steps (identical measured; 1e-4 for a capacitive divider's gmin).
RTOL_WARNED_MEASURE = 1e-4
#: A sample's prediction as the plan carries it against the same prediction made again: the same function of the
#: same modes (identical in practice).
RTOL_SAME_PREDICTION = 1e-12
#: A coupled design's stray coupling of 1e-6 loses nothing the first arrival's energy shows (measured 1e-7).
ATOL_STRAY_COUPLING_LOSS = 1e-4
#: A displaced mass with its coil's self-capacitance: ngspice's error at dt = 0.01 (3e-5 measured; the theory that
#: charged both capacitors was 4.8e-2 and 0.19 off).
MAX_DISPLACED_COIL_ERROR = 1e-3
