"""``lcchain run`` for one scene as a function: check its outputs, simulate it, write its report and plots."""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import replace
from typing import Any

from ..core.budget import Budget
from ..core.checks import instance
from ..core.errors import ParameterError
from ..report.files import check_output
from ..report.scenes import check_scene_outputs, write_scene_outputs
from ..scenes.run import SceneResult, simulate_scene
from ..scenes.schema import Scene
from ..spice.simulator import Simulator
from ..studies.executors import DEFAULT_EXECUTOR, EXECUTOR_TRAITS

__all__ = ["run_scene"]


def run_scene(scene: Scene, *, netlist_out: str | None = None, waveform_out: str | None = None,
              write_outputs: bool = True, progress: Callable[[float], None] | None = None,
              simulator: Simulator | None = None, budget: Budget | None = None, executor: str = "serial",
              workers: int | None = None, scheduler: str | None = None, transport: str = "auto",
              study_progress: Callable[[Any], None] | None = None,
              write_error: Callable[[OSError], None] | None = None) -> SceneResult:
    """Run every sample of a scene, write its report and plots, return the result: ``lcchain run``.

    Parameters
    ----------
    scene : Scene
    netlist_out, waveform_out : str, optional
        Keep the (first sample's) netlist, and its end waveforms as CSV
        ``t,first,last`` (dimensionless, as ``lcchain simulate`` writes them).
    write_outputs : bool
        Write the report file and plots named by the scene's ``[output]``.
    progress : callable, optional
        Called with the fraction of the scene's simulations done (0 to 1), one after the other.
    simulator : Simulator, optional
        Found once by the caller; found here when omitted.
    budget : Budget, optional
        The most memory and time the scene may take.
    executor, workers, scheduler, transport
        The samples on an executor of :mod:`lcchain.studies.executors` (``"process"``, ``"dask"``; workers > 1
        with ``"serial"`` means a process pool), as a study runs them; ``study_progress`` is called with each
        :class:`lcchain.studies.run.Progress`.  Default: one after the other in this process.
    write_error : callable, optional
        Called with the error when an output cannot be written (a full disk): the result is returned, with no
        files.  Default: the error is raised.
    """
    instance("scene", scene, Scene)
    if not isinstance(write_outputs, bool):
        raise ParameterError("write_outputs", write_outputs, "True or False")
    if workers is not None and (not isinstance(workers, int) or isinstance(workers, bool) or workers < 1):
        raise ParameterError("--workers", workers, "an integer >= 1")
    others = {"netlist_out": netlist_out, "waveform_out": waveform_out}
    for option, path in others.items():
        if path is not None:
            check_output(option, path)  # a file name, not a number or bytes
    check_scene_outputs([scene] if write_outputs else [], others)
    traits = EXECUTOR_TRAITS.get(executor)  # an unknown name goes on, to be refused with the executors' names
    parallel = traits is None or traits.parallel
    if workers is not None and workers > 1 or parallel:  # several workers asked of the serial executor: a pool
        result = _on_executor(scene, budget, executor if parallel else DEFAULT_EXECUTOR, workers, scheduler,
                              transport, study_progress)
    else:
        result = simulate_scene(scene, progress=progress, simulator=simulator, budget=budget)
    try:
        files = write_scene_outputs(result, netlist_out=netlist_out, waveform_out=waveform_out,
                                    write_outputs=write_outputs)
    except OSError as error:
        if write_error is None:
            raise
        write_error(error)
        files = []
    result.report["files"] = files
    return replace(result, files=tuple(files))


def _on_executor(scene: Scene, budget: Budget | None, executor: str, workers: int | None, scheduler: str | None,
                 transport: str, progress: Callable[[Any], None] | None) -> SceneResult:
    """A scene's tolerance samples on an executor, summed up as one after the other would be."""
    from ..scenes.plan import scene_plan, scene_specs
    from ..scenes.run import scene_result
    from ..studies.run import check_specs, run_specs

    start = time.perf_counter()
    plan = scene_plan(scene, budget)
    specs = scene_specs(scene, plan)
    # its workers' interpreters and runs, priced
    check_specs(specs, budget if budget is not None else Budget(), executor=executor, workers=workers)
    records = run_specs(specs, executor=executor, workers=workers, scheduler=scheduler, progress=progress,
                        transport=transport)
    return scene_result(scene, plan, specs, records, time.perf_counter() - start)
