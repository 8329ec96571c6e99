"""``python -m lcchain``, and the ``lcchain`` console script (``lcchain.__main__:main``)."""

from __future__ import annotations

import gc as _gc
import importlib
import os
import sys

#: ``typing.TYPE_CHECKING`` without importing typing before Ctrl-C is taken over; type checkers read it as true.
TYPE_CHECKING = False
if TYPE_CHECKING:
    from types import CodeType, FrameType

# signal's C module: ``import signal`` builds its enums first, a millisecond open to Ctrl-C (no stub: a ModuleType)
_signal = importlib.import_module("_signal")


def _interrupted_while_loading(signum: int, frame: object) -> None:
    os.write(2, b"lcchain: interrupted\n")
    os._exit(128 + signum)


#: The young generation's threshold of the command line's process while it starts (Python's is 700 allocations):
#: while a command's modules load, Python's collected 45 times, 8 to 13 ms of CPU before a batch's first run, and
#: found next to nothing (what a module makes lives as long as the process).  Python's thresholds are back after
#: the first collection (:func:`_collect_as_usual`): the garbage of at most these many allocations waits once.
YOUNG_THRESHOLD = 50_000
#: Python's thresholds, put back by the first collection (None once they are).
_usual: tuple[int, int, int] | None = None


def _collect_as_usual(phase: str, info: dict[str, int]) -> None:
    """A garbage collection's callback: after the first one, the process collects at Python's thresholds."""
    global _usual
    if phase == "stop" and _usual is not None:
        _gc.set_threshold(*_usual)
        _usual = None


def main() -> int:
    """The command line's exit status.  Ctrl-C while its modules load (the command's first 30 ms or so) ends as it
    does later, with one line and 130, not with Python's traceback: nothing has started that needs cleaning up.
    The command's own handling (:func:`lcchain.cli.main.main`) takes over before it starts anything.  The process's
    first garbage collection waits for :data:`YOUNG_THRESHOLD` allocations."""
    global _usual
    # Python's own Ctrl-C handling only: a process started with Ctrl-C ignored (a background job) keeps ignoring it
    taken = _signal.getsignal(_signal.SIGINT) is _signal.default_int_handler
    if taken:
        _signal.signal(_signal.SIGINT, _interrupted_while_loading)
    if _collect_as_usual not in _gc.callbacks:  # once, in the command's process: a library user's is theirs
        _usual = _gc.get_threshold()
        _gc.callbacks.append(_collect_as_usual)
        _gc.set_threshold(YOUNG_THRESHOLD, *_usual[1:])
    from .cli.main import main as command_line

    if taken:
        _signal.signal(_signal.SIGINT, _signal.default_int_handler)
    status = command_line()
    _end(status, sys._getframe(1))
    return status


def _end(status: int, caller: FrameType | None) -> None:
    """End the process at once, its output flushed and its exit handlers run (every worker ended, every log
    flushed): the interpreter's teardown (a garbage collection, every module freed) cost each command 20 to 25 ms
    after its last word.  Returns, for the usual ending, where something else may still need the process: another
    thread running, a caller's code around the command (a profiler, coverage, a program that ran this module), or
    output that cannot be flushed (Python then reports it as it always did).  ``caller``: the frame that called
    :func:`main`."""
    import atexit
    import threading

    if threading.active_count() > 1 or not _owns_the_process(caller):
        return
    streams = [stream for stream in (sys.stdout, sys.stderr) if stream is not None]  # None: started with it closed
    try:
        for stream in streams:
            stream.flush()
    except (OSError, ValueError):  # a reader gone, a full disk, a closed stream: the usual ending says so
        return
    atexit._run_exitfuncs()
    try:
        for stream in streams:
            stream.flush()  # what the exit handlers wrote
    except (OSError, ValueError):
        pass
    os._exit(status)


#: Where runpy's code says it comes from: frozen into the interpreter (3.11), or its source file.
_RUNPY = ("<frozen runpy>", os.path.join(os.path.dirname(os.__file__), "runpy.py"))


def _owns_the_process(frame: FrameType | None) -> bool:
    """Whether only the interpreter's start led to ``frame`` (the command's caller): the console script's module
    alone, or this module run by ``python -m`` (runpy's ``_run_module_as_main`` and nothing but runpy between).
    Any other code below it (cProfile's, coverage's, a program that ran this module) may still have work to do
    once the command returns."""
    codes: list[CodeType] = []
    while frame is not None:
        codes.append(frame.f_code)
        frame = frame.f_back
    if not codes or codes[0].co_name != "<module>":
        return False
    if len(codes) == 1:  # the console script's own module
        return True
    return codes[-1].co_name == "_run_module_as_main" and \
        all(code.co_filename in _RUNPY for code in codes[1:])


if __name__ == "__main__":
    sys.exit(main())
