"""Parts added from outside lcchain (issue 20, docs/extending.md): effects and an engine defined here, in the
tests folder, run through simulate and a study without any edit to lcchain."""

from __future__ import annotations

import dataclasses
import os
import re
import subprocess
import sys
import textwrap
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import ClassVar

import numpy as np
import pytest
from helpers.tolerances import ATOL_EFFECT_RUN, PREDICTION_FACTOR

import lcchain
from lcchain.circuit.effects import Effect
from lcchain.circuit.ladder import Ladder
from lcchain.circuit.netlist import SimulationOptions, ac_netlist_text, netlist_text
from lcchain.cli.main import main
from lcchain.core.errors import ParameterError
from lcchain.core.types import Backend
from lcchain.runs.request import Request, Transient, plan_request
from lcchain.runs.spectrum import SpectrumOptions, measure_spectrum
from lcchain.spice.ac import AcJob, run_ac
from lcchain.spice.engines import ENGINES
from lcchain.spice.job import Progress, RunJob
from lcchain.spice.ngspice.engine import Ngspice
from lcchain.spice.ngspice.find import find_simulator
from lcchain.spice.ngspice.runner import run
from lcchain.spice.result import RunResult
from lcchain.spice.simulator import Simulator
from lcchain.studies.options import RunOptions
from lcchain.studies.plan import request_plan
from lcchain.studies.run import run_plan
from lcchain.studies.store import Store
from lcchain.theory.cases import chain_for_case
from lcchain.theory.chain import Chain


@dataclass(frozen=True)
class HeavyEnds(Effect):
    """Test-only effect: both end coils ``factor`` times their design value (a chain change, so the netlist and
    the exact theory both follow from the realised chain)."""

    key: ClassVar[str] = "heavy_ends"
    factor: float

    def realise(self, chain: Chain, L0: float, C0: float) -> Chain:
        masses = np.array(chain.masses)
        masses[[0, -1]] *= self.factor
        return Chain(masses, chain.springs, name=chain.name, coupling=chain.coupling)


@dataclass(frozen=True)
class SeriesProbe(Effect):
    """Test-only effect: a 1 uohm resistor after every inductor (an element in series no chain can say)."""

    key: ClassVar[str] = "series_probe"

    def in_series(self, ladder: Ladder, loop: int) -> tuple[tuple[str, float], ...]:
        return (("R", 1e-6),)


def test_an_outside_effect_changes_netlist_and_theory_together():
    chain = chain_for_case("two-mass", 12)
    plain, heavy = (plan_request(Request(chain, Transient(dt=0.05), effects=effects)).specs[0]
                    for effects in ((), (HeavyEnds(1.25),)))
    assert heavy.theory.chain.masses[0] == 1.25 * chain.masses[0]
    assert f"L1 0 n1 {float(1.25 * chain.masses[0]) * 10e-6!r} IC=" in heavy.netlist
    assert plain.netlist != heavy.netlist
    # An effect whose elements the chain's theory cannot say is compared with the circuit's own theory of what it
    # writes, whatever its type (never with the chain's, to a wrong "ok"); the netlist writes the same elements.
    probe = plan_request(Request(chain, Transient(dt=0.05), effects=(SeriesProbe(),))).specs[0]
    assert probe.theory.circuit is not None and plain.theory.circuit is None
    assert sum(1 for e in probe.theory.circuit if e.kind == "R") == chain.N
    text = netlist_text(Ladder(chain), SimulationOptions(dt=0.05, tstop=10.0), effects=(SeriesProbe(),))
    assert "R1 m1 n1 1e-06" in text and text.count("\nR") == chain.N


@pytest.mark.ngspice
def test_an_outside_effect_runs_in_simulate_and_in_a_study(tmp_path):
    chain = chain_for_case("two-mass", 20)
    report = lcchain.simulate(Request(chain, Transient(dt=0.02, transits=2), effects=(HeavyEnds(1.1),)))
    assert report.chain.masses[-1] == 1.1 * chain.masses[-1]
    assert report.predicted_error is not None
    assert report.comparison.max_abs_error <= PREDICTION_FACTOR * report.predicted_error
    points = [({"factor": f}, Request(chain, Transient(dt=0.05), effects=(HeavyEnds(f),))) for f in (1.0, 1.2)]
    plan = request_plan(points)
    assert plan.axes == ("factor",) and len(plan.tasks) == 2
    summary = run_plan(plan, tmp_path / "heavy.sqlite", RunOptions(executor="process", workers=2))
    assert summary.ok == 2 and summary.failed == 0


class WrappedNgspice(Ngspice):
    """Test-only engine: ngspice under another name, with a dialect of its own (a comment after the title)."""

    name: ClassVar[str] = "wrapped-ngspice"
    runs_ac: ClassVar[bool] = False  # it wraps ngspice's transient only
    MARK = "* run by the test-only engine"

    def find(self, backend: Backend = "batch") -> Simulator:
        return dataclasses.replace(find_simulator(backend), engine=self.name)

    def dialect(self, netlist: str, vectors: Sequence[str]) -> str:
        title, rest = netlist.split("\n", 1)
        return f"{title}\n{self.MARK}\n{rest}"

    def run(self, job: RunJob, simulator: Simulator, progress: Progress | None = None) -> RunResult:
        ours = dataclasses.replace(job, netlist=self.dialect(job.netlist, job.vectors))
        result = run(ours, dataclasses.replace(simulator, engine="ngspice"), progress=progress)
        return dataclasses.replace(result, engine=self.name)


@pytest.mark.ngspice
def test_an_outside_engine_runs_in_simulate_and_in_a_study(tmp_path, monkeypatch):
    monkeypatch.setitem(ENGINES, WrappedNgspice.name, WrappedNgspice())  # one registry line, from outside
    chain = chain_for_case("perfect", 16)
    ours = lcchain.simulate_chain(chain, lcchain.ChainOptions(dt=0.05, engine="wrapped-ngspice"))
    plain = lcchain.simulate_chain(chain, lcchain.ChainOptions(dt=0.05))
    assert ours.run.engine == "wrapped-ngspice" and ours.record.engine == "wrapped-ngspice"
    assert ours.run.netlist_sha256 != plain.run.netlist_sha256  # it ran its own dialect...
    assert np.array_equal(ours.waveforms.last, plain.waveforms.last)  # ...of the same circuit
    assert ours.record.key != plain.record.key  # a record of another engine is never another's
    points = [({"N": n}, Request(chain_for_case("perfect", n), Transient(dt=0.05), engine="wrapped-ngspice"))
              for n in (8, 12)]
    store = tmp_path / "wrapped.sqlite"
    summary = run_plan(request_plan(points), store, RunOptions(executor="serial"))
    assert summary.ok == 2
    with Store(store, "read") as opened:
        engines = {row.engine for row in opened.runs()}
    assert engines == {"wrapped-ngspice"}


@pytest.mark.ngspice
def test_an_outside_engine_without_an_ac_analysis_is_refused_in_one_line(monkeypatch, capsys):
    monkeypatch.setitem(ENGINES, WrappedNgspice.name, WrappedNgspice())
    chain = chain_for_case("two-mass", 8)
    with pytest.raises(ParameterError, match="engine = 'wrapped-ngspice' .*an AC analysis: ngspice") as error:
        measure_spectrum(chain, options=SpectrumOptions(engine="wrapped-ngspice"))
    assert error.value.field == "engine"
    text = ac_netlist_text(Ladder(chain, 10e-6, 1e-6), points=32, omega_max=2.1)
    with pytest.raises(ParameterError, match="engine = 'wrapped-ngspice'"):
        run_ac(AcJob(text, ["i(l1)"], 32), WrappedNgspice().find())
    assert main(["spectrum", "--case", "two-mass", "--N", "8", "--engine", "wrapped-ngspice"]) == 2
    err = capsys.readouterr().err.strip()
    assert "wrapped-ngspice" in err and "\n" not in err


# ------------------------------------------------------ the recipe of docs/extending.md, followed literally
DOC = Path(__file__).parent.parent / "docs" / "extending.md"
RECIPE_MARK = "<!-- recipe: effect -->"


def recipe_blocks(text: str) -> list[str]:
    """The fenced python blocks that follow the recipe's marker, in order."""
    blocks = []
    for part in text.split(RECIPE_MARK)[1:]:
        match = re.match(r"\s*```python\n(.*?)\n```", part, re.DOTALL)
        assert match, f"a {RECIPE_MARK} not followed by a python block"
        blocks.append(match.group(1))
    return blocks


def test_the_recipe_has_an_effect_a_registration_and_a_run():
    blocks = recipe_blocks(DOC.read_text(encoding="utf-8"))
    assert len(blocks) == 3
    assert "class Leakage(Effect)" in blocks[0] and "def across_capacitor" in blocks[0]
    assert "EFFECTS[Leakage.key] = Leakage" in blocks[1]
    assert "lcchain.simulate(Request(chain, Transient(dt=0.02), effects=(Leakage(" in blocks[2]


@pytest.mark.ngspice
def test_the_docs_recipe_runs_as_written(tmp_path):
    """docs/extending.md's blocks, one script in a fresh interpreter: an effect with a new kind of element (a
    resistor across every capacitor), registered outside lcchain, runs in ngspice against the circuit's exact
    theory; then it is a scene table and an option of its own."""
    script = "\n\n".join(recipe_blocks(DOC.read_text(encoding="utf-8")))
    script += textwrap.dedent("""

        from lcchain.scenes.load import parse_scene
        from lcchain.cli.main import build_parser

        assert report.comparison.max_abs_error < ATOL
        assert "RA1_2 n1 0 " in report.netlist
        scene = parse_scene({"chain": {"case": "two-mass", "N": 10}, "effects": {"leakage": {"R": 100}}})
        assert scene.effects.present() == (Leakage(100.0),) and parse_scene(scene.to_dict()) == scene
        args = build_parser().parse_args(["simulate", "--case", "two-mass", "--N", "10", "--leakage", "100"])
        assert args.leakage == 100.0
        print("recipe ok")
    """).replace("ATOL", repr(ATOL_EFFECT_RUN))
    (tmp_path / "recipe.py").write_text(script, encoding="utf-8")
    env = {**os.environ, "TMPDIR": str(tmp_path), "PYTHONDONTWRITEBYTECODE": "1"}
    done = subprocess.run([sys.executable, "recipe.py"], cwd=tmp_path, env=env, capture_output=True, text=True,
                          timeout=600)
    assert done.returncode == 0, done.stderr
    assert done.stdout.splitlines()[-1] == "recipe ok"
    assert done.stdout.startswith("max |ngspice - exact theory| = ")
