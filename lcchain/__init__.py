"""lcchain: quasi-uniform spring-mass chains (a Newton's cradle of springs)
and their LC-ladder equivalent, simulated in ngspice.

The package's folders follow the data's path (see docs/layout.md)::

    core -> theory -> circuit -> spice -> compare -> runs -> scenes -> studies -> report -> cli

The public names below load on first use (Scientific Python's SPEC 1), so
``import lcchain`` is quick for a pool worker or a command that needs little;
``import lcchain`` never loads matplotlib, PySpice or Dask.
``lcchain.plots`` is :mod:`lcchain.report.plots`.
"""

from __future__ import annotations

import importlib

from .core import __version__

#: ``typing.TYPE_CHECKING`` without importing typing (8 ms): every child lcchain starts (a warm ngspice worker)
#: imports this package first.  Type checkers read the name itself as true.
TYPE_CHECKING = False

if TYPE_CHECKING:  # what a type checker reads for each public name (they load on first use, below)
    from .app.scenes import SceneHooks, SceneRun, run_scene
    from .circuit.effects import (
        CapacitorESL,
        CapacitorESR,
        CoilCapacitance,
        CoilResistance,
        Coupling,
        Effect,
        Losses,
        PreferredValues,
        Tolerance,
        Walls,
    )
    from .circuit.ladder import Ladder
    from .circuit.netlist import SimulationOptions, netlist_text
    from .compare.accuracy import dt_for_accuracy, predicted_error
    from .core.budget import Budget
    from .core.errors import (
        DesignError,
        ExtraMissingError,
        Interrupted,
        LcchainError,
        ParameterError,
        SimulationError,
        SimulatorMissingError,
    )
    from .report import plots as plots
    from .runs.execute import RunRecord, execute
    from .runs.request import AC, Drive, Request, Transient, plan_request
    from .runs.simulate import ChainOptions, SimulationReport, simulate, simulate_chain
    from .runs.spec import RunSpec, Theory
    from .runs.spectrum import SpectrumReport, spectrum
    from .scenes.load import load_scene, parse_scene
    from .scenes.run import simulate_scene
    from .scenes.schema import Scene
    from .spice.ngspice.find import find_simulator
    from .spice.simulator import Simulator
    from .theory.arrivals import Arrival, arrivals, first_arrival
    from .theory.asymptotic import asymptotic_amplitude, asymptotic_optimum
    from .theory.cases import chain_for_case
    from .theory.chain import PERFECT_ARRIVAL, Chain
    from .theory.closed_form import closed_form_modes
    from .theory.design import Design, optimal_design, optimal_one_mass, optimal_two_mass
    from .theory.modes import Modes
    from .theory.perfect import PerfectDesign, chain_from_spectrum, perfect_design, spectrum_of
    from .theory.response import linear_response
    from .theory.spectrum import normal_modes, return_amplitude, transmission_amplitude

#: Public name -> the module that defines it.
_PUBLIC = {
    "Ladder": "circuit.ladder",
    "SimulationOptions": "circuit.netlist", "netlist_text": "circuit.netlist",
    "dt_for_accuracy": "compare.accuracy", "predicted_error": "compare.accuracy",
    "Interrupted": "core.errors", "LcchainError": "core.errors", "ParameterError": "core.errors",
    "DesignError": "core.errors",
    "SimulationError": "core.errors", "SimulatorMissingError": "core.errors", "ExtraMissingError": "core.errors",
    "Budget": "core.budget",
    "run_scene": "app.scenes", "SceneRun": "app.scenes", "SceneHooks": "app.scenes",
    "RunRecord": "runs.execute", "execute": "runs.execute",
    "SimulationReport": "runs.simulate", "simulate": "runs.simulate", "simulate_chain": "runs.simulate",
    "ChainOptions": "runs.simulate",
    "SpectrumReport": "runs.spectrum", "spectrum": "runs.spectrum",
    "Request": "runs.request", "Drive": "runs.request", "Transient": "runs.request", "AC": "runs.request",
    "plan_request": "runs.request",
    "Effect": "circuit.effects", "Walls": "circuit.effects", "Coupling": "circuit.effects",
    "Losses": "circuit.effects", "Tolerance": "circuit.effects", "PreferredValues": "circuit.effects",
    "CoilCapacitance": "circuit.effects", "CoilResistance": "circuit.effects", "CapacitorESR": "circuit.effects",
    "CapacitorESL": "circuit.effects",
    "RunSpec": "runs.spec", "Theory": "runs.spec",
    "load_scene": "scenes.load", "parse_scene": "scenes.load",
    "simulate_scene": "scenes.run", "Scene": "scenes.schema",
    "Simulator": "spice.simulator", "find_simulator": "spice.ngspice.find",
    "Arrival": "theory.arrivals", "arrivals": "theory.arrivals", "first_arrival": "theory.arrivals",
    "asymptotic_amplitude": "theory.asymptotic", "asymptotic_optimum": "theory.asymptotic",
    "chain_for_case": "theory.cases",
    "PERFECT_ARRIVAL": "theory.chain", "Chain": "theory.chain",
    "closed_form_modes": "theory.closed_form",
    "Design": "theory.design", "optimal_design": "theory.design", "optimal_one_mass": "theory.design",
    "optimal_two_mass": "theory.design",
    "Modes": "theory.modes",
    "PerfectDesign": "theory.perfect", "perfect_design": "theory.perfect", "chain_from_spectrum": "theory.perfect",
    "spectrum_of": "theory.perfect",
    "linear_response": "theory.response",
    "normal_modes": "theory.spectrum", "return_amplitude": "theory.spectrum",
    "transmission_amplitude": "theory.spectrum",
}

__all__ = [
    "Ladder", "SimulationOptions", "netlist_text", "dt_for_accuracy", "predicted_error", "Interrupted",
    "LcchainError", "ParameterError", "DesignError", "SimulationError", "SimulatorMissingError", "ExtraMissingError",
    "Budget",
    "run_scene", "SceneRun", "SceneHooks", "RunRecord",
    "execute", "SimulationReport", "simulate", "simulate_chain", "ChainOptions", "SpectrumReport", "spectrum",
    "Request", "Drive", "Transient", "AC", "plan_request", "Effect",
    "Walls",
    "Coupling", "Losses", "Tolerance", "PreferredValues", "CoilCapacitance", "CoilResistance", "CapacitorESR",
    "CapacitorESL", "RunSpec", "Theory", "load_scene", "parse_scene",
    "simulate_scene",
    "Scene", "Simulator", "find_simulator", "Arrival", "arrivals", "first_arrival", "asymptotic_amplitude",
    "asymptotic_optimum", "chain_for_case", "PERFECT_ARRIVAL", "Chain", "closed_form_modes", "Design",
    "optimal_design", "optimal_one_mass", "optimal_two_mass", "Modes", "PerfectDesign", "perfect_design",
    "chain_from_spectrum", "spectrum_of", "linear_response", "normal_modes",
    "return_amplitude", "transmission_amplitude", "__version__",
]


def __getattr__(name: str) -> object:
    if name == "plots":  # matplotlib loads only when a figure is wanted
        return importlib.import_module(".report.plots", __name__)
    if name in _PUBLIC:
        value = getattr(importlib.import_module(f".{_PUBLIC[name]}", __name__), name)
        globals()[name] = value  # looked up once
        return value
    raise AttributeError(f"module 'lcchain' has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted([*__all__, "plots"])
