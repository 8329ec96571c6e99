"""The paper's figures and the validation report (issue 12): wall times cold and cached, and the screenshot.

Run from the repository root (about 5 minutes):

    .venv/bin/python benchmarks/bench_report.py > benchmarks/report.md

Each command runs as a user would run it (``.venv/bin/lcchain``), with its own cache folder: "cold" starts
from an empty one, "cached" reuses what the cold run stored.  The full figures are written to
``docs/figures`` (the README shows them) and a screenshot of the full report's first screen to
``docs/report.png`` (Debian's Chromium through Playwright, 1366 x 900).
"""

from __future__ import annotations

import os
import platform
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
LCCHAIN = str(Path(sys.executable).parent / "lcchain")


def timed(argv: list[str], cache: Path) -> tuple[float, str]:
    env = {**os.environ, "XDG_CACHE_HOME": str(cache)}
    start = time.perf_counter()
    proc = subprocess.run([LCCHAIN, *argv], capture_output=True, text=True, env=env, cwd=ROOT, check=False)
    seconds = time.perf_counter() - start
    if proc.returncode != 0:
        raise SystemExit(f"{' '.join(argv)} failed ({proc.returncode}):\n{proc.stderr[-2000:]}")
    return seconds, proc.stdout.strip().splitlines()[-1] if proc.stdout.strip() else ""


def screenshot(page: Path, out: Path) -> None:
    from playwright.sync_api import sync_playwright

    with sync_playwright() as p:
        browser = p.chromium.launch(executable_path=shutil.which("chromium"), headless=True, args=["--no-sandbox"])
        try:
            tab = browser.new_page(viewport={"width": 1366, "height": 900})
            tab.goto(page.resolve().as_uri(), wait_until="load")
            tab.screenshot(path=str(out))
        finally:
            browser.close()


def main() -> None:
    work = Path(tempfile.mkdtemp(prefix="lcchain-bench-report-"))
    rows = []
    try:
        for label, argv, cache in (
            ("figures --quick, cold", ["figures", "--out", str(work / "fq"), "--quick"], work / "c1"),
            ("figures (full), cold", ["figures", "--out", "docs/figures"], work / "c2"),
            ("figures (full), cached", ["figures", "--out", str(work / "ff")], work / "c2"),
            ("report --quick, cold", ["report", "--out", str(work / "rq"), "--quick"], work / "c3"),
            ("report (full), cold", ["report", "--out", str(work / "rf")], work / "c4"),
            ("report (full), cached", ["report", "--out", str(work / "rf2")], work / "c4"),
        ):
            seconds, said = timed(argv, cache)
            rows.append((label, " ".join(["lcchain", *argv]).replace(str(work), "DIR"), seconds,
                         said.replace(str(work), "DIR")))
            print(f"{label}: {seconds:.1f} s", file=sys.stderr)
        screenshot(work / "rf" / "index.html", ROOT / "docs" / "report.png")
        size = (work / "rf" / "index.html").stat().st_size
    finally:
        shutil.rmtree(work, ignore_errors=True)
    print("# The paper's figures and the validation report: wall time\n")
    print("Command: `.venv/bin/python benchmarks/bench_report.py > benchmarks/report.md`  ")
    print(f"Machine: {platform.machine()}, {os.cpu_count()} cores, Python {platform.python_version()}\n")
    print("| what | command | wall s | it said |")
    print("|---|---|---:|---|")
    for label, command, seconds, said in rows:
        print(f"| {label} | `{command}` | {seconds:.1f} | {said.replace(str(ROOT) + '/', '')} |")
    print(f"\nThe full report's page: {size / 2**20:.1f} MiB, every figure embedded.  Targets (issue 12): figures "
          "--quick under 1 minute; the full report under 10 minutes, under 2 when its rows are cached.  "
          "Per-row design times: [rows.md](rows.md).")


if __name__ == "__main__":
    main()
