"""Command line: ``lcchain <command> ...`` (a thin layer over the package).

Exit status: 0 ok, 1 simulation or comparison failed (or an output could not
be written), 2 bad usage or bad input, 3 simulator missing, 128 + n after
signal n (130 for Ctrl-C), 141 when the reader of the output went away.
"""

from __future__ import annotations

import argparse
import contextlib
import logging
import os
import signal
import sys
import threading
import warnings
from collections.abc import Iterator, Sequence
from typing import Any, NoReturn

from ..circuit.effects import Coupling
from ..core import __version__
from ..core.blas import BLAS_THREADS
from ..core.errors import (
    ExtraMissingError,
    Interrupted,
    LcchainError,
    ParameterError,
    SimulationError,
    SimulatorMissingError,
)
from ..core.types import (
    BACKENDS,
    DEFAULT_C0,
    DEFAULT_L0,
    DESIGN_CASES,
    EXCITATIONS,
    METHODS,
    NAMED_CASES,
    STUDY_METRICS,
)
from ..spice.engines import DEFAULT_ENGINE, ENGINES
from . import bom, check, commands, requirements, sensitivity, studies, validation
from .common import (
    EXIT_EXTRA,
    EXIT_FAILED,
    EXIT_MISSING,
    EXIT_SIGPIPE,
    EXIT_USAGE,
    OPTION_NAMES,
    add_effect_arguments,
    add_parts_arguments,
    budget_parent,
    int_list,
    list_entries,
    number_type,
    si_number,
    single_valued,
)

__all__ = ["main", "build_parser"]

log = logging.getLogger("lcchain")


class _UsageError(Exception):
    pass


class _Parser(argparse.ArgumentParser):
    """argparse that reports bad usage as one line (exit 2), never a traceback; a single-value option given twice
    is bad usage, and ``-1e-5`` is a value, not an option (:func:`~lcchain.cli.common.single_valued`)."""

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        super().__init__(*args, **kwargs)
        single_valued(self)

    def error(self, message: str) -> NoReturn:
        raise _UsageError(f"{self.prog}: {message} (see '{self.prog} --help')")


def engine_list(text: str) -> tuple[str, ...]:
    """``--engine ngspice`` or ``--engine ngspice,gnucap``: registered engines, each once."""
    names = tuple(list_entries("--engine", text, "engine names"))
    for name in names:
        if name not in ENGINES:
            raise argparse.ArgumentTypeError(f"unknown engine {name!r}: expected {' | '.join(ENGINES)}, or several "
                                             "separated by commas")
    if len(set(names)) != len(names):
        raise argparse.ArgumentTypeError(f"{text!r} names an engine twice")
    return names


def _add_circuit_arguments(p: argparse.ArgumentParser) -> None:
    """The circuit: a chain (named, or a file), its coils' coupling and its bulk L0, C0."""
    p.add_argument("--case", choices=NAMED_CASES,
                   help="named chain (one-mass/two-mass: the optimal design for N; perfect: the perfect cradle)")
    p.add_argument("--N", type=int, help="number of masses (ladder cells)")
    p.add_argument("--walls", type=int, default=0, metavar="J",
                   help="--case perfect only: J >= 1 ties the perfect cradle to walls (frequencies n - 1 + 2J)")
    p.add_argument("--chain", metavar="FILE", help='JSON file {"masses": [...], "springs": [...]} in bulk units')
    coupling = Coupling.option
    assert coupling is not None  # the chain's own: every command with a circuit takes it
    p.add_argument(coupling, type=number_type(coupling), default=None, metavar="K", help=Coupling.option_help)
    p.add_argument("--L0", type=si_number("--L0", "H"), default=DEFAULT_L0,
                   help=f"bulk inductance, henry: 1e-5, 10u or 10uH (default {DEFAULT_L0:g})")
    p.add_argument("--C0", type=si_number("--C0", "F"), default=DEFAULT_C0,
                   help=f"bulk capacitance, farad: 1e-8, 10n or 10nF (default {DEFAULT_C0:g})")


def _add_chain_arguments(p: argparse.ArgumentParser) -> None:
    """The circuit and how a transient drives and watches it."""
    _add_circuit_arguments(p)
    p.add_argument("--excitation", choices=EXCITATIONS, default="kick",
                   help="kick: initial current in L1; displacement: initial charge in loop 1")
    p.add_argument("--title", help="netlist title (one line)")
    p.add_argument("--transits", type=int, default=1, help="end-to-end transits to simulate (default 1)")
    p.add_argument("--dt", type=number_type("--dt"), default=None,
                   help=f"maximum time step in units of sqrt(L0*C0) (default {commands.DEFAULT_DT})")


def build_parser() -> argparse.ArgumentParser:
    parser = _Parser(prog="lcchain", description="Quasi-uniform spring-mass chains and their LC ladders in ngspice.")
    parser.add_argument("-v", "--verbose", action="store_true", help="log every ngspice run to stderr")
    parser.add_argument("--version", action="version", version=f"lcchain {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=_Parser)
    sub.required = True
    budget: list[Any] = [budget_parent()]  # argparse parents (typeshed wants the subparser class)

    p = sub.add_parser("design", parents=budget,
                       help="optimal one-mass or two-mass chain for N (a row of Table I or II), or a perfect cradle")
    p.add_argument("--case", choices=(*DESIGN_CASES, "perfect"), required=True,
                   help="one-mass, two-mass: the paper's optima; perfect: alpha_N = 1 exactly, designed from its "
                        "spectrum (every mass and spring modulated)")
    p.add_argument("--N", type=int, required=True)
    p.add_argument("--walls", type=int, default=0, metavar="J",
                   help="--case perfect only: J >= 1 ties the chain to walls (frequencies n - 1 + 2J)")
    p.add_argument("--json", action="store_true")
    p.set_defaults(func=commands.cmd_design)

    p = sub.add_parser("table", parents=budget, help="Table I (one-mass) or II (two-mass) for a list of N")
    p.add_argument("--case", choices=DESIGN_CASES, required=True)
    p.add_argument("--N", type=int_list("--N"), default=[3, 4, 5, 6, 7, 8, 9, 10, 12, 14, 16, 18, 20, 100, 1000])
    out = p.add_mutually_exclusive_group()
    out.add_argument("--json", action="store_true")
    out.add_argument("--csv", action="store_true")
    p.set_defaults(func=commands.cmd_table)

    p = sub.add_parser("asymptotic", help="N -> infinity: maximum of alpha_inf(tau, sigma) and the scaling laws")
    p.add_argument("--case", choices=DESIGN_CASES, default="two-mass")
    p.add_argument("--json", action="store_true")
    p.set_defaults(func=commands.cmd_asymptotic)

    p = sub.add_parser("netlist", help="SPICE netlist of the equivalent LC ladder")
    _add_chain_arguments(p)
    add_effect_arguments(p)
    p.add_argument("-o", "--output", metavar="FILE", help="write here instead of stdout")
    p.set_defaults(func=commands.cmd_netlist)

    p = sub.add_parser("examples", help="the example scenes that ship with lcchain: list them, or write one here")
    p.add_argument("name", nargs="?", metavar="NAME", help="the example to write (default: list them)")
    p.add_argument("-o", "--output", metavar="FILE", help="where to write it (default: NAME.toml here)")
    p.set_defaults(func=commands.cmd_examples)

    p = sub.add_parser("reference-netlists", help="regenerate the reference netlists of netlists/")
    p.add_argument("--out", default="netlists", help="folder (default netlists)")
    p.set_defaults(func=commands.cmd_reference_netlists)

    p = sub.add_parser("spectrum", parents=budget, help="the ladder's normal frequencies and mode weights from an AC "
                       "analysis in ngspice (or gnucap), beside theory")
    _add_circuit_arguments(p)
    p.add_argument("--engine", choices=tuple(ENGINES), default=DEFAULT_ENGINE,
                   help=f"the simulator that runs the AC analysis (default {DEFAULT_ENGINE})")
    p.add_argument("--points", type=int, default=None, metavar="P",
                   help="frequencies of the AC sweep, in even segments placed where the poles are dense (default: "
                        "twice the fewest that separate every pole)")
    add_effect_arguments(p)  # --Q (each mode's fitted Q_n beside omega_n Q), the real parts, a plugin's
    p.add_argument("--plot", metavar="FILE", help="Fig. Pk20-100: |P_n| and the spacing against omega_n, the "
                   "circuit's modes on top of theory")
    p.add_argument("--touchstone", metavar="FILE.s2p",
                   help="also the ladder as a two-port (port 1: a break in loop 1 where the AC source sits; port 2: "
                        "its mirror image in loop N), its S-parameters from two AC analyses (one per end) as a "
                        "Touchstone v1 file, --points evenly spaced frequencies (default 401) up to 5 %% above the "
                        "highest normal frequency")
    p.add_argument("--z0", type=number_type("--z0"), default=None, metavar="OHMS",
                   help="--touchstone's reference impedance on both ports, ohms (default 50)")
    p.add_argument("--shapes", action="store_true",
                   help="also every mode with its shape, from a second AC run (ngspice) that drives every loop and "
                        "saves every loop's current, against the chain's exact eigensolution")
    p.add_argument("--json", action="store_true")
    p.set_defaults(func=commands.cmd_spectrum)

    p = sub.add_parser("bom", help="bill of materials: the ladder's distinct inductors and capacitors (rounded to "
                       "a preferred-number series with --series) with their counts, as a table or --csv")
    _add_circuit_arguments(p)
    bom.add_bom_arguments(p)
    add_effect_arguments(p)
    p.set_defaults(func=bom.cmd_bom)

    p = sub.add_parser("sensitivity", parents=budget, help="which components move the first-arrival peak: dp/dL_i "
                       "and dp/dC_j from exact theory, ranked (--check M: against ngspice finite differences)")
    _add_circuit_arguments(p)
    sensitivity.add_sensitivity_arguments(p)
    p.set_defaults(func=sensitivity.cmd_sensitivity)

    p = sub.add_parser("requirements", parents=budget, help="how good must the parts be: the first arrival's "
                       "energy against a coil's self-capacitance and resistance, a capacitor's ESR and ESL, and "
                       "coupling, from the circuit's exact theory, with ngspice points")
    _add_circuit_arguments(p)
    requirements.add_requirements_arguments(p)
    p.set_defaults(func=requirements.cmd_requirements)

    p = sub.add_parser("simulate", parents=budget, help="run the ladder in ngspice (or gnucap) and compare with "
                       "alpha_N(t)")
    _add_chain_arguments(p)
    p.add_argument("--backend", choices=BACKENDS, default="batch")
    p.add_argument("--engine", type=engine_list, default=(DEFAULT_ENGINE,), metavar="ENGINE[,ENGINE]",
                   help=f"the circuit simulator: {' or '.join(ENGINES)} (default {DEFAULT_ENGINE}); gnucap runs one "
                        "fixed-step run (no --extrapolate); several, comma-separated, run the same netlist in each "
                        "and report their difference beside each one's error against theory")
    p.add_argument("--method", choices=METHODS, default="trap")
    p.add_argument("--accuracy", type=number_type("--accuracy"), metavar="EPS",
                   help="wanted max |simulation - theory|: lcchain picks the largest dt that meets it "
                        "(instead of --dt); a run that misses it exits 1")
    p.add_argument("--extrapolate", type=int, choices=(1, 2, 3), metavar="{1,2,3}",
                   help="combine this many runs at dt, dt/2, dt/4 (Richardson: the dt^2 and dt^4 errors cancel); "
                        "with --accuracy and without this option, lcchain picks the cheapest of 1, 2 and 3")
    p.add_argument("--plot", metavar="FILE", help="figure (.png, .svg, .pdf): theory and simulation, residual below")
    p.add_argument("--netlist-out", metavar="FILE", help="keep the netlist (written before ngspice starts)")
    p.add_argument("--waveform-out", metavar="FILE", help="CSV t,first,last (dimensionless)")
    p.add_argument("--json", action="store_true")
    add_effect_arguments(p)
    p.set_defaults(func=commands.cmd_simulate)

    p = sub.add_parser("run", parents=budget, help="run a scene (TOML experiment description)")
    p.add_argument("scene", metavar="SCENE.toml", nargs="+", help="one or more scene files, run in order")
    p.add_argument("--json", action="store_true", help="print the report as JSON (a list for several scenes)")
    p.add_argument("--side-by-side", metavar="FILE",
                   help="figure (.png, .svg, .pdf): the scenes' overlays next to each other on shared axes")
    p.add_argument("--netlist-out", metavar="FILE", help="keep the (first sample's) netlist")
    p.add_argument("--waveform-out", metavar="FILE", help="CSV t,first,last (first sample, dimensionless)")
    add_parts_arguments(p)
    studies.add_study_arguments(p, store=False)
    p.set_defaults(func=commands.cmd_run, executor="serial")

    p = sub.add_parser("sweep", parents=budget, help="many runs: the product of comma-list axes, or a scene or a "
                       "netlist varied")
    studies.add_sweep_arguments(p)
    p.set_defaults(func=studies.cmd_sweep)

    p = sub.add_parser("batch", parents=budget, help="netlists lcchain did not write, checked, priced and run in a "
                       "sandbox, into a store")
    p.add_argument("netlist", nargs="+", metavar="NETLIST",
                   help="netlist files: comments, R L C K V I B D Q M J S W X elements, .tran .ac .options .save "
                        ".ic .param .meas .subckt/.ends .model .func .global .temp .op .dc .end and .include/.lib of "
                        "files in the netlist's folder; any other line is refused")
    p.add_argument("--allow-control", action="store_true",
                   help="run a netlist as it is (.control blocks, any include), still in the sandbox")
    p.add_argument("--check", action="store_true",
                   help="also compare each run's saved vectors with the netlist's exact response (lcchain check): "
                        "the largest error, in the vectors' own units, is stored as the measurement "
                        "check_max_abs_error (empty, with the reason, for a netlist that is not linear)")
    p.add_argument("--strict", action="store_true",
                   help="stop at the first netlist lcchain will not run, with its reason, before anything runs "
                        "(exit 2); by default each is stored as refused, with its reason, the others run, and "
                        "the exit status is 1")
    studies.add_study_arguments(p)
    p.set_defaults(func=studies.cmd_batch)

    p = sub.add_parser("check", parents=budget,
                       help="a linear netlist (R L C K, V/I with DC PULSE SIN PWL EXP) run in a simulator and "
                            "compared with its exact response: the error of every saved vector, the error the step "
                            "predicts, the step an accuracy needs")
    check.add_check_arguments(p, tuple(ENGINES))
    p.set_defaults(func=check.cmd_check)

    p = sub.add_parser("results", parents=budget,
                       help="a store's runs: a table, --json, --csv, or a --plot of the study")
    p.add_argument("store", metavar="STORE.sqlite")
    out = p.add_mutually_exclusive_group()
    out.add_argument("--json", action="store_true", help="a list in task order: index, key, status, params, ...")
    out.add_argument("--csv", action="store_true")
    p.add_argument("--summary", action="store_true",
                   help="the transmitted peak's distribution per combination of the axes (n, mean, std, worst, "
                        "5th percentile, median, best); with --json or --csv in that form")
    p.add_argument("--plot", metavar="FILE",
                   help="figure: Fig. delta for a sweep over N, histograms of the samples (one per combination)")
    p.add_argument("--metric", default="peak", metavar="{" + ",".join(STUDY_METRICS) + "} or NAME",
                   help="what --summary and the samples' --plot show: the first arrival's peak I_N/I_1(0) "
                        "(default); after a kick the energy fraction at that peak, peak^2 L_N/L_1, or the energy "
                        "lost, 1 - that (drawn on a log scale); of an AC analysis: omega (max relative error of "
                        "omega_n), P (max absolute error of P_n), spacing ((max - min) / mean of delta omega_n); "
                        "of a batch of netlists, the NAME of one of their .meas cards (--summary only)")
    p.add_argument("--netcdf", metavar="FILE.nc", help="write the study as a netCDF file: the study's axes as "
                   "dimensions, the metrics as variables (needs lcchain[data])")
    p.add_argument("--parquet", metavar="FILE.parquet", help="write one row per run, the axes as columns "
                   "(needs lcchain[data] and pyarrow)")
    p.add_argument("--waveforms", action="store_true",
                   help="--netcdf also holds every run's saved vectors and their time (padded with NaN)")
    p.set_defaults(func=studies.cmd_results)

    p = sub.add_parser("figures", help="the paper's figures, recomputed: one file per figure, named by its label")
    validation.add_figures_arguments(p)
    p.set_defaults(func=validation.cmd_figures)

    p = sub.add_parser("report", help="the validation report: the paper reproduced and the circuit validated, in "
                       "DIR/index.html and DIR/report.json (exit 1 when a check fails)")
    validation.add_report_arguments(p)
    p.set_defaults(func=validation.cmd_report)

    p = sub.add_parser("bench", help="benchmarks (accuracy: what each digit costs per method and N)")
    bench = p.add_subparsers(dest="bench", metavar="BENCH", parser_class=_Parser)
    bench.required = True
    b = bench.add_parser("accuracy", parents=budget,
                         help="sweep dt x method x stepping, DOP853 and the modal sum as peers")
    b.add_argument("--N", type=int_list("--N"), help="chain sizes (default 20,100,1000; --quick: 20,100)")
    b.add_argument("--quick", action="store_true", help="fewer steps and tolerances (under 2 minutes)")
    b.add_argument("--out", default="benchmarks/accuracy", help="output folder (default benchmarks/accuracy)")
    b.set_defaults(func=commands.cmd_bench_accuracy)

    p = sub.add_parser("doctor", help="check ngspice, its shared library and PySpice")
    p.set_defaults(func=commands.cmd_doctor)
    return parser


def _raise_interrupted(signum: int, frame: object) -> None:
    raise Interrupted(signum)


@contextlib.contextmanager
def _signals_interrupt() -> Iterator[None]:
    """SIGTERM and SIGHUP raise Interrupted while a command runs, so that every cleanup runs."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    previous = {sig: signal.signal(sig, _raise_interrupted) for sig in (signal.SIGTERM, signal.SIGHUP)}
    try:
        yield
    finally:
        for sig, handler in previous.items():
            signal.signal(sig, handler)


def _as_typed(error: ParameterError, args: argparse.Namespace) -> ParameterError:
    """The error under the option the user typed (``--dt``, not ``dt``) when it came from the command line.

    A refusal of the chain itself (``chain``: its time scale, its poles; ``N``: its size) names how the user gave
    the chain: ``--chain FILE`` (with a file, --N was not typed), else ``--walls`` for a walled cradle, else ``--N``.
    So does a refusal of a step the user did not type (the default --dt): the chain makes the run long.
    """
    if error.where is not None:
        return error
    allowed = error.allowed
    if error.field == "dt" and "dt" in args and args.dt is None:  # the default step: what the user gave is the chain
        allowed = f"{allowed} (at the default step --dt {error.value!r})"
        if isinstance(getattr(args, "N", None), list):  # a sweep: its sizes
            return ParameterError("--N", ",".join(str(N) for N in args.N), allowed)
        error = ParameterError("chain", error.value, allowed)
    chain_file = getattr(args, "chain", None)
    if error.field in ("chain", "N") and isinstance(chain_file, str):
        return ParameterError("--chain", chain_file, allowed)
    if error.field == "chain":
        walls, N = getattr(args, "walls", 0), getattr(args, "N", None)
        if walls:
            return ParameterError("--walls", walls, f"{allowed} (with --N {N})")
        if isinstance(N, int):
            return ParameterError("--N", N, allowed)
    if error.field in OPTION_NAMES:
        return error.renamed(OPTION_NAMES[error.field])
    return error


def _quiet_stdout() -> None:
    """The reader of our output went away: send what is left nowhere, say nothing."""
    try:
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
    except (OSError, ValueError):
        pass


def _show_warning(message: Warning | str, category: type[Warning], filename: str, lineno: int,
                  file: Any = None, line: str | None = None) -> None:
    print(f"lcchain: warning: {message}", file=sys.stderr)


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command line; returns the exit status."""
    argv = list(sys.argv[1:] if argv is None else argv)
    try:
        parser = build_parser()  # reads the registries: a broken plugin is bad input, one line
    except ParameterError as error:
        print(f"lcchain: {error}", file=sys.stderr)
        return EXIT_USAGE
    try:
        args = parser.parse_args(argv)
    except _UsageError as error:
        print(str(error), file=sys.stderr)
        return EXIT_USAGE
    except SystemExit as exit_:  # --help, --version
        return int(exit_.code or 0)
    args.argv_echo = argv[1:]
    logging.basicConfig(level=logging.INFO if args.verbose else logging.WARNING, format="lcchain: %(message)s")
    from threadpoolctl import threadpool_limits  # here: --help and --version set no limit

    try:
        with _signals_interrupt(), threadpool_limits(limits=BLAS_THREADS, user_api="blas"), \
                warnings.catch_warnings():
            warnings.showwarning = _show_warning  # one line a person reads, not a source location
            status = int(args.func(args))
        sys.stdout.flush()
        return status
    except SimulatorMissingError as error:
        print(f"lcchain: {error}", file=sys.stderr)
        return EXIT_MISSING
    except ExtraMissingError as error:
        print(f"lcchain: {error}", file=sys.stderr)
        return EXIT_EXTRA
    except ParameterError as error:
        print(f"lcchain: {_as_typed(error, args)}", file=sys.stderr)
        return EXIT_USAGE
    except SimulationError as error:
        print(f"lcchain: simulation failed: {error}", file=sys.stderr)
        return EXIT_FAILED
    except LcchainError as error:
        print(f"lcchain: {error}", file=sys.stderr)
        return EXIT_FAILED
    except BrokenPipeError:
        _quiet_stdout()
        return EXIT_SIGPIPE
    except OSError as error:  # e.g. a disk full or a folder removed while running
        where = f"{error.filename}: " if error.filename else ""
        print(f"lcchain: {where}{error.strerror or error}", file=sys.stderr)
        return EXIT_FAILED
    except KeyboardInterrupt:
        print("lcchain: interrupted", file=sys.stderr)
        return 130
    except Interrupted as interrupt:
        print(f"lcchain: interrupted by signal {interrupt.signum}", file=sys.stderr)
        return 128 + interrupt.signum


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
