"""Command line: ``lcchain <command> ...`` (a thin layer over the package).

Exit status: 0 ok, 1 simulation or comparison failed, 2 bad usage or bad
input, 3 simulator missing.
"""

from __future__ import annotations

import argparse
import contextlib
import json
import logging
import math
import os
import signal
import sys
import threading
from collections.abc import Callable, Iterator, Sequence
from fractions import Fraction
from pathlib import Path

from threadpoolctl import threadpool_limits

from ..core import __version__
from ..core.blas import BLAS_THREADS
from ..core.errors import Interrupted, LcchainError, ParameterError, SimulationError, SimulatorMissingError
from ..core.types import BACKENDS, DESIGN_CASES, EXCITATIONS, METHODS, NAMED_CASES

__all__ = ["main"]

EXIT_OK, EXIT_FAILED, EXIT_USAGE, EXIT_MISSING = 0, 1, 2, 3
#: Step when neither --dt nor --accuracy is given, units of sqrt(L0*C0).
DEFAULT_DT = 0.05
log = logging.getLogger("lcchain")


class _UsageError(Exception):
    pass


class _Parser(argparse.ArgumentParser):
    """argparse that reports bad usage as one line (exit 2), never a traceback."""

    def error(self, message: str) -> None:  # type: ignore[override]
        raise _UsageError(f"{self.prog}: {message} (see '{self.prog} --help')")


# ------------------------------------------------------------------ helpers
def _positive_int_list(text: str) -> list[int]:
    try:
        values = [int(v) for v in text.split(",") if v.strip()]
    except ValueError:
        raise argparse.ArgumentTypeError(
            f"--N = {text!r} is not allowed: expected integers separated by commas") from None
    if not values:
        raise argparse.ArgumentTypeError("--N is empty: expected integers separated by commas")
    return values


def _float(name: str):
    def parse(text: str) -> float:
        try:
            value = float(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{name} = {text!r} is not allowed: expected a number") from None
        if not math.isfinite(value):
            raise argparse.ArgumentTypeError(f"{name} = {text!r} is not allowed: expected a finite number")
        return value

    return parse


def _draw_bar(fraction: float, text: str) -> None:
    width = 30
    filled = int(width * min(max(fraction, 0.0), 1.0))
    end = "\n" if fraction >= 1 else ""
    # "\033[K" clears what a longer previous label left on the line (drawn on terminals only)
    sys.stderr.write(f"\r[{'#' * filled}{'.' * (width - filled)}] {text}\033[K{end}")
    sys.stderr.flush()


def _progress(done: int, total: int, label: str) -> None:
    """A one-line progress indicator on a terminal (nothing when piped)."""
    if sys.stderr.isatty():
        _draw_bar(done / max(total, 1), f"{done}/{total} {label}")


def _fraction_bar(label: str) -> Callable[[float], None] | None:
    """A progress callback for long runs: a bar on a terminal, None when piped."""
    if not sys.stderr.isatty():
        return None
    shown: list[int] = []

    def show(fraction: float) -> None:
        percent = int(100 * fraction)
        if not shown or percent != shown[-1]:  # once per percent, and 100% once
            shown.append(percent)
            _draw_bar(fraction, f"{percent:3d}% {label}")

    return show


def _check_outputs(args, *options: str) -> None:
    """Refuse output files in missing or read-only folders before any work is done."""
    for option in options:
        path = getattr(args, option.lstrip("-").replace("-", "_"), None)
        if not path:
            continue
        folder = Path(path).parent
        if not folder.is_dir():
            raise ParameterError(option, path, f"a file in an existing folder ({folder} does not exist)")
        if not os.access(folder, os.W_OK):
            raise ParameterError(option, path, f"a file in a writable folder ({folder} is not writable)")


def _write_text(path: str, text: str) -> None:
    try:
        Path(path).write_text(text, encoding="utf-8")
    except OSError as error:
        raise ParameterError("output file", path, f"a writable path ({error.strerror})") from None


def _emit_json(data) -> None:
    print(json.dumps(data, indent=2))


def _load_chain_file(path: str):
    from ..theory.chain import Chain

    try:
        data = json.loads(Path(path).read_text(encoding="utf-8"))
    except OSError as error:
        raise ParameterError("--chain", path, f"a readable JSON file ({error.strerror})") from None
    except json.JSONDecodeError as error:
        raise ParameterError("--chain", path, f"valid JSON (line {error.lineno}: {error.msg})") from None
    return Chain.from_dict(data, where=path)


def _chain_from_args(args):
    from ..theory.cases import chain_for_case

    if args.chain:
        return _load_chain_file(args.chain)
    if args.case is None or args.N is None:
        raise ParameterError("--case/--N", None, "--case and --N, or --chain FILE")
    return chain_for_case(args.case, args.N)


# ------------------------------------------------------------------ commands
_TABLE_COLUMNS = {
    "one-mass": [("N", "N", "{:>6d}"), ("x*", "x", "{:.4f}"), ("delta*", "delta", "{:.4f}"), ("s*", "s", "{:6.2f}"),
                 ("m1*", "m1", "{:7.3f}"), ("Delta*", "Delta", "{:#.4g}"), ("delta*(1)", "delta_uniform", "{:.4f}")],
    "two-mass": [("N", "N", "{:>6d}"), ("r*", "r", "{:.4f}"), ("w*", "w", "{:.4f}"), ("delta*", "delta", "{:.5f}"),
                 ("s*", "s", "{:6.2f}"), ("m1*", "m1", "{:7.3f}"), ("m2*", "m2", "{:.4f}"), ("K12*", "K12", "{:.4f}")],
}


def _format_table(case: str, rows: list[dict]) -> str:
    columns = _TABLE_COLUMNS[case]
    cells = [[fmt.format(row[key]) for _, key, fmt in columns] for row in rows]
    widths = [max(len(head), *(len(c[i]) for c in cells)) for i, (head, _, _) in enumerate(columns)]
    title = "Table I: one optimised mass" if case == "one-mass" else "Table II: two optimised masses and their spring"
    lines = [title, "  ".join(h.rjust(w) for (h, _, _), w in zip(columns, widths, strict=True))]
    lines.append("-" * len(lines[-1]))
    lines += ["  ".join(c.rjust(w) for c, w in zip(row, widths, strict=True)) for row in cells]
    return "\n".join(lines)


def cmd_design(args) -> int:
    from ..theory.design import optimal_design

    design = optimal_design(args.case, args.N)
    if args.json:
        _emit_json(design.to_dict())
    else:
        print(_format_table(args.case, [design.to_dict()]))
    return EXIT_OK


def cmd_table(args) -> int:
    from ..theory.design import optimal_design

    rows = []
    for i, N in enumerate(args.N):
        _progress(i, len(args.N), f"N={N}")
        rows.append(optimal_design(args.case, N).to_dict())
    _progress(len(args.N), len(args.N), "done")
    if args.json:
        _emit_json(rows)
    elif args.csv:
        keys = list(rows[0])
        print(",".join(keys))
        for row in rows:
            print(",".join(repr(row[k]) if isinstance(row[k], float) else str(row[k]) for k in keys))
    else:
        print(_format_table(args.case, rows))
    return EXIT_OK


def cmd_asymptotic(args) -> int:
    from ..theory.asymptotic import EXPONENTS, asymptotic_optimum

    optimum = asymptotic_optimum(args.case)
    if args.json:
        _emit_json(optimum.to_dict())
        return EXIT_OK
    print(f"{args.case}: alpha* = {optimum.alpha:.6f}  delta* = {optimum.delta:.6f}  "
          f"sigma* = {optimum.sigma:.5f}  tau* = {optimum.tau:.5f}")
    exponents = EXPONENTS[args.case]
    for key, value in optimum.to_dict()["coefficients"].items():
        law = {"y": "sqrt(2) - {c} N^{p}", "m2": "1/2 + {c} N^{p}"}.get(key, "{c} N^{p}")
        power = Fraction(exponents[key]).limit_denominator(6)
        print(f"  {key:>6} ~ " + law.format(c=f"{value:.5g}", p=f"({power})"))
    return EXIT_OK


def _netlist_for(args):
    from ..circuit.netlist import make_netlist

    chain = _chain_from_args(args)
    command = "lcchain netlist " + " ".join(args.argv_echo)
    dt = args.dt if args.dt is not None else DEFAULT_DT
    text, _, _ = make_netlist(chain, dt=dt, transits=args.transits, excitation=args.excitation,
                              L0=args.L0, C0=args.C0, title=args.title, comments=(f"made by: {command}",))
    return text


def cmd_netlist(args) -> int:
    text = _netlist_for(args)
    if args.output:
        _write_text(args.output, text)
    else:
        sys.stdout.write(text)
    return EXIT_OK


def cmd_reference_netlists(args) -> int:
    from ..circuit.reference import REFERENCE_SET, reference_netlist

    folder = Path(args.out)
    folder.mkdir(parents=True, exist_ok=True)
    for reference in REFERENCE_SET:
        path = folder / reference.name
        _write_text(str(path), reference_netlist(reference))
        print(path)
    return EXIT_OK


def _print_arrivals(arrivals) -> None:
    print(f"{'arrival':>7} {'end':>5} {'t theory':>12} {'t sim':>12} {'peak theory':>12} {'peak sim':>12}")
    for a in arrivals:
        print(f"{a['index']:>7} {a['end']:>5} {a['t_theory']:12.4f} {a['t_sim']:12.4f} "
              f"{a['peak_theory']:12.6f} {a['peak_sim']:12.6f}")


def cmd_simulate(args) -> int:
    import warnings

    from ..runs.simulate import simulate

    _check_outputs(args, "--plot", "--netlist-out", "--waveform-out")
    chain = _chain_from_args(args)
    if args.accuracy is not None and args.dt is not None:
        raise ParameterError("--accuracy", args.accuracy, "either --dt or --accuracy, not both")
    dt = None if args.accuracy is not None else (args.dt if args.dt is not None else DEFAULT_DT)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        report = simulate(chain, dt=dt, accuracy=args.accuracy, transits=args.transits,
                          excitation=args.excitation, L0=args.L0, C0=args.C0, backend=args.backend,
                          method=args.method, title=args.title, progress=_fraction_bar("ngspice"))
    for warning in caught:
        print(f"lcchain: warning: {warning.message}", file=sys.stderr)
    if args.netlist_out:
        _write_text(args.netlist_out, report.netlist)
    if args.waveform_out:
        _write_text(args.waveform_out, report.waveforms.to_csv())
    if args.plot:
        from ..report.plots import overlay

        w, c = report.waveforms, report.comparison
        overlay(w.t, w.last, w.t, c.theory_last, residual=w.last - c.theory_last,
                arrivals=[a.to_dict() for a in c.arrivals if a.end == "last"],
                title=f"{chain.name} chain, N = {chain.N}, dt = {report.options.dt:.4g}, {args.excitation}",
                ylabel="I_N / I_1(0)" if args.excitation == "kick" else "Q_N / Q_1(0)", path=args.plot)
    data = report.to_dict()
    if args.json:
        _emit_json(data)
    else:
        print(f"{chain.name} chain, N = {chain.N}: ngspice {data['ngspice_version']} ({data['backend']}), "
              f"{data['points']} points in {data['wall_s']:.3f} s")
        print(f"max |simulation - theory| = {data['max_abs_error']:.3e} (dt = {data['dt']:.4g}, "
              f"predicted {data['predicted_error']:.3e})")
        if data["integration_error"] is not None:
            print(f"  integration error (simulation - trapezoidal model) = {data['integration_error']:.3e}, "
                  f"physics error (model - exact theory) = {data['physics_error']:.3e}")
        _print_arrivals(data["arrivals"])
    return EXIT_OK


def _print_scene_summary(scene, result) -> None:
    report = result.report
    count = len(report["samples"])
    print(scene.title)
    print(f"N = {report['N']}, dt = {report['dt']:.4g}, {count} sample{'s' if count > 1 else ''}, "
          f"ngspice {report['ngspice_version']}, {report['wall_s']['total']:.2f} s")
    if "max_abs_error" in report:
        print(f"max |simulation - theory| = {report['max_abs_error']:.3e}")
        _print_arrivals(report["arrivals"])
    if "transmitted_peak" in report:
        p = report["transmitted_peak"]
        print(f"transmitted peak over {p['count']} samples: mean {p['mean']:.5f}, std {p['std']:.5f}, "
              f"worst {p['worst']:.5f} (nominal theory {p['theory_nominal']:.5f})")
    for record in report["samples"]:
        if "error" in record:
            print(f"sample {record['sample']} failed: {record['error']}", file=sys.stderr)
    for path in result.files:
        print(f"wrote {path}")


def cmd_run(args) -> int:
    from ..report.scenes import run_scene
    from ..scenes.load import load_scene
    from ..scenes.run import overlay_panel

    if len(args.scene) > 1 and (args.netlist_out or args.waveform_out):
        option = "--netlist-out" if args.netlist_out else "--waveform-out"
        raise ParameterError(option, args.netlist_out or args.waveform_out, "one scene only (got "
                             f"{len(args.scene)})")
    _check_outputs(args, "--netlist-out", "--waveform-out", "--side-by-side")
    scenes = [load_scene(path) for path in args.scene]  # every file checked before anything runs
    results = []
    for scene in scenes:
        result = run_scene(scene, netlist_out=args.netlist_out, waveform_out=args.waveform_out,
                           progress=_fraction_bar(Path(scene.source).name if scene.source else "scene"))
        results.append(result)
        if not args.json:
            _print_scene_summary(scene, result)
    if args.side_by_side:
        from ..report.plots import side_by_side

        panels = [p for p in (overlay_panel(r) for r in results) if p is not None]
        if panels:
            side_by_side(panels, path=args.side_by_side)
            if not args.json:
                print(f"wrote {args.side_by_side}")
        else:
            print(f"lcchain: no scene ran, so {args.side_by_side} was not drawn", file=sys.stderr)
    if args.json:
        reports = [r.report for r in results]
        _emit_json(reports[0] if len(reports) == 1 else reports)
    return EXIT_OK if all(r.ok for r in results) else EXIT_FAILED


def cmd_bench_accuracy(args) -> int:
    from ..report.bench import write_accuracy_bench
    from ..studies.bench import bench_accuracy

    result = bench_accuracy(args.N, quick=args.quick, progress=_progress)
    print(result["markdown"], end="")
    for path in write_accuracy_bench(args.out, result):
        print(f"wrote {path}")
    return EXIT_OK


def cmd_doctor(args) -> int:
    from ..spice.doctor import doctor

    checks = doctor()
    for check in checks:
        mark = "ok  " if check.ok else "FAIL"
        print(f"[{mark}] {check.name}: {check.detail}")
        if not check.ok and check.fix:
            print(f"       fix: {check.fix}")
    return EXIT_OK if all(c.ok for c in checks) else EXIT_MISSING


# ------------------------------------------------------------------ parser
def _add_chain_arguments(p, with_dt: bool) -> None:
    p.add_argument("--case", choices=NAMED_CASES, help="named chain (one-mass/two-mass: the optimal design for N)")
    p.add_argument("--N", type=int, help="number of masses (ladder cells)")
    p.add_argument("--chain", metavar="FILE", help='JSON file {"masses": [...], "springs": [...]} in bulk units')
    p.add_argument("--L0", type=_float("--L0"), default=10e-6, help="bulk inductance, henry (default 10e-6)")
    p.add_argument("--C0", type=_float("--C0"), default=10e-9, help="bulk capacitance, farad (default 10e-9)")
    p.add_argument("--excitation", choices=EXCITATIONS, default="kick",
                   help="kick: initial current in L1; displacement: initial charge in loop 1")
    p.add_argument("--title", help="netlist title (one line)")
    p.add_argument("--transits", type=int, default=1, help="end-to-end transits to simulate (default 1)")
    p.add_argument("--dt", type=_float("--dt"), default=None,
                   help=f"maximum time step in units of sqrt(L0*C0) (default {DEFAULT_DT})")


def build_parser() -> argparse.ArgumentParser:
    parser = _Parser(prog="lcchain", description="Quasi-uniform spring-mass chains and their LC ladders in ngspice.")
    parser.add_argument("-v", "--verbose", action="store_true", help="log every ngspice run to stderr")
    parser.add_argument("--version", action="version", version=f"lcchain {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=_Parser)
    sub.required = True

    p = sub.add_parser("design", help="optimal one-mass or two-mass chain for N (a row of Table I or II)")
    p.add_argument("--case", choices=DESIGN_CASES, required=True)
    p.add_argument("--N", type=int, required=True)
    p.add_argument("--json", action="store_true")
    p.set_defaults(func=cmd_design)

    p = sub.add_parser("table", help="Table I (one-mass) or II (two-mass) for a list of N")
    p.add_argument("--case", choices=DESIGN_CASES, required=True)
    p.add_argument("--N", type=_positive_int_list, default=[3, 4, 5, 6, 7, 8, 9, 10, 12, 14, 16, 18, 20, 100, 1000])
    out = p.add_mutually_exclusive_group()
    out.add_argument("--json", action="store_true")
    out.add_argument("--csv", action="store_true")
    p.set_defaults(func=cmd_table)

    p = sub.add_parser("asymptotic", help="N -> infinity: maximum of alpha_inf(tau, sigma) and the scaling laws")
    p.add_argument("--case", choices=DESIGN_CASES, default="two-mass")
    p.add_argument("--json", action="store_true")
    p.set_defaults(func=cmd_asymptotic)

    p = sub.add_parser("netlist", help="SPICE netlist of the equivalent LC ladder")
    _add_chain_arguments(p, with_dt=True)
    p.add_argument("-o", "--output", metavar="FILE", help="write here instead of stdout")
    p.set_defaults(func=cmd_netlist)

    p = sub.add_parser("reference-netlists", help="regenerate the reference netlists of netlists/")
    p.add_argument("--out", default="netlists", help="folder (default netlists)")
    p.set_defaults(func=cmd_reference_netlists)

    p = sub.add_parser("simulate", help="run the ladder in ngspice and compare with alpha_N(t)")
    _add_chain_arguments(p, with_dt=True)
    p.add_argument("--backend", choices=BACKENDS, default="batch")
    p.add_argument("--method", choices=METHODS, default="trap")
    p.add_argument("--accuracy", type=_float("--accuracy"), metavar="EPS",
                   help="wanted max |simulation - theory|: lcchain picks the largest dt that meets it "
                        "(instead of --dt)")
    p.add_argument("--plot", metavar="FILE", help="PNG: theory and simulation overlaid, residual below")
    p.add_argument("--netlist-out", metavar="FILE", help="keep the netlist that was run")
    p.add_argument("--waveform-out", metavar="FILE", help="CSV t,first,last (dimensionless)")
    p.add_argument("--json", action="store_true")
    p.set_defaults(func=cmd_simulate)

    p = sub.add_parser("run", help="run a scene (TOML experiment description)")
    p.add_argument("scene", metavar="SCENE.toml", nargs="+", help="one or more scene files, run in order")
    p.add_argument("--json", action="store_true", help="print the report as JSON (a list for several scenes)")
    p.add_argument("--side-by-side", metavar="FILE",
                   help="PNG: the scenes' overlays next to each other on shared axes")
    p.add_argument("--netlist-out", metavar="FILE", help="keep the (first sample's) netlist")
    p.add_argument("--waveform-out", metavar="FILE", help="CSV t,first,last (first sample, dimensionless)")
    p.set_defaults(func=cmd_run)

    p = sub.add_parser("bench", help="benchmarks (accuracy: what each digit costs per method and N)")
    bench = p.add_subparsers(dest="bench", metavar="BENCH", parser_class=_Parser)
    bench.required = True
    b = bench.add_parser("accuracy", help="sweep dt x method x stepping, DOP853 and the modal sum as peers")
    b.add_argument("--N", type=_positive_int_list, help="chain sizes (default 20,100,1000; --quick: 20,100)")
    b.add_argument("--quick", action="store_true", help="fewer steps and tolerances (under 2 minutes)")
    b.add_argument("--out", default="benchmarks/accuracy", help="output folder (default benchmarks/accuracy)")
    b.set_defaults(func=cmd_bench_accuracy)

    p = sub.add_parser("doctor", help="check ngspice, its shared library and PySpice")
    p.set_defaults(func=cmd_doctor)
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


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command line; returns the exit status."""
    argv = list(sys.argv[1:] if argv is None else argv)
    parser = build_parser()
    try:
        args = parser.parse_args(argv)
    except _UsageError as error:
        print(str(error), file=sys.stderr)
        return EXIT_USAGE
    except SystemExit as exit_:  # --help, --version
        return int(exit_.code or 0)
    args.argv_echo = argv[1:]
    logging.basicConfig(level=logging.INFO if args.verbose else logging.WARNING, format="lcchain: %(message)s")
    try:
        with _signals_interrupt(), threadpool_limits(limits=BLAS_THREADS, user_api="blas"):
            return int(args.func(args))
    except SimulatorMissingError as error:
        print(f"lcchain: {error}", file=sys.stderr)
        return EXIT_MISSING
    except ParameterError as error:
        print(f"lcchain: {error}", file=sys.stderr)
        return EXIT_USAGE
    except SimulationError as error:
        print(f"lcchain: simulation failed: {error}", file=sys.stderr)
        return EXIT_FAILED
    except LcchainError as error:
        print(f"lcchain: {error}", file=sys.stderr)
        return EXIT_FAILED
    except OSError as error:  # e.g. a disk full or a folder removed while running
        print(f"lcchain: {error.filename or ''}: {error.strerror or error}", file=sys.stderr)
        return EXIT_FAILED
    except KeyboardInterrupt:
        print("lcchain: interrupted", file=sys.stderr)
        return 130
    except Interrupted as interrupt:
        print(f"lcchain: interrupted by signal {interrupt.signum}", file=sys.stderr)
        return 128 + interrupt.signum


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
