"""One progress style (issue 22): the same words on a terminal and on a pipe, a time left only once it means
something, and nothing for short work on a pipe. A fake clock drives it: no test here depends on timing."""

from __future__ import annotations

import contextlib
import io
import re

import pytest

from lcchain.cli import progress as progress_module
from lcchain.cli.progress import Progress


class Clock:
    def __init__(self) -> None:
        self.now = 1000.0

    def __call__(self) -> float:
        return self.now


@pytest.fixture
def clock(monkeypatch: pytest.MonkeyPatch) -> Clock:
    fake = Clock()
    monkeypatch.setattr(progress_module.time, "monotonic", fake)
    return fake


@pytest.fixture(autouse=True)
def no_line_left_open(monkeypatch: pytest.MonkeyPatch) -> None:
    """Each test's own record of the terminal lines left unfinished (lines_ended's), not the previous tests'."""
    monkeypatch.setattr(progress_module, "_open", set())


class Terminal(io.StringIO):
    def isatty(self) -> bool:
        return True


def test_a_slow_start_does_not_inflate_the_time_left(clock: Clock) -> None:
    stream = Terminal()
    progress = Progress("", stream)
    clock.now += 60.0  # a minute of start-up (imports, a pool, the first design) before the first run ends
    progress.update(1, 1200, unit="runs")
    assert "left" not in stream.getvalue()  # one run done: no estimate yet
    for done in range(2, 12):
        clock.now += 0.125
        progress.update(done, 1200, unit="runs")
    last = stream.getvalue().split("\r")[-1]
    assert "runs, 8/s" in last and "about 2m29s left" in last, last  # (1200 - 11) / 8 per s, not 2h36m
    assert "] 11/1200 runs" in last


def test_on_a_pipe_short_work_prints_nothing_and_long_work_a_line_per_tenth(clock: Clock) -> None:
    stream = io.StringIO()
    progress = Progress("figures", stream)
    for done in range(1, 11):
        clock.now += 0.1
        progress.update(done, 10)
    assert stream.getvalue() == ""  # one second of work: nothing
    stream = io.StringIO()
    progress = Progress("report", stream)
    for done in range(1, 101):
        clock.now += 0.5
        progress.update(done, 100, phase="rows" if done <= 50 else "checks", failed=done // 60)
    lines = stream.getvalue().splitlines()
    assert 10 <= len(lines) <= 25 and all(line.startswith("lcchain: report ") for line in lines)
    assert any("report checks: 51/100" in line for line in lines)  # a new phase has its line
    assert "100/100" in lines[-1] and "failed" in lines[-1] and "left" not in lines[-1]
    assert not any("None" in line or "-0" in line for line in lines)


def test_a_fraction_shows_a_percent_and_a_terminal_redraws_one_line(clock: Clock) -> None:
    stream = Terminal()
    progress = Progress("ngspice", stream)
    for step in range(11):
        clock.now += 0.5
        progress.update(step / 10)
    text = stream.getvalue()
    assert text.count("\r") == 11 and text.endswith("\n") and text.count("\n") == 1
    assert "ngspice 50%" in text and "ngspice 100%" in text and "about" in text


def test_a_batch_plan_draws_nothing_when_short_and_its_rate_in_plain_digits_when_long(
        clock: Clock, monkeypatch: pytest.MonkeyPatch) -> None:
    """lcchain batch's plan line (plan_counter): a plan over within QUIET_SECONDS draws nothing, on a terminal
    too (every batch would otherwise show a bar for its plan); a long one draws its netlists checked, at a rate
    of thousands a second written in digits, and ends its line."""
    stream = Terminal()
    monkeypatch.setattr(progress_module.sys, "stderr", stream)
    short = progress_module.plan_counter()
    for done in (256, 512, 600):
        clock.now += 0.1
        short(done, 600)
    assert stream.getvalue() == ""
    long = progress_module.plan_counter()
    for done in range(256, 100_001, 256):
        clock.now += 256 / 3333
        long(done, 100_000)
    long(100_000, 100_000)
    text = stream.getvalue()
    assert text.endswith("\n") and text.count("\n") == 1, text[-200:]
    last = text.split("\r")[-1]
    assert re.search(r"\] 100000/100000 netlists checked, 33\d\d/s, 30s elapsed\x1b\[K\n$", last), last
    assert "e+" not in text
    assert [progress_module._rate(rate) for rate in (8.254, 46.94, 99.97, 469.2, 999.7)] == \
        ["8.25/s", "46.9/s", "100/s", "469/s", "1000/s"]
    assert " 2s elapsed" in text.split("\r")[1]  # first drawn once QUIET_SECONDS have passed


@pytest.mark.parametrize("raises", [True, False], ids=["error", "return"])
def test_a_line_left_unfinished_on_a_terminal_is_ended_before_the_command_says_more(clock: Clock,
                                                                                    raises: bool) -> None:
    """An error, an interrupt or a study stopped by its time budget leaves its bar unfinished: lines_ended ends it
    with one newline, so that what the command says next starts a line.  A finished line gets none more."""
    stream, done = Terminal(), Terminal()
    with pytest.raises(KeyboardInterrupt) if raises else contextlib.nullcontext():
        with progress_module.lines_ended():
            clock.now += 5.0
            Progress("", stream).update(3, 10, unit="runs")
            Progress("", done).update(10, 10, unit="runs")
            assert not stream.getvalue().endswith("\n") and done.getvalue().endswith("\n")
            if raises:
                raise KeyboardInterrupt
    assert stream.getvalue().endswith("\x1b[K\n") and stream.getvalue().count("\n") == 1
    assert done.getvalue().count("\n") == 1
    with progress_module.lines_ended():  # nothing left open: nothing written
        pass
    assert stream.getvalue().count("\n") == 1


def test_a_study_stopped_by_its_time_budget_says_its_summary_on_a_line_of_its_own(
        clock: Clock, monkeypatch: pytest.MonkeyPatch, capsys: pytest.CaptureFixture[str]) -> None:
    """A study whose time budget stops it leaves its runs' bar unfinished on the terminal (3 of 10 runs): the
    summary, on stdout (the same terminal), starts a line of its own."""
    from lcchain.app.studies import StudyResult
    from lcchain.cli.main import build_parser
    from lcchain.cli.studies import show_study
    from lcchain.studies.run import Summary

    terminal = Terminal()
    monkeypatch.setattr(progress_module.sys, "stderr", terminal)
    clock.now += 5.0
    Progress("").update(3, 10, unit="runs")
    assert not terminal.getvalue().endswith("\n")
    args = build_parser("batch").parse_args(["batch", "n.cir", "--store", "s.sqlite", "--max-time", "5"])
    show_study(args, StudyResult(Summary(10, 0, 3, 3, 0, "s.sqlite", 5.0, pending=7)))
    assert terminal.getvalue().endswith("\x1b[K\n")
    assert "7 not run: the --max-time of 5 s was spent" in capsys.readouterr().out
