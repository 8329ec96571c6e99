"""Each command imports only what it needs (issue 35): a guard, so that no later import undoes it.

Lazy imports were made once (issue 23) and undone by a later change that no test noticed: ``lcchain batch`` of
one netlist went back to 1.4 s, 0.6 s of it importing ``scipy.interpolate`` for a fit it never made.  Here every
command of the parser (read from :func:`lcchain.cli.main.build_parser`, so a new command is covered without an
edit) runs its ``--help`` in a fresh interpreter under ``python -X importtime``, which names every module the
process imports and the module that imported it; a command that does work without scipy (``batch`` of a foreign
netlist, ``results`` as a table) also runs for real.  A heavy module on the forbidden list fails the test with
the chain of imports that brought it in.  Timings are in ``benchmarks/start.md``, not here: this asserts which
modules load, which no noisy machine can change.
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
from collections.abc import Iterator
from pathlib import Path

import pytest
from helpers.netlists import RC_NETLIST

from lcchain.cli.main import build_parser

ROOT = Path(__file__).resolve().parent.parent

#: Top-level packages no command loads before it does work: the numerics beyond numpy, plots, tables, arrays
#: with labels, the cluster, the shared library.  Those that need one import it inside the function that uses
#: it (``import scipy.linalg`` in the function body, or ``import scipy`` and its submodules on first use).
HEAVY = ("scipy", "matplotlib", "pandas", "xarray", "dask", "distributed", "PySpice")


#: Lighter modules a batch of foreign netlists has no use for, each found on its start once (issue 35): numpy's
#: masked arrays (``np.unique`` imports them), its polynomials (a pulse's quadrature nodes), a process pool's
#: machinery (a batch's runs are driven by threads), the entry points' reader (ngspice is an own engine, which no
#: plugin can take: looking it up reads no entry point), threadpoolctl (a command line's process loads its BLAS with
#: OPENBLAS_NUM_THREADS set, and a batch computes no theory, whose limit it sets).
BATCH_UNNEEDED = ("numpy.ma", "numpy.polynomial", "multiprocessing", "concurrent.futures.process", "importlib.metadata",
                  "threadpoolctl", "decimal")


def loaded(chains: dict[str, list[str]], names: tuple[str, ...]) -> list[str]:
    """The modules of ``names`` (or their submodules) in ``chains``, each with the chain that imported it."""
    return [" <- ".join(chain) for name, chain in chains.items()
            if any(name == n or name.startswith(n + ".") for n in names)
            and not any(importer.startswith(names) for importer in chain[1:])]


def heavy(module: str, allowed: tuple[str, ...] = ()) -> bool:
    """One of :data:`HEAVY` or a module of one (``scipy.interpolate._bsplines``, ``matplotlib.pyplot``), unless
    ``allowed`` names its scipy subpackage (``("scipy.linalg",)`` allows it, scipy and scipy's private modules)."""
    if module.partition(".")[0] not in HEAVY:
        return False
    if allowed and (module == "scipy" or module.startswith(("scipy._", "scipy.version"))):
        return False
    return not any(module == name or module.startswith(name + ".") for name in allowed)


def commands(parser: argparse.ArgumentParser, prefix: tuple[str, ...] = ()) -> Iterator[tuple[str, ...]]:
    """Every command and subcommand of the parser (``("bench",)``, ``("bench", "accuracy")``, ...)."""
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            for name, sub in action.choices.items():
                yield (*prefix, name)
                yield from commands(sub, (*prefix, name))


def imports(argv: list[str], cwd: Path) -> tuple[subprocess.CompletedProcess[str], dict[str, list[str]]]:
    """Run ``python -X importtime -m lcchain ARGV``; every module it imported -> the chain that imported it
    (the module, its importer, ... up to the top)."""
    done = subprocess.run([sys.executable, "-X", "importtime", "-m", "lcchain", *argv], capture_output=True,
                          text=True, cwd=cwd)
    rows = []  # (depth, module), in the order importtime prints them: a module after everything it imported
    for line in done.stderr.splitlines():
        if line.startswith("import time:") and "[us]" not in line:
            name = line.split("|")[2]
            rows.append(((len(name) - len(name.lstrip())) // 2, name.strip()))
    chains = {}
    for i, (depth, name) in enumerate(rows):
        chain = [name]
        for later_depth, later in rows[i + 1:]:
            if later_depth < depth:  # the first shallower module printed after this one is its importer
                chain.append(later)
                depth = later_depth
        chains.setdefault(name, chain)
    return done, chains


def forbidden(chains: dict[str, list[str]], allowed: tuple[str, ...] = ()) -> list[str]:
    """The heavy modules lcchain imported (not those a heavy package imports for itself: what ``scipy.linalg``
    needs is its own business), each with the chain that brought it in."""
    return [" <- ".join(chain) for name, chain in chains.items()
            if heavy(name, allowed) and not any(heavy(importer) for importer in chain[1:])]


def test_heavy_names_what_it_should() -> None:
    assert heavy("scipy") and heavy("scipy.interpolate") and heavy("scipy._lib._ccallback")
    assert heavy("matplotlib.pyplot") and heavy("dask") and heavy("pandas.core.frame")
    assert not heavy("numpy") and not heavy("lcchain.report.plots") and not heavy("daskish")
    linalg = ("scipy.linalg",)
    assert not heavy("scipy", linalg) and not heavy("scipy.linalg._basic", linalg) and not heavy("scipy._lib", linalg)
    assert heavy("scipy.optimize", linalg) and heavy("scipy.linalgx", linalg) and heavy("matplotlib", linalg)
    assert not heavy("scipy.optimize", ("scipy",)) and heavy("matplotlib.pyplot", ("scipy",))


#: Imports every module of lcchain (the CLI's too) in turn and prints, as JSON, each heavy module (a scipy
#: subpackage, or a package of HEAVY other than scipy) -> the lcchain module whose import first loaded it.
EVERY_MODULE = """\
import importlib, json, pkgutil, sys
import lcchain
HEAVY = {heavy!r}
def heavy():
    return {{m for m in sys.modules if m.partition(".")[0] in HEAVY and m != "scipy"
             and not m.startswith(("scipy._", "scipy.version"))}}
loaded, seen = {{}}, heavy()
for name in sorted(m.name for m in pkgutil.walk_packages(lcchain.__path__, "lcchain.")):
    if name.endswith("__main__"):
        continue
    importlib.import_module(name)
    for module in heavy() - seen:
        loaded[module] = name
    seen = heavy()
print(json.dumps(loaded))
"""


def test_no_module_imports_a_heavy_package_at_its_top() -> None:
    """Every module of lcchain imports scipy's subpackages, matplotlib, pandas, xarray, dask and PySpice inside the
    functions that use them (or ``import scipy`` and uses its submodules, which load on first use): importing a
    module for one name never costs a command a heavy package it does not use.  Imports made at a module's top
    are in order, in one thread, so this check is exact where a command's run (threads, lazy attributes) is not;
    it would have caught ``from scipy.interpolate import AAA`` in compare.poles, which every request imports."""
    code = EVERY_MODULE.format(heavy=HEAVY)
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=ROOT)
    assert done.returncode == 0, done.stderr[-2000:]
    by_module: dict[str, set[str]] = {}
    for module, by in json.loads(done.stdout).items():  # scipy.fft._basic -> scipy.fft, matplotlib.pyplot -> matplotlib
        by_module.setdefault(by, set()).add(".".join(module.split(".")[:2 if module.startswith("scipy.") else 1]))
    assert not by_module, "\n".join(f"importing {by} loads {', '.join(sorted(names))}" for by, names in by_module.items())


def test_every_command_is_found() -> None:
    """The list below is read from the parser: these must be in it, and a new command joins it by itself."""
    found = set(commands(build_parser()))
    assert {("batch",), ("results",), ("simulate",), ("report",), ("bench",), ("bench", "accuracy")} <= found


@pytest.mark.parametrize("command", [(), *commands(build_parser())], ids=lambda c: " ".join(c) or "lcchain")
def test_help_imports_nothing_heavy(command: tuple[str, ...]) -> None:
    """``lcchain [COMMAND] --help`` builds every parser and imports no scipy, plotting, table or cluster module."""
    done, chains = imports([*command, "--help"], ROOT)
    assert done.returncode == 0, done.stderr[-2000:]
    assert "usage: lcchain" in done.stdout
    assert not forbidden(chains), "\n".join(forbidden(chains))


def test_version_imports_nothing_heavy() -> None:
    done, chains = imports(["--version"], ROOT)
    assert done.returncode == 0, done.stderr[-2000:]
    assert not forbidden(chains), "\n".join(forbidden(chains))




#: Commands that start without numpy (issue 35: a fixed start under 0.15 s, of which numpy alone took 0.08 s and,
#: with OpenBLAS's threads spinning, 0.15 s of CPU): those about no chain.  A command about a chain imports it
#: with the chain's options and effects, which compute.
WITHOUT_NUMPY = (("--version",), ("--help",), ("batch", "--help"), ("results", "--help"), ("report", "--help"))


@pytest.mark.parametrize("command", WITHOUT_NUMPY, ids=" ".join)
def test_a_command_about_no_chain_starts_without_numpy(command: tuple[str, ...]) -> None:
    done, chains = imports(list(command), ROOT)
    assert done.returncode == 0, done.stderr[-2000:]
    assert not loaded(chains, ("numpy",)), "\n".join(loaded(chains, ("numpy",)))


#: A batch's engine found (``ngspice -v``, the sandbox's trial run) by what ``lcchain batch`` imports before its
#: plan: prints the numpy modules loaded by then.
ENGINE_FIRST = """\
import sys
from lcchain.app.batch import batch
from lcchain.spice.engines import DEFAULT_ENGINE
from lcchain.studies.executors import EngineStart
with EngineStart(DEFAULT_ENGINE, "batch", runs=0, workers=1, executor="process", transport="auto") as start:
    print(start.simulator().engine)
print(sorted(name for name in sys.modules if name.partition(".")[0] == "numpy"))
"""


@pytest.mark.ngspice
def test_a_batch_finds_its_engine_before_numpy_loads(tmp_path: Path) -> None:
    """``lcchain batch`` starts finding ngspice (a subprocess, and the sandbox's) before it plans: the modules that
    do it load no numpy, so the engine's start overlaps numpy's import and the plan's, not the other way round."""
    done = subprocess.run([sys.executable, "-c", ENGINE_FIRST], capture_output=True, text=True, cwd=tmp_path)
    assert done.returncode == 0, done.stderr[-2000:]
    engine, numpy_modules = done.stdout.splitlines()
    assert engine == "ngspice"
    assert numpy_modules == "[]"


@pytest.mark.ngspice
def test_batch_and_results_import_nothing_heavy(tmp_path: Path) -> None:
    """A foreign netlist checked, priced, run in ngspice and stored, then the store read back as a table: the
    allow-list, pricing, the store and running ngspice need numpy, never scipy (not even ``import scipy``),
    plots or tables."""
    netlist = tmp_path / "rc.cir"
    netlist.write_text(RC_NETLIST)
    store = tmp_path / "rc.sqlite"
    done, chains = imports(["batch", str(netlist), "--store", str(store)], ROOT)
    assert done.returncode == 0, done.stderr[-2000:]
    assert "1 ok" in done.stdout
    assert not forbidden(chains), "\n".join(forbidden(chains))
    assert not loaded(chains, BATCH_UNNEEDED), "\n".join(loaded(chains, BATCH_UNNEEDED))
    refused = tmp_path / "control.cir"  # refused by the allow-list: stored as such, the batch carries on (exit 1)
    refused.write_text(RC_NETLIST.replace(".end\n", ".control\nrun\n.endc\n.end\n"))
    done, chains = imports(["batch", str(netlist), str(refused), "--store", str(tmp_path / "refused.sqlite")], ROOT)
    assert done.returncode == 1, done.stderr[-2000:]
    assert "1 refused" in done.stdout
    assert not forbidden(chains), "\n".join(forbidden(chains))
    for argv in (["results", str(store)], ["results", str(store), "--json"], ["results", str(store), "--csv"]):
        done, chains = imports(argv, ROOT)
        assert done.returncode == 0, done.stderr[-2000:]
        assert not forbidden(chains), f"{argv}:\n" + "\n".join(forbidden(chains))


@pytest.mark.ngspice
def test_a_sweep_of_a_netlist_imports_nothing_heavy(tmp_path: Path) -> None:
    """``sweep --netlist``: the batch's allow-list, pricing and store, the variants' text and the seeded draws
    (numpy only): no scipy, plots or tables."""
    netlist = tmp_path / "rc.cir"
    netlist.write_text(RC_NETLIST.replace("C1 out 0 1e-9", ".param cv = 1e-9\nC1 out 0 {cv}"))
    done, chains = imports(["sweep", "--netlist", str(netlist), "--vary", "R1=1k,2k", "--vary",
                            "cv=normal:1n:5%", "--samples", "2", "--store", str(tmp_path / "s.sqlite")], ROOT)
    assert done.returncode == 0, done.stderr[-2000:]
    assert "4 ok" in done.stdout
    assert not forbidden(chains), "\n".join(forbidden(chains))


#: Commands that do their work here (``{tmp}``: a temporary folder) -> the scipy subpackages their work needs.
#: ``netlist`` of a chain it need not design solves the chain's modes (its stop time), nothing else.
RUNS = {
    "netlist --case perfect": (["netlist", "--case", "perfect", "--N", "5", "-o", "{tmp}/perfect.cir"],
                               ("scipy.linalg",)),
    "netlist --chain": (["netlist", "--chain", "{tmp}/chain.json", "-o", "{tmp}/chain.cir"], ("scipy.linalg",)),
    "examples": (["examples"], ()),
}


#: Commands that run ngspice and compare with theory: scipy is theirs, plots (without --plot), tables and the
#: cluster (without --executor dask) are not.
NGSPICE_RUNS = {
    "simulate": (["simulate", "--case", "two-mass", "--N", "5"], ("scipy",)),
    "spectrum": (["spectrum", "--case", "two-mass", "--N", "5"], ("scipy",)),
    "sweep": (["sweep", "--case", "two-mass", "--N", "4,5", "--dt", "0.1", "--store", "{tmp}/sweep.sqlite"],
              ("scipy",)),
}


@pytest.mark.parametrize("name", [*RUNS, *(pytest.param(name, marks=pytest.mark.ngspice) for name in NGSPICE_RUNS)])
def test_work_imports_only_what_it_needs(name: str, tmp_path: Path) -> None:
    (tmp_path / "chain.json").write_text('{"masses": [1, 1, 1, 1], "springs": [0, 1, 1, 1, 0]}')
    argv, allowed = {**RUNS, **NGSPICE_RUNS}[name]
    done, chains = imports([a.replace("{tmp}", str(tmp_path)) for a in argv], ROOT)
    assert done.returncode == 0, done.stderr[-2000:]
    assert not forbidden(chains, allowed), "\n".join(forbidden(chains, allowed))


@pytest.mark.ngspice
def test_results_of_an_ac_study_import_nothing_heavy(tmp_path: Path) -> None:
    """An AC sweep's store holds spectral metrics (compare.spectral names them): reading it back needs no fit."""
    store = tmp_path / "ac.sqlite"
    done = subprocess.run([sys.executable, "-m", "lcchain", "sweep", "--case", "two-mass", "--N", "4", "--analysis",
                           "ac", "--store", str(store)], capture_output=True, text=True, cwd=ROOT)
    assert done.returncode == 0, done.stderr[-2000:]
    for argv in (["results", str(store)], ["results", str(store), "--csv"],
                 ["results", str(store), "--summary", "--metric", "omega"]):
        done, chains = imports(argv, ROOT)
        assert done.returncode == 0, done.stderr[-2000:]
        assert not forbidden(chains), f"{argv}:\n" + "\n".join(forbidden(chains))


def test_a_warm_worker_greets_before_loading_what_it_does_not_need_for_it() -> None:
    """A warm worker (``python -S -P -m lcchain.spice.ngspice.warm_worker``, started for every batch) sends its hello
    after loading only the library: its module imports no ``typing``, ``json``, ``re`` or ``hashlib`` (OpenSSL), which
    together cost it about 20 ms of a batch's start; the line split and digest load after the hello."""
    from lcchain.spice.processes import PACKAGE_ROOT

    probe = "import sys, lcchain.spice.ngspice.warm_worker; print(' '.join(sorted(sys.modules)))"
    done = subprocess.run([sys.executable, "-S", "-P", "-c", probe], capture_output=True, text=True, check=True,
                          env={"PYTHONPATH": PACKAGE_ROOT})
    modules = set(done.stdout.split())
    assert "lcchain.spice.ngspice.warm_worker" in modules
    assert not modules & {"typing", "re", "json", "hashlib", "_hashlib", "lcchain.spice.text"}, sorted(modules)


FIRST_RUN = """\
import sys
from lcchain.spice.ngspice import warm

loaded = []
original = warm.WarmWorker.run


def run(self, job):  # what of numpy, and of what only a batch of more than stream.HELD runs needs, is loaded
    loaded.append(",".join(name for name in ("numpy", "pickle", "ctypes") if name in sys.modules) or "none")
    return original(self, job)


warm.WarmWorker.run = run
from lcchain.cli.main import main

status = main(["batch", *sys.argv[1:], "--workers", "1", "--store", "s.sqlite", "--json"])
print(status, loaded[0] if loaded else "no-warm-run", "numpy" in sys.modules)
"""


@pytest.mark.ngspice
def test_a_batch_sends_its_first_run_before_numpy_loads(tmp_path: Path) -> None:
    """``lcchain batch`` of netlists without breakpoints plans, prices, keys and stores every run and sends the first
    to a warm worker with no numpy loaded: numpy's import (50 to 100 ms) then overlaps that run (a thread of its
    own) instead of delaying the start, and the run's reply finds it loaded.  Nor is pickle loaded (4 ms), which
    only a batch of more runs than the spool holds in memory needs, nor ctypes (2 ms, for the BLAS limit of theory
    a batch does not compute)."""
    import lcchain
    from lcchain.runs.simulate import ChainOptions, simulation_spec

    spec, _, _ = simulation_spec(lcchain.chain_for_case("two-mass", 6), ChainOptions(dt=0.05, transits=1))
    names = []
    for i in range(12):  # distinct netlists, enough for a warm worker (WARM_MIN_RUNS_PER_WORKER)
        (tmp_path / f"n{i:02d}.cir").write_text(spec.netlist.replace("\n", f" #{i}\n", 1))
        names.append(f"n{i:02d}.cir")
    done = subprocess.run([sys.executable, "-c", FIRST_RUN, *names], capture_output=True, text=True, cwd=tmp_path)
    assert done.returncode == 0, done.stderr[-2000:]
    assert done.stdout.splitlines()[-1].split() == ["0", "none", "True"], done.stdout + done.stderr[-2000:]
