"""Named tolerances shared by the tests, in one place (STYLE.md, "Tests").

A plain module of constants: import what you need, add what you must, and say
in a comment why each value is what it is.  Absolute tolerances (ATOL_*) apply
to dimensionless quantities of order one (masses and springs in bulk units,
mode densities, amplitudes, frequencies in units of sqrt(K/m)).
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
#: S from the circuit's exact admittances at the same frequencies: both are exact to rounding of the nodal solve
#: and the modal sum (observed ~4e-13 for N = 8, z0 = 50 and 75 ohm).
ATOL_TWO_PORT_S = 1e-9
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
