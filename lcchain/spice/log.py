"""Reading ngspice's output: which lines mean failure, which are worth quoting."""

from __future__ import annotations

import re
from collections.abc import Collection

__all__ = ["fatal_lines", "failure_reason", "useful_output", "trim_log", "LOG_MAX_CHARS", "ERROR_MAX_LINES"]

#: At most this many characters of ngspice's output are kept in ``RunResult.log``.
LOG_MAX_CHARS = 8000
#: At most this many lines of ngspice's output are quoted in an error.
ERROR_MAX_LINES = 30

# Lines of ngspice output that mean the run failed even when it exits 0 ("Error: measure NAME ..." does not: a
# .meas ngspice could not make is that measurement's result, missing, with its reason: lcchain.spice.measure; nor
# does "error = 6.3e-01", the value of a .meas named error).  "Warning: singular matrix" is ngspice's warning where
# its gmin stepping then finds the operating point (when the run fails after it, ngspice says so in its own lines:
# "timestep too small", "aborted"); "warning, can't find model 'X'" is a failure (ngspice runs the element with a
# default value: "L2 a b 1.0.0") unless X is a parameter of the netlist, which ngspice then uses ("C1 a 0 c0").
_FATAL = re.compile(
    r"^\s*error\b(?!:?\s*measure\b)(?!\s*=)|^(?:(?!warning).)*singular matrix|can't find model"
    r"|could not find a valid modelname|timestep too small|circuit not parsed|simulation\(s\) aborted"
    r"|simulation interrupted",
    re.IGNORECASE,
)
# Resource-usage chatter ngspice prints after every batch run.
_BOILERPLATE = re.compile(
    r"^\s*(DRAM|Total DRAM|Maximum ngspice|Current ngspice|Shared ngspice|Text \(code\)"
    r"|Stack =|Library pages|Total elapsed|Note: No compatibility mode)",
    re.IGNORECASE,
)


#: The line ngspice prints after a ``.meas`` it could not make (its reason, an ``Error:`` line, just before it).
_MEASURE_FAILED = re.compile(r"^\s*\.meas\w*\s.*\bfailed!\s*$", re.IGNORECASE)
_ERROR = re.compile(r"^\s*error\b", re.IGNORECASE)
_NO_MODEL = re.compile(r"can't find model '([^']*)'", re.IGNORECASE)
_SINGULAR = re.compile(r"singular matrix", re.IGNORECASE)


def fatal_lines(log: str, parameters: Collection[str] = ()) -> list[str]:
    """The lines of ngspice's output that mean its run failed, each once.  An ``Error:`` line just before a
    ``.meas ... failed!`` line is that measurement's reason ("no such vector as v(zz)"), not the run's failure:
    the run stands, and the measurement is missing (:func:`lcchain.spice.measure.read_measurements`).  Neither is
    ngspice's "can't find model 'X'" for X one of ``parameters`` (the netlist's, lower case): ngspice uses it."""
    lines = [line for line in log.splitlines() if line.strip()]
    return list(dict.fromkeys(
        line.strip() for k, line in enumerate(lines) if _FATAL.search(line) and not (
            _ERROR.match(line) and k + 1 < len(lines) and _MEASURE_FAILED.match(lines[k + 1])) and not (
            (model := _NO_MODEL.search(line)) is not None and model.group(1).lower() in parameters)))


def failure_reason(log: str, fallback: str, parameters: Collection[str] = ()) -> str:
    """What ngspice said of a failed run: its fatal lines, after the first "singular matrix" warning, which names
    the node it could not solve for ("check node nx"); ``fallback`` when it said nothing."""
    fatal = fatal_lines(log, parameters)
    if fatal:
        warned = next((line.strip() for line in log.splitlines() if _SINGULAR.search(line)), None)
        fatal = [warned, *fatal] if warned is not None and warned not in fatal else fatal
    return "ngspice reported an error: " + " | ".join(fatal) if fatal else fallback


def _clean_lines(log: str) -> list[str]:
    lines: list[str] = []
    for line in log.splitlines():
        text = line.rstrip()
        if not text.strip() or _BOILERPLATE.match(text):
            continue
        if lines and lines[-1] == text:  # ngspice repeats e.g. "singular matrix" many times
            continue
        if lines and text.lstrip().startswith("Reference value") and lines[-1].lstrip().startswith("Reference value"):
            lines[-1] = text  # progress lines: the last one says how far the run got
            continue
        lines.append(text)
    return lines


def useful_output(log: str) -> str:
    """The part of ngspice's output worth quoting: around the first fatal line, at most 30 lines."""
    lines = _clean_lines(log)
    if len(lines) > ERROR_MAX_LINES:
        fatal = [i for i, line in enumerate(lines) if _FATAL.search(line)]
        start = max(0, (fatal[0] if fatal else len(lines)) - 5)
        start = min(start, len(lines) - ERROR_MAX_LINES)
        lines = ["..."] * (start > 0) + lines[start : start + ERROR_MAX_LINES] + ["..."] * (
            start + ERROR_MAX_LINES < len(lines)
        )
    return "\n".join(lines)


def trim_log(log: str) -> str:
    text = "\n".join(_clean_lines(log))
    if len(text) > LOG_MAX_CHARS:
        half = LOG_MAX_CHARS // 2
        text = text[:half] + "\n...\n" + text[-half:]
    return text
