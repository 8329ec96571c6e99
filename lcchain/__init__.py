"""lcchain: quasi-uniform spring-mass chains (a Newton's cradle of springs)
and their LC-ladder equivalent, simulated in ngspice.

The package's folders follow the data's path (see README, "Layout")::

    core -> theory -> circuit -> spice -> compare -> runs -> scenes -> studies -> report -> cli

``import lcchain`` loads the theory and the orchestration, never matplotlib,
PySpice or Dask (those are imported on demand, in ``report``, ``spice``'s
child process and ``studies``).  ``lcchain.plots`` is
:mod:`lcchain.report.plots`, loaded when first used.
"""

from typing import Any

from .circuit.ladder import Ladder
from .circuit.netlist import SimulationOptions, netlist_text
from .compare.accuracy import dt_for_accuracy, predicted_error
from .core import __version__
from .core.errors import Interrupted, LcchainError, ParameterError, SimulationError, SimulatorMissingError
from .report.scenes import run_scene
from .runs.execute import RunRecord, execute
from .runs.simulate import SimulationReport, simulate
from .runs.spec import RunSpec, Theory
from .scenes.load import load_scene, parse_scene
from .scenes.run import simulate_scene
from .scenes.schema import Scene
from .spice.simulator import Simulator, find_simulator
from .theory.arrivals import Arrival, arrivals, first_arrival
from .theory.asymptotic import asymptotic_amplitude, asymptotic_optimum
from .theory.cases import chain_for_case
from .theory.chain import PERFECT_ARRIVAL, Chain
from .theory.closed_form import closed_form_modes
from .theory.design import Design, optimal_design, optimal_one_mass, optimal_two_mass
from .theory.modes import Modes
from .theory.response import linear_response
from .theory.spectrum import normal_modes, return_amplitude, transmission_amplitude

__all__ = [
    "Arrival", "arrivals", "first_arrival", "asymptotic_amplitude", "asymptotic_optimum", "chain_for_case",
    "PERFECT_ARRIVAL", "Chain", "closed_form_modes", "Design", "optimal_design", "optimal_one_mass",
    "optimal_two_mass", "LcchainError", "ParameterError", "SimulationError", "SimulatorMissingError", "Interrupted",
    "Modes", "normal_modes", "return_amplitude", "transmission_amplitude", "Ladder", "SimulationOptions",
    "netlist_text", "simulate", "SimulationReport", "dt_for_accuracy", "predicted_error", "linear_response", "Scene",
    "load_scene", "parse_scene", "run_scene", "simulate_scene", "RunSpec", "Theory", "RunRecord", "execute",
    "Simulator", "find_simulator", "__version__",
]


def __getattr__(name: str) -> Any:
    if name == "plots":  # matplotlib loads only when a figure is wanted
        from .report import plots

        return plots
    raise AttributeError(f"module 'lcchain' has no attribute {name!r}")
