"""``lcchain run`` for one scene as a function: check its outputs, simulate it, write its report and plots."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import replace

from ..core.budget import Budget
from ..core.checks import instance
from ..core.errors import ParameterError
from ..report.files import check_output
from ..report.scenes import check_scene_outputs, write_scene_outputs
from ..scenes.run import SceneResult, simulate_scene
from ..scenes.schema import Scene
from ..spice.simulator import Simulator

__all__ = ["run_scene"]


def run_scene(scene: Scene, *, netlist_out: str | None = None, waveform_out: str | None = None,
              write_outputs: bool = True, progress: Callable[[float], None] | None = None,
              simulator: Simulator | None = None, budget: Budget | None = None) -> SceneResult:
    """Run every sample of a scene, write its report and plots, return the result.

    Parameters
    ----------
    scene : Scene
    netlist_out, waveform_out : str, optional
        Keep the (first sample's) netlist, and its end waveforms as CSV
        ``t,first,last`` (dimensionless, as ``lcchain simulate`` writes them).
    write_outputs : bool
        Write the report file and plots named by the scene's ``[output]``.
    progress : callable, optional
        Called with the fraction of the scene's simulations done (0 to 1).
    simulator : Simulator, optional
        Found once by the caller; found here when omitted.
    budget : Budget, optional
        The most memory and time the scene may take.
    """
    instance("scene", scene, Scene)
    if not isinstance(write_outputs, bool):
        raise ParameterError("write_outputs", write_outputs, "True or False")
    others = {"netlist_out": netlist_out, "waveform_out": waveform_out}
    for option, path in others.items():
        if path is not None:
            check_output(option, path)  # a file name, not a number or bytes
    check_scene_outputs([scene] if write_outputs else [], others)
    result = simulate_scene(scene, progress=progress, simulator=simulator, budget=budget)
    files = write_scene_outputs(result, netlist_out=netlist_out, waveform_out=waveform_out,
                                write_outputs=write_outputs)
    result.report["files"] = files
    return replace(result, files=tuple(files))
