"""Every request priced before it starts (issue 19, section 2): studies from their axes, designs with their fixed
cost, scene samples with their theory, the bench too; the interpreter's own memory and start in every estimate.

Each refusal must come within seconds (``seconds=20``: a study used to plan a 1000-value axis for minutes
before its price was known) and name the option, the estimate and the limit.
"""

from __future__ import annotations

import pytest
from helpers.catalogue import Case, run_case

from lcchain.cli import main
from lcchain.core.budget import INTERPRETER_BYTES, INTERPRETER_SECONDS, Budget, design_estimate, run_estimate
from lcchain.studies.bench import bench_estimate

AXIS = ",".join(str(n) for n in range(3, 1003))
SAMPLES = '[chain]\ncase = "two-mass"\nN = 50\n[effects.tolerance]\nL = 0.05\nsamples = 2000\nseed = 1\n'


def _priced(argv: list[str], said: list[str], files: dict[str, str | bytes] | None = None) -> Case:
    return Case(argv, said, files=files or {}, family="pricing", seconds=20.0)


CASES: dict[str, Case] = {
    "a 1000-value N axis": _priced(["sweep", "--case", "two-mass", "--N", AXIS, "--dt", "0.05", "--store", "s.sqlite",
                                    "--max-time", "10min"], ["--N = '1000 points'", "10 min", "--max-time"]),
    "a 1000-value N axis of a scene": _priced(["sweep", "s.toml", "--vary", f"chain.N={AXIS}", "--store", "s.sqlite",
                                               "--max-time", "2min"], ["--vary/--samples = '1000 scenes'", "2 min"],
                                              {"s.toml": '[chain]\ncase = "two-mass"\nN = 10\n'}),
    "a table of 500 designs": _priced(["table", "--case", "two-mass", "--N", ",".join(str(n) for n in range(3, 503)),
                                       "--max-time", "30s"], ["--N", "500 two-mass designs", "30 s"]),
    "a scene of 2000 samples": _priced(["run", "s.toml", "--max-time", "30s"],
                                       ["effects.tolerance.samples = 2000", "30 s"], {"s.toml": SAMPLES}),
    "a sweep of 2000 samples": _priced(["sweep", "s.toml", "--store", "s.sqlite", "--max-time", "30s"],
                                       ["--vary/--samples", "30 s"], {"s.toml": SAMPLES}),
    "the full accuracy bench in 5 min": _priced(["bench", "accuracy", "--out", "b", "--max-time", "5min"],
                                                ["bench accuracy", "5 min", "--quick"]),
    "the quick bench in 1 s": _priced(["bench", "accuracy", "--quick", "--out", "b", "--max-time", "1s"],
                                      ["bench accuracy", "--max-time"]),
    "a bench in 1 MiB": _priced(["bench", "accuracy", "--quick", "--out", "b", "--max-memory", "1M"],
                                ["bench accuracy", "--max-memory"]),
    "a design within the interpreter's own memory": _priced(["design", "--case", "two-mass", "--N", "10",
                                                             "--max-memory", "50M"],
                                                            ["--max-memory = '50M'", "96 MiB (the interpreter's own"]),
}


@pytest.mark.ngspice
@pytest.mark.parametrize("case", CASES.values(), ids=CASES.keys())
def test_a_request_beyond_its_budget_is_refused_before_any_work(case: Case, tmp_path) -> None:
    outcome = run_case(case, tmp_path, main)
    assert outcome.kind == "clean", outcome.detail


def test_every_estimate_counts_the_interpreter() -> None:
    """A request that needs nothing still costs the interpreter: 50 MiB or half a second is not enough."""
    nothing = run_estimate(points=1, saved=1, compared=0, unknowns=1)
    assert nothing.total_memory >= INTERPRETER_BYTES and nothing.total_seconds >= INTERPRETER_SECONDS
    assert not nothing.fits(Budget(max_memory=50 * 2**20)) and not nothing.fits(Budget(max_seconds=0.5))
    assert nothing.fits(Budget())


def test_a_design_has_a_fixed_cost_and_the_bench_a_price() -> None:
    """Two-mass designs cost 0.2 s at any N (measured, benchmarks/pricing.md): 500 of them are not 25 s."""
    assert sum(design_estimate("two-mass", N).seconds for N in range(3, 503)) > 100
    quick, full = bench_estimate(quick=True), bench_estimate()
    assert 0 < quick.seconds < full.seconds and full.seconds > 5 * 60


def test_an_ac_sweep_is_priced_with_its_fit(tmp_path, monkeypatch, capsys):
    """A study of AC runs is priced as each run is (the engine's frequencies x unknowns, and the fit): three
    two-mass-sized spectra of N = 200 (priced 0.36 s each: 0.22 s of ngspice, 0.13 s of the fit from theory's poles;
    2.4 s with the interpreter and the theory) do not fit in 2 s on one worker, though each does alone; the
    transient model priced them at 0.2 s each."""
    monkeypatch.chdir(tmp_path)
    argv = ["sweep", "--case", "two-mass,one-mass,uniform-bounded", "--N", "200", "--analysis", "ac",
            "--workers", "1", "--store", "p.sqlite"]
    assert main([*argv, "--max-time", "2"]) == 2
    error = capsys.readouterr().err
    assert "3 runs on 1 worker" in error and "--max-time" in error and not (tmp_path / "p.sqlite").exists()
