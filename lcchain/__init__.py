"""lcchain: quasi-uniform spring-mass chains (a Newton's cradle of springs)
and their LC-ladder equivalent, simulated in ngspice.

The theory (numpy/scipy) is imported here; matplotlib and PySpice are never
imported by ``import lcchain`` (plots and the shared-library backend load
them on demand).
"""

from .accuracy import dt_for_accuracy, predicted_error
from .arrivals import Arrival, arrivals, first_arrival
from .asymptotic import asymptotic_amplitude, asymptotic_optimum
from .cases import chain_for_case
from .chain import PERFECT_ARRIVAL, Chain
from .closed_form import closed_form_modes
from .design import Design, optimal_design, optimal_one_mass, optimal_two_mass
from .errors import LcchainError, ParameterError, SimulationError, SimulatorMissingError
from .modes import Modes, normal_modes, return_amplitude, transmission_amplitude
from .netlist import Ladder, SimulationOptions, netlist_text
from .response import linear_response
from .scene import Scene, load_scene, parse_scene
from .scene_run import run_scene
from .simulation import simulate

__version__ = "0.1.0"

__all__ = [
    "Arrival", "arrivals", "first_arrival", "asymptotic_amplitude", "asymptotic_optimum", "chain_for_case",
    "PERFECT_ARRIVAL", "Chain", "closed_form_modes", "Design", "optimal_design", "optimal_one_mass",
    "optimal_two_mass", "LcchainError", "ParameterError", "SimulationError", "SimulatorMissingError", "Modes",
    "normal_modes", "return_amplitude", "transmission_amplitude", "Ladder", "SimulationOptions", "netlist_text",
    "simulate", "dt_for_accuracy", "predicted_error", "linear_response", "Scene", "load_scene", "parse_scene",
    "run_scene", "__version__",
]
