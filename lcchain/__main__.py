"""``python -m lcchain``, and the ``lcchain`` console script (``lcchain.__main__:main``)."""

import importlib
import os
import sys

# signal's C module: ``import signal`` builds its enums first, a millisecond open to Ctrl-C (no stub: a ModuleType)
_signal = importlib.import_module("_signal")


def _interrupted_while_loading(signum: int, frame: object) -> None:
    os.write(2, b"lcchain: interrupted\n")
    os._exit(128 + signum)


def main() -> int:
    """The command line's exit status.  Ctrl-C while its modules load (the command's first 30 ms or so) ends as it
    does later, with one line and 130, not with Python's traceback: nothing has started that needs cleaning up.
    The command's own handling (:func:`lcchain.cli.main.main`) takes over before it starts anything."""
    # Python's own Ctrl-C handling only: a process started with Ctrl-C ignored (a background job) keeps ignoring it
    taken = _signal.getsignal(_signal.SIGINT) is _signal.default_int_handler
    if taken:
        _signal.signal(_signal.SIGINT, _interrupted_while_loading)
    from .cli.main import main as command_line

    if taken:
        _signal.signal(_signal.SIGINT, _signal.default_int_handler)
    status = command_line()
    _end(status)
    return status


def _end(status: int) -> None:
    """End the process at once, its output flushed and its exit handlers run (every worker ended, every log
    flushed): the interpreter's teardown (a garbage collection, every module freed) cost each command 20 to 25 ms
    after its last word.  Returns, for the usual ending, while another thread still runs (it is waited for)."""
    import atexit
    import threading

    if threading.active_count() > 1:
        return
    atexit._run_exitfuncs()
    try:
        sys.stdout.flush()
    except (BrokenPipeError, ValueError):  # the reader went away (the command said so), or stdout was closed
        pass
    try:
        sys.stderr.flush()
    except (BrokenPipeError, ValueError):
        pass
    os._exit(status)


if __name__ == "__main__":
    sys.exit(main())
