"""``lcchain netlist``, ``lcchain reference-netlists`` and ``lcchain examples`` as functions: the texts lcchain
writes (a ladder's netlist, the reference set, the example scenes), checked and written."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

from ..circuit.effects import Effect
from ..core.budget import Budget
from ..core.errors import ParameterError
from ..report.files import check_output_folder
from .inputs import LadderRequest, Outputs, make_chain

__all__ = ["DEFAULT_DT", "NetlistRequest", "NetlistResult", "netlist", "ReferenceRequest", "ReferenceNetlists",
           "reference_netlists", "ExampleRequest", "ExampleResult", "example", "examples"]

#: Step when neither --dt nor --accuracy is given, units of sqrt(L0*C0).
DEFAULT_DT = 0.05


@dataclass(frozen=True)
class NetlistRequest(LadderRequest):
    """A ladder's netlist: the chain, its units, how a transient drives it, its effects; ``output`` a file
    (``-``: stdout; None: only returned); ``command`` the command line its comment echoes."""

    effects: tuple[Effect, ...] = ()
    command: str = "lcchain netlist"
    output: str | None = None
    budget: Budget = field(default_factory=Budget)


@dataclass(frozen=True)
class NetlistResult:
    """The netlist's text; whether ``output`` could not be written, and the note that says so."""

    text: str
    failed: bool
    notes: tuple[str, ...] = ()


def netlist(request: NetlistRequest) -> NetlistResult:
    """The netlist's text, written to ``request.output`` when one is given."""
    from ..circuit.netlist import ChainNetlist, Drive, make_netlist

    outputs = Outputs(inputs={"--chain": request.chain.chain} if request.chain.chain else {})
    outputs.check("--output", request.output)
    chain = make_chain(request.chain, request.budget)
    dt = request.dt if request.dt is not None else DEFAULT_DT
    for effect in request.effects:  # walls and the like change the chain itself; the others add elements
        chain = effect.realise(chain, request.L0, request.C0)
    options = ChainNetlist(dt=dt, transits=request.transits, L0=request.L0, C0=request.C0,
                           drive=Drive(request.excitation), title=request.title,
                           comments=(f"made by: {request.command}",), effects=request.effects)
    text, _, _ = make_netlist(chain, options)
    if request.output:
        outputs.text("--output", text)  # "-" too: stdout
    return NetlistResult(text, bool(outputs.failed), tuple(outputs.notes))


@dataclass(frozen=True)
class ReferenceRequest:
    """Where the reference netlists go (folder ``out``, made with its parents) and ``written(path)``, called
    after each is written."""

    out: str = "netlists"
    written: Callable[[Path], None] | None = None


@dataclass(frozen=True)
class ReferenceNetlists:
    """The netlists' paths, and whether one could not be written (said in a note)."""

    paths: tuple[Path, ...]
    failed: bool
    notes: tuple[str, ...] = ()


def reference_netlists(request: ReferenceRequest) -> ReferenceNetlists:
    """Regenerate the reference netlists: every file checked before any is written."""
    from ..circuit.reference import REFERENCE_SET, reference_netlist

    written = request.written
    folder = check_output_folder("--out", request.out, parents=True)
    outputs = Outputs()
    for reference in REFERENCE_SET:
        outputs.check(reference.name, str(folder / reference.name), make_folder=True)
    folder.mkdir(parents=True, exist_ok=True)  # only now: every check has passed
    for reference in REFERENCE_SET:
        outputs.text(reference.name, reference_netlist(reference))
        if written is not None:
            written(folder / reference.name)
    return ReferenceNetlists(tuple(folder / reference.name for reference in REFERENCE_SET), bool(outputs.failed),
                             tuple(outputs.notes))


def examples() -> list[tuple[str, str]]:
    """The example scenes that ship with lcchain: (name, title)."""
    from ..scenes.bundled import example_names, example_title

    return [(name, example_title(name)) for name in example_names()]


@dataclass(frozen=True)
class ExampleResult:
    """Where the example went: ``target``; ``unchanged`` when the same file was there already; ``failed`` when it
    could not be written (``notes`` says why); ``to_stdout`` when it went to stdout (``-o -``)."""

    target: str
    unchanged: bool = False
    failed: bool = False
    to_stdout: bool = False
    notes: tuple[str, ...] = ()


@dataclass(frozen=True)
class ExampleRequest:
    """The example scene ``name``, written here (``NAME.toml``) or to ``output`` (``-``: stdout)."""

    name: str
    output: str | None = None


def example(request: ExampleRequest) -> ExampleResult:
    """Write the example scene: a file of that name already here is kept (the same text: nothing to do)."""
    from ..scenes.bundled import example_text

    name, output = request.name, request.output
    text = example_text(name)
    target = output or f"{name}.toml"
    if output is None and (Path(target).exists() or Path(target).is_symlink()):
        if _holds(Path(target), text):  # the same example written before: nothing to do
            return ExampleResult(target, unchanged=True)
        raise ParameterError("NAME", name, f"an example whose file is not here yet: {target} exists (your own "
                             "copy?); write it elsewhere with -o FILE")
    outputs = Outputs()
    outputs.check("-o", target)
    outputs.text("-o", text)
    return ExampleResult(target, failed=bool(outputs.failed), to_stdout=outputs.to_stdout is not None,
                         notes=tuple(outputs.notes))


def _holds(path: Path, text: str) -> bool:
    """Whether a regular file holds exactly this text (a special file or a link is never read)."""
    try:
        return not path.is_symlink() and path.is_file() and path.stat().st_size == len(text.encode()) \
            and path.read_text(encoding="utf-8") == text
    except (OSError, UnicodeDecodeError):
        return False
