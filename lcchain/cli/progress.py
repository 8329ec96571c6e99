"""One progress style for every long command: sweep, batch, run, simulate, figures, report, table, bench.

The same words everywhere: the phase, how many of how many (or the percent), the rate, the failures, the time
elapsed and, once it means something, the time left::

    [#########.....................] runs: 120/400, 41.3/s, 2 failed, 3s elapsed, about 7s left

On a terminal it is one line redrawn in place (stderr, at most every 0.1 s); on a pipe or a log file the same
text as a line of its own, ``lcchain: ...``, at each new phase, every 10 % and at least every 30 s, and at the
end, once the work has lasted 2 s (short work prints nothing); its text is made only when it is shown.  The time
left is shown only once three units are done and a second has passed since the first one: it is estimated
from the rate since the first one finished, so a slow start (imports, a pool starting, the first design)
does not inflate it (the first estimate of a 1200-run sweep once said 2h36m).  A line left unfinished on a
terminal (an error, an interrupt, a study stopped by its time budget) is ended before anything else is said
(:func:`lines_ended`).
"""

from __future__ import annotations

import contextlib
import sys
import time
from collections.abc import Callable, Iterator
from typing import TYPE_CHECKING, TextIO

if TYPE_CHECKING:
    from ..app.studies import StudyProgress

__all__ = ["Progress", "duration", "counter", "fraction", "study_counter", "plan_counter", "lines_ended", "end_lines"]

#: On a pipe: a line at least this often (seconds), and every this fraction of the work; nothing for work
#: that ends within QUIET_SECONDS (short work needs no progress).
LINE_SECONDS, LINE_FRACTION, QUIET_SECONDS = 30.0, 0.1, 2.0
#: The time left is shown from this many units done, and this many seconds after the first.
ETA_AFTER_UNITS, ETA_AFTER_SECONDS = 3, 1.0
#: On a terminal: the line is redrawn at most this often (seconds), and at each new phase and at the end.
REDRAW_SECONDS = 0.1
_WIDTH = 30


#: The terminals whose last progress line is drawn and not ended (no newline yet).
_open: set[TextIO] = set()


def end_lines() -> None:
    """End every progress line left unfinished on a terminal (a study stopped by its time budget, say), so that
    what is said next starts a line of its own."""
    while _open:
        stream = _open.pop()
        with contextlib.suppress(OSError, ValueError):  # a terminal gone: nothing to end
            stream.write("\n")
            stream.flush()


@contextlib.contextmanager
def lines_ended() -> Iterator[None]:
    """Around a command: a progress line it leaves unfinished on a terminal is ended when it returns or raises, so
    that its error or its interrupt starts on a line of its own (:func:`end_lines`)."""
    try:
        yield
    finally:
        end_lines()


def _rate(rate: float) -> str:
    """``8.25/s``, ``46.9/s``, ``469/s``, ``3333/s`` (never ``3.33e+03``, nor ``1e+03`` for 999.7)."""
    return f"{rate:.3g}/s" if rate < 100 else f"{rate:.0f}/s"


def duration(seconds: float) -> str:
    """``42s``, ``3m07s``, ``2h05m``."""
    seconds = int(round(seconds))
    return f"{seconds // 3600}h{seconds % 3600 // 60:02d}m" if seconds >= 3600 else \
        f"{seconds // 60}m{seconds % 60:02d}s" if seconds >= 60 else f"{seconds}s"


class Progress:
    """A progress line for one command; call :meth:`update` as work finishes (``total`` 0: a fraction)."""

    def __init__(self, what: str, stream: TextIO | None = None, *, quiet: bool = False) -> None:
        """``quiet``: nothing on a terminal either before the work has lasted :data:`QUIET_SECONDS` (a phase that is
        over in a moment, a short batch's plan, draws no line of its own)."""
        self.what = what
        self.stream = stream if stream is not None else sys.stderr
        self.terminal = bool(getattr(self.stream, "isatty", lambda: False)())
        self.quiet = quiet
        self.start = time.monotonic()
        self.first: tuple[float, float] | None = None  # (time, done) when the first unit finished
        self.phase: str | None = None
        self.line = (-1.0, 0.0)  # (fraction, time) of the last line on a pipe
        self.drawn = -REDRAW_SECONDS  # when the line was last drawn on a terminal
        self.ended = False

    def text(self, done: float, total: float, failed: int = 0, unit: str = "") -> str:
        now = time.monotonic()
        parts = [f"{done:g}/{total:g}{' ' + unit if unit else ''}" if total else f"{100 * done:.0f}%"]
        left = None
        if self.first is not None and now - self.first[0] >= ETA_AFTER_SECONDS and done > self.first[1]:
            rate = (done - self.first[1]) / (now - self.first[0])  # since the first unit: start-up excluded
            if total:
                parts.append(_rate(rate))
            if done >= (ETA_AFTER_UNITS if total else 0.03) and done < (total or 1.0):
                left = ((total or 1.0) - done) / rate
        if failed:
            parts.append(f"{failed} failed")
        parts.append(f"{duration(now - self.start)} elapsed")
        if left is not None:
            parts.append(f"about {duration(left)} left")
        head = " ".join(part for part in (self.what, f"{self.phase}:" if self.phase else "") if part)
        return f"{head} {', '.join(parts)}" if head else ", ".join(parts)

    def update(self, done: float, total: float = 0, *, failed: int = 0, phase: str | None = None,
               unit: str = "") -> None:
        """``done`` of ``total`` (or, with ``total`` 0, a fraction from 0 to 1) in ``phase``."""
        if self.ended:
            return
        now = time.monotonic()
        new_phase = phase is not None and phase != self.phase
        if new_phase:
            self.phase, self.first = phase, None
        if self.first is None and done > 0:
            self.first = (now, float(done))
        fraction = done / total if total else float(done)
        finished = fraction >= 1.0
        if self.terminal:  # redrawn at most every REDRAW_SECONDS: a batch of 10,000 runs is 10,000 updates
            if (new_phase or finished or now - self.drawn >= REDRAW_SECONDS) \
                    and not (self.quiet and now - self.start < QUIET_SECONDS):
                self.drawn = now
                filled = int(_WIDTH * min(max(fraction, 0.0), 1.0))
                self.stream.write(f"\r[{'#' * filled}{'.' * (_WIDTH - filled)}] {self.text(done, total, failed, unit)}"
                                  "\033[K" + ("\n" if finished else ""))
                self.stream.flush()
                if finished:
                    _open.discard(self.stream)
                else:
                    _open.add(self.stream)
        elif now - self.start >= QUIET_SECONDS and (new_phase or finished or fraction - self.line[0] >= LINE_FRACTION
                                                     or now - self.line[1] >= LINE_SECONDS):
            self.line = (fraction, now)
            print(f"lcchain: {self.text(done, total, failed, unit)}", file=self.stream, flush=True)
        if finished and phase is None:
            self.ended = True


def counter(what: str) -> Callable[[int, int, str], None]:
    """A ``progress(done, total, label)`` callback; the label's first word is the phase (figures, report)."""
    progress = Progress(what)

    def show(done: int, total: int, label: str) -> None:
        phase = label.split(",")[0].split(" ")[0] if label else None
        progress.update(done, total, phase=phase)

    return show


def fraction(what: str) -> Callable[[float], None]:
    """A ``progress(fraction)`` callback (one simulation, one design)."""
    progress = Progress(what)
    return lambda done: progress.update(done)


def plan_counter() -> Callable[[int, int], None]:
    """A batch's plan's callback, ``planning(done, total)``: its netlists read, checked and priced before any
    run (``1024/100000 netlists checked, 3333/s, 2s elapsed, about 30s left``), timed from the plan's first
    word (not from the command's start: a short plan after a slow start stays quiet), quiet for a short plan."""
    started: list[Progress] = []

    def show(done: int, total: int) -> None:
        if not started:
            started.append(Progress("", quiet=True))
        started[0].update(done, total, unit="netlists checked")

    return show


def study_counter(unit: str) -> Callable[[StudyProgress], None]:
    """A study's callback: it gets a :class:`lcchain.studies.run.Progress` (done, total, failed)."""
    progress = Progress("")
    return lambda p: progress.update(p.done, p.total, failed=p.failed, unit=unit)
