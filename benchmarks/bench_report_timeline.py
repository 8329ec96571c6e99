"""Where a cold ``lcchain report`` runs alone (issue 35): the seconds before its pool has work, and after its last
result, from the report's own progress calls.

    .venv/bin/python benchmarks/bench_report_timeline.py OUT_DIR [--quick]

Prints the seconds from start to the pool's start (imports, finding the engines, pricing the jobs), to the last
row of Tables I and II, to the pool's last result, and to the end; the first and the last part are what no second
core can share (``SERIAL_S`` of ``bench_report_cold.py``).  ``XDG_CACHE_HOME`` is an empty folder: cold.
"""

from __future__ import annotations

import os
import sys
import tempfile
import time

START = time.perf_counter()


def main() -> None:
    os.environ["XDG_CACHE_HOME"] = tempfile.mkdtemp(prefix="lcchain-timeline-")
    from lcchain.app.validation import make_report

    marks: list[tuple[float, str]] = []

    def progress(done: int, total: int, label: str) -> None:
        marks.append((time.perf_counter() - START, label))

    make_report(sys.argv[1], quick="--quick" in sys.argv[2:], progress=progress)
    end = time.perf_counter() - START
    started = next(t for t, label in marks if label.startswith("Table"))
    rows = max(t for t, label in marks if label.startswith("Table"))
    pool = next(t for t, label in marks if label == "done")
    print(f"pool started {started:.1f} s, rows all in {rows:.1f} s, pool's last result {pool:.1f} s, end {end:.1f} s: "
          f"alone {started:.1f} + {end - pool:.1f} s; load average at the end {os.getloadavg()[0]:.2f}")


if __name__ == "__main__":
    main()
