"""``lcchain report`` cold (issues 23 and 35): the whole command against the code before, side by side.

Run from the repository root (about 15 minutes on 2 cores):

    .venv/bin/python benchmarks/bench_report_cold.py [BEFORE_COMMIT [ROUNDS]] > benchmarks/report_cold.md

Each round runs, one after the other and in alternating order, the whole ``python -m lcchain report --out DIR``
as a user would, cold: ``XDG_CACHE_HOME`` points at an empty folder of its own, so that every row of Tables I
and II is designed again; the before code is ``BEFORE_COMMIT`` (default: the commit before issue 35's work)
exported with ``git archive`` into a temporary folder.  Measured: the command's wall time
(``time.perf_counter`` around the process, start-up included) and the CPU time of it and its children
(``os.wait4``: lcchain, ngspice, gnucap and the pool's workers), with the load average before each run since
the machine is shared; with the load, the wall an idle machine would see is estimated as CPU / 2 plus the part
that runs alone (:data:`SERIAL_S`).  The reports are then compared (:func:`compare_reports`): every number of
``report.json`` and every figure of ``index.html`` must be the same, timings aside, except the circuit checks the
after code no longer runs (issue 35's sizes), which are listed.
"""

from __future__ import annotations

import json
import os
import platform
import re
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parent.parent
#: main before issue 35's report work (the checks at every size, the figures drawn after the pool's work).
BEFORE = "b97ce31"
#: Seconds of a cold report that no second core can share, an upper bound: measured by bench_report_timeline.py
#: (at load 2.5-3.9), 0.9 s before the pool has its work and 0.5 s after its last result; the rest of the 5 s is
#: room for the workers' start and for the last job ending on one core.
SERIAL_S = 5.0
ROUNDS = 2

_TIMING_KEYS = {"created", "seconds", "wall_s", "row_seconds"}


def _without_timings(value: Any) -> Any:
    if isinstance(value, dict):
        return {k: _without_timings(v) for k, v in value.items() if k not in _TIMING_KEYS}
    if isinstance(value, list):
        return [_without_timings(v) for v in value]
    return value


def _html_without_timings(text: str) -> str:
    """The page with its timings blanked: the date and total of the header line, the ``seconds`` column of the
    tables of rows and the ``ngspice s`` column of the circuit's checks (the cell before the verdict)."""
    text = re.sub(r"made \S+ by (<code>.*?</code>)(.*?) in \d+ s</p>", r"made - by \1\2 in - s</p>", text)
    out, in_rows = [], False
    for line in text.splitlines():
        if line.startswith('<table class="rows">'):
            in_rows = True
        if in_rows and line.startswith("<tr><td>"):
            line = re.sub(r"<td>[0-9.]*</td></tr>$", "<td>-</td></tr>", line)
        if line.startswith("</tbody></table>"):
            in_rows = False
        line = re.sub(r"<td>[^<]*</td>(<td><span class=\"(?:pass|fail)\">)", r"<td>-</td>\1", line)
        out.append(line)
    return "\n".join(out)


_FIGURE = re.compile(r'<span class=view id="([^"]+)"></span><a class=open [^>]*><img alt="[^"]*" '
                     r'src="data:image/png;base64,([^"]+)">')


def compare_reports(before: Path, after: Path) -> tuple[list[str], list[str]]:
    """What differs between two report folders beyond their timings, and the checks only ``before`` has.

    ``report.json``: every key the same, and the after's checks the before's without those it no longer runs
    (its new sizes); ``index.html``: every figure (by its view anchor) the same PNG, the before's figures of the
    checks left out aside.  The page's text is not compared: it says the new sizes.
    """
    differences = []
    ja, jb = (_without_timings(json.loads((p / "report.json").read_text())) for p in (before, after))
    kept = {check["name"] for check in jb["checks"]}
    dropped = [check["name"] for check in ja["checks"] if check["name"] not in kept]
    ja["checks"] = [check for check in ja["checks"] if check["name"] in kept]
    for key in sorted(set(ja) | set(jb)):
        if ja.get(key) != jb.get(key):
            differences.append(f"report.json {key}")
    fa, fb = (dict(_FIGURE.findall((p / "index.html").read_text())) for p in (before, after))
    gone = {"view-check-" + "".join(c if c.isalnum() or c in "-_" else "-" for c in name) for name in dropped}
    for view in sorted(set(fa) | set(fb)):
        if view in gone and view not in fb:
            continue
        if fa.get(view) != fb.get(view):
            differences.append(f"index.html figure {view}")
    return differences, dropped


def _cold_report(source: Path, scratch: Path, name: str) -> dict[str, Any]:
    out, cache = scratch / name / "out", scratch / name / "cache"
    cache.mkdir(parents=True)
    env = dict(os.environ, PYTHONPATH=str(source), XDG_CACHE_HOME=str(cache))
    load = os.getloadavg()[0]
    clock = time.perf_counter()
    process = subprocess.Popen([sys.executable, "-m", "lcchain", "report", "--out", str(out)], cwd=scratch,
                               env=env, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    _, status, usage = os.wait4(process.pid, 0)
    wall = time.perf_counter() - clock
    stderr = process.stderr.read().decode() if process.stderr else ""
    if status != 0:
        raise SystemExit(f"{name}: lcchain report failed ({status}): {stderr[-2000:]}")
    rows = json.loads((out / "report.json").read_text())["paper"]["row_seconds"]
    return {"wall": wall, "cpu": usage.ru_utime + usage.ru_stime, "load": load, "out": out,
            "row_seconds": sum(sum(v.values()) for v in rows.values())}


def main() -> None:
    before = sys.argv[1] if len(sys.argv) > 1 else BEFORE
    rounds = int(sys.argv[2]) if len(sys.argv) > 2 else ROUNDS
    with tempfile.TemporaryDirectory(prefix="lcchain-bench-report-") as folder:
        scratch = Path(folder)
        old = scratch / "before-src"
        old.mkdir()
        archive = subprocess.run(["git", "archive", before, "lcchain"], cwd=ROOT, check=True, capture_output=True)
        subprocess.run(["tar", "-x", "-C", str(old)], input=archive.stdout, check=True)
        runs: dict[str, list[dict[str, Any]]] = {"before": [], "after": []}
        for i in range(rounds):
            order = ["before", "after"] if i % 2 == 0 else ["after", "before"]
            for which in order:
                source = old if which == "before" else ROOT
                runs[which].append(_cold_report(source, scratch, f"{which}-{i}"))
                r = runs[which][-1]
                print(f"round {i + 1} {which}: load {r['load']:.2f}, wall {r['wall']:.1f} s, CPU {r['cpu']:.1f} s",
                      file=sys.stderr, flush=True)
        compared = [compare_reports(a["out"], b["out"]) for a in runs["before"] for b in runs["after"]]
        differences = sorted({d for found, _ in compared for d in found})
        dropped = compared[0][1]
        head = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=ROOT, capture_output=True, text=True)
        print("# `lcchain report` cold: the whole command, before and after issue 35\n")
        print(f"Machine: {os.cpu_count()} cores ({len(os.sched_getaffinity(0))} usable), Python "
              f"{platform.python_version()}, shared with other work (load average before each run below). "
              f"Command: `{sys.executable} benchmarks/bench_report_cold.py {before} {rounds} > "
              "benchmarks/report_cold.md` "
              f"(after = {head.stdout.strip()}{' with uncommitted changes' if _dirty() else ''}).\n")
        print("Each run: `python -m lcchain report --out DIR` in a process of its own with `XDG_CACHE_HOME` an "
              "empty folder (every row designed again), before and after alternating. *wall*: the whole "
              "command, start-up included; *CPU*: user + system time of it and all its children (lcchain, "
              "ngspice, gnucap, the pool's workers); *idle estimate*: CPU / 2 + "
              f"{SERIAL_S:g} s run alone, the wall a 2-core machine with nothing else to do would see (an "
              "estimate, not a measurement); *rows*: the seconds the rows' designs took, summed (each measured "
              "where it ran).\n")
        print("| round | code | load before | wall s | CPU s | idle estimate s | rows s (summed) |")
        print("|---|---|---|---|---|---|---|")
        for i in range(rounds):
            for which in ("before", "after"):
                r = runs[which][i]
                print(f"| {i + 1} | {which} | {r['load']:.2f} | {r['wall']:.1f} | {r['cpu']:.1f} | "
                      f"{r['cpu'] / 2 + SERIAL_S:.1f} | {r['row_seconds']:.1f} |")
        best = {which: min(r["wall"] for r in runs[which]) for which in runs}
        cpu = {which: min(r["cpu"] for r in runs[which]) for which in runs}
        print(f"\nBest wall: before {best['before']:.1f} s, after {best['after']:.1f} s "
              f"({best['before'] / best['after']:.2f}x); least CPU: before {cpu['before']:.1f} s, after "
              f"{cpu['after']:.1f} s ({cpu['before'] / cpu['after']:.2f}x).\n")
        print(f"Reports compared (every before against every after, timings blanked: `compare_reports` in the "
              f"script): {'the same' if not differences else 'DIFFERENT in ' + ', '.join(differences)}, but for "
              f"the {len(dropped)} checks the after code no longer runs: {', '.join(dropped) or 'none'}.")


def _dirty() -> bool:
    status = subprocess.run(["git", "status", "--porcelain", "lcchain"], cwd=ROOT, capture_output=True, text=True)
    return bool(status.stdout.strip())


if __name__ == "__main__":
    main()
