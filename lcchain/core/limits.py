"""Every limit lcchain enforces, stated once.

The command line, the Python API and scenes all check against these names;
an error message quotes the number from here.
"""

from __future__ import annotations

#: Smallest chain lcchain accepts (the paper's smallest model, Sec. II.C).
MIN_N = 3
#: Largest N the optimisers accept (memory: a few arrays of N floats).
MAX_DESIGN_N = 10_000_000
#: Largest N diagonalised exactly (eigenvectors need 8 N^2 bytes: 800 MB at 10^4).
EXACT_MAX_N = 10_000
#: Largest chain with coupled coils: its modes solve a dense generalised eigenproblem, O(N^3) (N = 2000: ~3 s).
COUPLED_MAX_N = 2000
#: Largest perfect cradle designed: O(N^2) (the design and its check), about 25 s free and 50 s with walls here.
MAX_PERFECT_N = 20_000
#: Largest chain simulated as a netlist (about 2 N elements) by simulate, scenes and sweeps.
MAX_CIRCUIT_N = 100_000
#: Most end-to-end transits one run may watch.
MAX_TRANSITS = 1000
#: Largest fixed step written into a netlist, units of sqrt(L0*C0) (the bulk period is 2 pi).
MAX_DT = 1.0
#: Largest step --accuracy chooses, units of sqrt(L0*C0): the bulk band reaches omega = 2, warped 8 % at 0.5.
MAX_ACCURACY_DT = 0.5
#: Shortest and longest pulse (gaussian standard deviation or rect duration), units of sqrt(L0*C0).  A pulse is
#: stepped at a width / 8 at most: narrower than 1e-3 (1/6000 of the bulk period) it is a kick that only costs
#: steps (1e-300 was refused as an accuracy no budget affords, naming analysis.accuracy).
MIN_PULSE_WIDTH = 1e-3
MAX_PULSE_WIDTH = 1000.0
#: The kick's current I0 (ampere) and the pulse's scale: the circuit is linear, but ngspice squares its
#: currents (1e300 A aborted its run; 1e-300 to 1e200 ran to the same relative error).  A wider range is a typo.
MIN_I0, MAX_I0 = 1e-100, 1e100
#: Stiffest wall spring (``[effects.walls] K0``, bulk units): its mode at sqrt(K0) needs steps of 1/sqrt(K0);
#: 1e12 is still refused by the price of its accuracy in seconds, 1e300 ran for minutes before any refusal.
MAX_WALL_SPRING = 1e12
#: Largest parasitic of a real part, in units of its bulk element (a coil's self-capacitance in C0, a winding
#: resistance or an ESR in sqrt(L0/C0), an ESL in L0).  A million times the bulk part is another part, not its
#: parasitic; past it float64 lost the circuit's exact theory: a winding resistance or an ESR of 1e18 gave NaN
#: errors and overflow warnings, an ESL of 1e18 an inductance matrix no Cholesky factor holds.
MAX_PARASITIC = 1e6
#: Most tolerance samples in one scene or sweep.
MAX_SAMPLES = 10_000
#: Boxes the worst-case search's branch and bound on its quadratic model may make (N = 9: the model's minimum proved
#: within 12,000; N = 50: 20,000 take about 2 s and leave a gap).
WORST_CASE_MODEL_NODES = 20_000
#: Most runs one sweep of a foreign netlist makes (``sweep --netlist``: its lists and grids multiplied, times its
#: samples), and most values one ``--vary`` grid holds.
MAX_NETLIST_VARIANTS = 10_000
#: Most components a worst-case study moves together (``sweep --worst-case --components``): 2^K corners.
MAX_CORNER_COMPONENTS = 12
#: Longest title or comment line written into a netlist.
MAX_TITLE_LENGTH = 200
MAX_COMMENT_LENGTH = 400
#: Longest title line ngspice 39 reads safely, in UTF-8 bytes: it reads the title into a fixed buffer, a title of
#: 505 bytes or more aborts it ("buffer overflow detected"), and a much longer one spills its tail into the next
#: card (measured: a 100,000-character title was read as a transmission line).  lcchain's own titles and a
#: foreign netlist's first line are held well below it.
MAX_TITLE_BYTES = 400
#: The circuit's time unit sqrt(L0*C0), seconds, and impedance sqrt(L0/C0), ohm: ngspice 39 reproduces the
#: trapezoidal model to ~1e-14 from 1e-21 to 1e4 s and from 1e-6 to 1e12 ohm, and hangs at 1e9 s (measured).
MIN_TIME_UNIT, MAX_TIME_UNIT = 1e-18, 1e3
MIN_IMPEDANCE, MAX_IMPEDANCE = 1e-6, 1e12
#: The smallest accuracy a run may ask for: ngspice's rounding grows with the number of steps; 1e-9 is
#: usually met (7.0e-10 to 7.9e-10 on perfect and two-mass chains) but not always (1.7e-9 on the uniform
#: bounded N = 20 chain), and 1e-11 never (7e-11 to 6e-10).  A run that misses its accuracy fails.
ACCURACY_FLOOR = 1e-9
#: Shortest timeout of a run (--timeout), seconds: a run's start alone takes 0.02 s; 1e-300 timed every run out.
MIN_TIMEOUT = 0.1
#: Longest time any budget or timeout may name (--max-time, --timeout): a year, in seconds.  Larger ones mean
#: "no limit", and 1e300 overflowed the deadline arithmetic (time_t) with a traceback.
MAX_SECONDS = 365 * 86400.0
#: Largest memory budget (--max-memory): 1 PiB, beyond any machine, so a number like 1e300 is a typo.
MAX_BUDGET_BYTES = float(2**50)
#: Largest netlist (or included file) lcchain reads: 2 N + 10 lines of at most 100 characters at MAX_CIRCUIT_N.
MAX_NETLIST_BYTES = 64 * 2**20
#: The largest list of netlist names ``lcchain batch --from`` reads (a million names of 60 characters).
MAX_NETLIST_LIST_BYTES = 64 * 2**20
#: Most elements a foreign netlist may hold once its sub-circuits are expanded (ngspice expands them: ten
#: sub-circuits each instantiating the next ten times are 10^10 elements in 20 lines): ten times lcchain's own
#: largest netlist (about 2 MAX_CIRCUIT_N elements), 1.7 GB in ngspice at its 850 B an element.
MAX_EXPANDED_ELEMENTS = 2_000_000
#: Most points of one foreign ``.dc`` sweep (its sources' values, nested sweeps multiplied).
MAX_DC_POINTS = 1_000_000
#: Largest --chain file read (a JSON chain of MAX_CIRCUIT_N masses takes about 5 MB).
MAX_CHAIN_FILE_BYTES = 64 * 2**20
#: Largest scene file read (a custom scene lists its masses and springs like a --chain file).
MAX_SCENE_BYTES = 64 * 2**20
#: Frequencies of one AC analysis (lcchain spectrum --points): a few per mode at least, at most a million.
MIN_AC_POINTS = 16
MAX_AC_POINTS = 1_000_000
#: The losses' quality factor Q (``[effects.losses] Q``, ``--Q``): each inductor's series resistor is
#: L_i / (Q sqrt(L0*C0)).  Below 1 the decay rate 1/Q leaves the bulk band the step is chosen for (measured: Q = 0.5
#: misses accuracy 1e-3 at N = 100, Q = 1e-6 divided by zero in the planner); above 1e10 the resistors, 1e-10 of
#: the line impedance, are beyond ngspice's resolution (Q = 1e13 missed 1e-3; 1e300 made its matrix singular).
MIN_Q, MAX_Q = 1.0, 1e10
#: The accuracy (max |simulation - theory|) of the runs of ``lcchain sensitivity --check``: met by extrapolated
#: runs for N up to a few hundred.
SENSITIVITY_CHECK_ACCURACY = 1e-7
