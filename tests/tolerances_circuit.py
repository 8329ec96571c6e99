"""Named tolerances for comparisons between ngspice and theory (one place)."""

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
