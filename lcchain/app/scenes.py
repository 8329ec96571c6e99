"""``lcchain run`` as functions: for one scene (:func:`run_scene`: check its outputs, simulate it, write its
report and plots) and for the scene files of a command line (:func:`run_scenes`)."""

from __future__ import annotations

import time
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import TypedDict

from ..core.budget import Budget
from ..core.checks import instance, integer
from ..core.errors import ParameterError
from ..report.files import check_output
from ..report.scenes import check_scene_outputs, write_scene_outputs
from ..scenes.run import SceneResult, simulate_scene
from ..scenes.schema import Scene
from ..spice.simulator import Simulator
from ..studies.executors import DEFAULT_EXECUTOR, EXECUTOR_TRAITS
from ..studies.options import Progress, RunOptions
from .inputs import Outputs
from .studies import StudyOptions

__all__ = ["SceneRun", "SceneHooks", "run_scene", "RunRequest", "ScenesRun", "run_scenes", "PartOverrides",
           "SceneResult"]


@dataclass(frozen=True)
class SceneRun:
    """How :func:`run_scene` runs a scene and what it keeps.

    Attributes
    ----------
    netlist_out, waveform_out : str, optional
        Keep the (first sample's) netlist, and its end waveforms as CSV ``t,first,last`` (dimensionless, as
        ``lcchain simulate`` writes them); ``-``: stdout.
    write_outputs : bool
        Write the report file and plots named by the scene's ``[output]``.
    budget : Budget, optional
        The most memory and time the scene may take.
    executor, workers, scheduler, transport
        The samples on an executor of :mod:`lcchain.studies.executors` (``"process"``, ``"dask"``; workers >= 1,
        and > 1 with ``"serial"`` means a process pool), as a study runs them
        (``lcchain.studies.options.RunOptions``).  Default: one after the other in this process.
    simulator : Simulator, optional
        Found once by the caller; found here when omitted.

    Notes
    -----
    ``write_outputs``, ``workers`` and the two file names are checked here; the executor where the samples go to
    one (an unknown name is refused with the executors' names).
    """

    netlist_out: str | None = None
    waveform_out: str | None = None
    write_outputs: bool = True
    budget: Budget | None = None
    executor: str = "serial"
    workers: int | None = None
    scheduler: str | None = None
    transport: str = "auto"
    simulator: Simulator | None = field(default=None, compare=False)

    def __post_init__(self) -> None:
        if not isinstance(self.write_outputs, bool):
            raise ParameterError("write_outputs", self.write_outputs, "True or False")
        if self.workers is not None:  # stored as an int (a numpy integer is one too)
            object.__setattr__(self, "workers", integer("--workers", self.workers, at_least=1))
        from ..studies.executors import check_transport

        check_transport(self.transport)
        for option, path in self.others().items():
            if path is not None:
                check_output(option, path)  # a file name, not a number or bytes

    def others(self) -> dict[str, str | None]:
        """The files kept beside the scene's own outputs, by option."""
        return {"netlist_out": self.netlist_out, "waveform_out": self.waveform_out}


@dataclass(frozen=True)
class SceneHooks:
    """What :func:`run_scene` calls while it runs: ``progress`` with the fraction of the scene's simulations done
    (0 to 1, one after the other), ``study_progress`` with each ``lcchain.studies.options.Progress`` of its
    samples on an executor, and ``write_error`` with the error when an output cannot be written (a full disk:
    the result is returned, with no files; default: the error is raised)."""

    progress: Callable[[float], None] | None = None
    study_progress: Callable[[Progress], None] | None = None
    write_error: Callable[[OSError], None] | None = None


def run_scene(scene: Scene, options: SceneRun | None = None, hooks: SceneHooks | None = None) -> SceneResult:
    """Run every sample of a scene, write its report and plots, return the result: ``lcchain run``.

    Parameters
    ----------
    scene : Scene
    options : SceneRun, optional
        The files it keeps, whether it writes its own, its budget and where its samples run (default: every
        output the scene names, one sample after the other in this process).
    hooks : SceneHooks, optional
        Its progress, its samples' progress on an executor, and what an output that cannot be written does.
    """
    instance("scene", scene, Scene)
    options = options if options is not None else SceneRun()
    hooks = hooks if hooks is not None else SceneHooks()
    instance("options", options, SceneRun)
    check_scene_outputs([scene] if options.write_outputs else [], options.others())
    executor, workers = options.executor, options.workers
    traits = EXECUTOR_TRAITS.get(executor)  # an unknown name goes on, to be refused with the executors' names
    parallel = traits is None or traits.parallel
    if workers is not None and workers > 1 or parallel:  # several workers asked of the serial executor: a pool
        result = _on_executor(scene, options.budget, RunOptions(executor if parallel else DEFAULT_EXECUTOR, workers,
                                                                options.scheduler, options.transport),
                              hooks.study_progress)
    else:
        result = simulate_scene(scene, progress=hooks.progress, simulator=options.simulator, budget=options.budget)
    write_error = hooks.write_error
    try:
        files = write_scene_outputs(result, netlist_out=options.netlist_out, waveform_out=options.waveform_out,
                                    write_outputs=options.write_outputs)
    except OSError as error:
        if write_error is None:
            raise
        write_error(error)
        files = []
    result.report["files"] = files
    return replace(result, files=tuple(files))


def _on_executor(scene: Scene, budget: Budget | None, options: RunOptions,
                 progress: Callable[[Progress], None] | None) -> SceneResult:
    """A scene's tolerance samples on an executor, summed up as one after the other would be."""
    from ..scenes.plan import scene_plan, scene_specs
    from ..scenes.run import scene_result
    from ..studies.options import RunHooks
    from ..studies.run import check_specs, run_specs

    start = time.perf_counter()
    plan = scene_plan(scene, budget)
    specs = scene_specs(scene, plan)
    # its workers' interpreters and runs, priced
    assert isinstance(options.executor, str)  # run_scene's executor is a registry name
    check_specs(specs, budget if budget is not None else Budget(), executor=options.executor, workers=options.workers)
    records = run_specs(specs, options, RunHooks(progress=progress))
    return scene_result(scene, plan, specs, records, time.perf_counter() - start)


class PartOverrides(TypedDict, total=False):
    """A scene's real parts set from the command line (``--tolerance``, ``--series``, ``--samples``, ``--seed``;
    None: the scene's own), checked by :func:`lcchain.scenes.load.override_parts`."""

    tolerance: Mapping[str, float] | None
    series: str | None
    samples: int | None
    seed: int | None


@dataclass(frozen=True)
class RunRequest:
    """``lcchain run``: the scene files, run in order; ``parts`` the real parts set from the command line
    (tolerance, series, samples, seed: None leaves a scene's own), the files to keep (``netlist_out``,
    ``waveform_out``: one scene only; ``-``: stdout) and the figure of the scenes side by side; where the
    samples run (``study``); whether the report goes out as JSON; ``progress(label)`` gives the callback of a
    scene's fraction done, ``study_progress(label)`` that of its samples on an executor."""

    scenes: tuple[str, ...]
    parts: PartOverrides = field(default_factory=lambda: PartOverrides())
    netlist_out: str | None = None
    waveform_out: str | None = None
    side_by_side: str | None = None
    json: bool = False
    study: StudyOptions = field(default_factory=lambda: StudyOptions(executor="serial"))
    budget: Budget | None = None
    progress: Callable[[str], Callable[[float], None]] | None = None
    study_progress: Callable[[str], Callable[[Progress], None]] | None = None


@dataclass(frozen=True)
class ScenesRun:
    """Each scene's result, the scenes whose outputs could not be written, the outputs checked (which of them
    goes to stdout; their notes say what was not written) and the figure of the scenes side by side, when
    drawn."""

    results: list[SceneResult]
    failed_files: list[str | None]
    outputs: Outputs
    side_by_side: str | None = None

    @property
    def ok(self) -> bool:
        return all(r.ok for r in self.results) and not self.failed_files and not self.outputs.failed


def _with_parts(scene: Scene, parts: PartOverrides) -> Scene:
    """The scene with ``--tolerance``, ``--series``, ``--samples`` and ``--seed`` set, when any is given."""
    from ..scenes.load import check_samples_spread, override_parts, parse_scene

    if all(value is None for value in parts.values()):
        return scene
    data = override_parts(scene.to_dict(), **parts)
    check_samples_spread(parts.get("samples"), [data])
    return parse_scene(data, source=scene.source)


def check_run(request: RunRequest) -> tuple[list[Scene], Outputs]:
    """Every scene file read and every output checked, before anything runs."""
    from ..core.analyses import analysis_kind
    from ..report.files import FIGURE_FORMATS
    from ..scenes.load import load_scene

    if len(request.scenes) > 1 and (request.netlist_out or request.waveform_out):
        option = "--netlist-out" if request.netlist_out else "--waveform-out"
        raise ParameterError(option, request.netlist_out or request.waveform_out, "one scene only (got "
                             f"{len(request.scenes)})")
    scenes = [_with_parts(load_scene(path), request.parts) for path in request.scenes]  # every file checked first
    outputs = Outputs()
    outputs.check("--side-by-side", request.side_by_side, FIGURE_FORMATS)
    swept = next((path for path, scene in zip(request.scenes, scenes, strict=True)
                  if analysis_kind(scene.analysis.kind).swept), None)
    if request.side_by_side is not None and swept is not None:  # its overlays are transients' waveforms
        raise ParameterError("--side-by-side", request.side_by_side, f"transient scenes only ({swept} sweeps "
                             "frequencies: its spectrum is drawn by its [output] plots)")
    for option, value in (("--netlist-out", request.netlist_out), ("--waveform-out", request.waveform_out)):
        if value == "":
            raise ParameterError(option, "", "a file name")
        if value == "-":
            outputs.claim_stdout(option)
    if request.json and outputs.to_stdout:
        raise ParameterError(outputs.to_stdout, "-", "a file name with --json (both would write to stdout)")
    check_scene_outputs(scenes, {"--netlist-out": request.netlist_out, "--waveform-out": request.waveform_out,
                                 "--side-by-side": request.side_by_side},
                        inputs=[("SCENE", path) for path in request.scenes])
    return scenes, outputs


def run_scenes(request: RunRequest, shown: Callable[[SceneResult, Outputs], None] | None = None) -> ScenesRun:
    """Run every scene of the request in order (each checked first), calling ``shown(result, outputs)`` after
    each; then draw the scenes side by side when asked."""
    from ..scenes.run import overlay_panel

    scenes, outputs = check_run(request)
    study = request.study
    results: list[SceneResult] = []
    failed_files: list[str | None] = []
    for scene in scenes:
        label = Path(scene.source).name if scene.source else "scene"

        def unwritten(error: OSError, source: str | None = scene.source) -> None:
            failed_files.append(source)
            outputs.notes.append(f"could not write {error.filename or 'an output'} of {source}: "
                                 f"{error.strerror or error}")

        options = SceneRun(request.netlist_out, request.waveform_out, budget=request.budget,
                           executor=study.executor, workers=study.workers, scheduler=study.scheduler,
                           transport=study.transport)
        hooks = SceneHooks(None if request.progress is None else request.progress(label),
                           None if request.study_progress is None else request.study_progress(f"samples of {label}"),
                           unwritten)
        result = run_scene(scene, options, hooks)
        results.append(result)
        if shown is not None:
            shown(result, outputs)
    drawn = None
    if request.side_by_side:
        from ..report.plots import side_by_side

        panels = [p for p in (overlay_panel(r) for r in results) if p is not None]
        if panels:
            outputs.write("--side-by-side", lambda path: side_by_side(panels, path=path))
            if "--side-by-side" not in outputs.failed:
                drawn = request.side_by_side
        else:
            outputs.notes.append(f"no scene ran, so {request.side_by_side} was not drawn")
    return ScenesRun(results, failed_files, outputs, drawn)
