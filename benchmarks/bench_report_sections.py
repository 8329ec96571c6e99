"""Where a cold ``lcchain report`` spends its CPU, section by section (issue 35), before and after.

Run from the repository root (about 10 minutes on 2 cores):

    .venv/bin/python benchmarks/bench_report_sections.py [BEFORE_COMMIT | none] > benchmarks/report_sections.md

Each section of the report is done here one piece after the other, in a process of its own per code version
(the before code exported with ``git archive``; ``XDG_CACHE_HOME`` an empty folder), and measured in CPU seconds
of that process and of its children (ngspice, gnucap): on a machine shared with other work CPU time is what can
be compared, and on 2 cores the whole report cannot take less wall time than half the sum.  The pieces are the
public functions the report's pool runs (:func:`lcchain.studies.validation.run_check`,
:func:`lcchain.studies.spectrum_checks.run_spectrum_check`, :func:`lcchain.studies.requirements.run_requirements`,
:func:`lcchain.studies.designs.design_row`) and the figures' data and drawing.
"""

from __future__ import annotations

import json
import os
import platform
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
BEFORE = "b97ce31"

#: Run in a process of its own with the code under test first on sys.path: prints one JSON list of
#: [section, piece, CPU s of the process, CPU s of its children].
_PROBE = r'''
import json, resource, sys
def cpu():
    own, kids = resource.getrusage(resource.RUSAGE_SELF), resource.getrusage(resource.RUSAGE_CHILDREN)
    return own.ru_utime + own.ru_stime, kids.ru_utime + kids.ru_stime
out = []
def timed(section, piece, function, *args):
    own, kids = cpu()
    result = function(*args)
    own2, kids2 = cpu()
    out.append([section, piece, own2 - own, kids2 - kids])
    return result
own0, _ = cpu()
from lcchain.report.build import _check_figure, report_rows
from lcchain.report.figure_data import DesignRows
from lcchain.report.html import figure_png
from lcchain.report.paper_figures import FIGURES
from lcchain.studies.designs import design_row
from lcchain.studies.requirements import requirements_jobs, run_requirements
from lcchain.studies.spectrum_checks import run_spectrum_check, spectrum_jobs
from lcchain.studies.validation import check_jobs, installed_engines, run_check
out.append(["start", "imports", cpu()[0] - own0, 0.0])
simulators = installed_engines()
checks = []
for job in check_jobs(simulators=simulators):
    size = "N = 1000" if job.N >= 1000 else "N <= 100"
    checks.append(timed(f"checks {job.simulator.engine} {size}", job.name, run_check, job))
for job in spectrum_jobs(simulator=simulators[0]):
    timed("spectrum", job.name, run_spectrum_check, job)
for job in requirements_jobs():
    timed("requirements", job.name, run_requirements, job)
rows = DesignRows()
for case, N in report_rows():
    row = timed("rows N >= 10000" if N >= 10000 else "rows N < 10000", f"{case} {N}", design_row, case, N)
    rows._rows[f"{case}:{N}"] = row
for check in checks:
    if check.curves:
        timed("figures: checks", check.name, lambda c: figure_png(_check_figure(c), dpi=90), check)
for figure in FIGURES:
    section = "figures: minimiz" if figure.label == "minimiz" else "figures: the paper's others"
    timed(section, figure.label, lambda f: figure_png(f.build(rows, False)), figure)
print(json.dumps(out))
'''


def _measure(source: Path, scratch: Path) -> list[list]:
    cache = scratch / "cache"
    cache.mkdir(parents=True)
    env = dict(os.environ, PYTHONPATH=str(source), XDG_CACHE_HOME=str(cache))
    done = subprocess.run([sys.executable, "-c", _PROBE], cwd=scratch, env=env, capture_output=True, text=True,
                          check=True)
    return json.loads(done.stdout.strip().splitlines()[-1])


def main() -> None:
    before = sys.argv[1] if len(sys.argv) > 1 else BEFORE
    with tempfile.TemporaryDirectory(prefix="lcchain-bench-sections-") as folder:
        scratch = Path(folder)
        old = scratch / "before-src"
        old.mkdir()
        if before != "none":
            archive = subprocess.run(["git", "archive", before, "lcchain"], cwd=ROOT, check=True, capture_output=True)
            subprocess.run(["tar", "-x", "-C", str(old)], input=archive.stdout, check=True)
        loads, results = {}, {}
        versions = (("before", old), ("after", ROOT)) if before != "none" else (("after", ROOT),)
        for which, source in versions:
            loads[which] = os.getloadavg()[0]
            results[which] = _measure(source, scratch / which)
            print(f"{which}: done", file=sys.stderr, flush=True)
    head = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=ROOT, capture_output=True, text=True)
    print("# `lcchain report` cold, section by section: CPU seconds\n")
    said = ", ".join(f"{which} {load:.2f}" for which, load in loads.items())
    print(f"Machine: {os.cpu_count()} cores, Python {platform.python_version()}, shared with other work (load "
          f"average before: {said}). Command: `{sys.executable} "
          f"benchmarks/bench_report_sections.py {before} > benchmarks/report_sections.md` (after = "
          f"{head.stdout.strip()}).\n")
    print("Every piece of a cold report done one after the other in one process (no pool), CPU seconds of the "
          "process (*lcchain*) and of its children (*engines*: ngspice, gnucap). On 2 cores the report cannot "
          "take less wall time than half the total.\n")
    names = list(results)
    print("| section | " + " | ".join(f"{w}: pieces | {w}: lcchain s | {w}: engines s" for w in names) + " |")
    print("|---|" + "---|---|---|" * len(names))
    sections = list(dict.fromkeys(row[0] for which in names for row in results[which]))
    totals = {which: [0.0, 0.0] for which in names}
    for section in sections:
        cells = []
        for which in names:
            pieces = [row for row in results[which] if row[0] == section]
            own, kids = sum(row[2] for row in pieces), sum(row[3] for row in pieces)
            totals[which][0] += own
            totals[which][1] += kids
            cells += [str(len(pieces)), f"{own:.1f}", f"{kids:.1f}"]
        print(f"| {section} | " + " | ".join(cells) + " |")
    print("| **total** | " + " | ".join(f" | {totals[w][0]:.1f} | {totals[w][1]:.1f}" for w in names) + " |")
    print("\nTotal CPU: " + ", ".join(f"{w} {sum(totals[w]):.1f} s (half: {sum(totals[w]) / 2:.1f} s, the least "
                                       "wall time on 2 cores)" for w in names) + ".")
    print("\nThe ten most expensive pieces after:\n")
    for row in sorted(results["after"], key=lambda row: -(row[2] + row[3]))[:10]:
        print(f"- {row[0]}: {row[1]}, {row[2] + row[3]:.2f} s")


if __name__ == "__main__":
    main()
