"""Every ``lcchain`` command of the README and the documentation's pages, run as written from a wheel in a fresh
virtual environment.

Builds the wheel (``python -m build``), makes a new virtual environment, installs the wheel with the
``data`` extra from the package registry (the newest versions it serves), and runs each command line of
the shell blocks of the README and of the site's pages (``PAGES``) that starts with ``lcchain`` in one empty
folder, in the pages' order (so a scene written by ``lcchain examples`` is there for the ``lcchain run`` that
follows).  Lines holding ``...``
(a placeholder for options) are listed as skipped.  Prints a markdown table: the command, its exit status
and its wall time.

    python benchmarks/readme_from_wheel.py [--keep DIR] [--only REGEX] > benchmarks/readme_from_wheel.md

Exit status 1 when any command exits non-zero.
"""

from __future__ import annotations

import argparse
import os
import re
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
#: The README and the documentation's pages, in the site's order (a scene is written before it is run).
PAGES = ["README.md", "docs/getting-started.md", "docs/physics.md"] + [f"docs/guide/{name}.md" for name in (
    "simulate", "spectrum", "scenes", "studies", "batch", "report", "requirements")]


def readme_commands(text: str) -> list[str]:
    """The README's ``lcchain`` command lines (continuations joined, comments cut), in order."""
    commands = []
    for block in re.findall(r"```(?:sh|console)\n(.*?)```", text, flags=re.S):
        lines = block.replace("\\\n", " ").splitlines()
        for line in lines:
            line = re.sub(r"\s+#.*$", "", line).strip().removeprefix("$ ")  # "$ lcchain ...": a shown session
            if line.startswith("lcchain "):
                commands.append(re.sub(r"\s+", " ", line))
    return commands


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--keep", type=Path, help="work here (and keep it) instead of a temporary folder")
    parser.add_argument("--only", help="run only the commands this regular expression finds something in")
    args = parser.parse_args()
    work = args.keep or Path(tempfile.mkdtemp(prefix="lcchain-readme-"))
    work.mkdir(parents=True, exist_ok=True)
    dist, venv, here = work / "dist", work / "venv", work / "empty"
    here.mkdir(exist_ok=True)
    subprocess.run([sys.executable, "-m", "build", "--wheel", "--outdir", str(dist), str(ROOT)], check=True,
                   capture_output=True)
    wheel = max(dist.glob("lcchain-*.whl"), key=lambda p: p.stat().st_mtime)
    subprocess.run([sys.executable, "-m", "venv", str(venv)], check=True)
    subprocess.run([str(venv / "bin" / "pip"), "install", "-q", f"{wheel}[data]"], check=True)
    env = dict(os.environ, PATH=f"{venv / 'bin'}:{os.environ['PATH']}")
    env.pop("PYTHONPATH", None)
    print(f"Wheel {wheel.name} in a fresh virtual environment; commands run in an empty folder, in order.\n")
    print("| command | exit | seconds |\n|---|---:|---:|")
    failed = 0
    for command in [c for page in PAGES for c in readme_commands((ROOT / page).read_text())]:
        if args.only and not re.search(args.only, command):
            continue
        if "..." in command:
            print(f"| `{command}` | skipped (placeholder) | |")
            continue
        start = time.perf_counter()
        done = subprocess.run(["bash", "-c", command], cwd=here, env=env, capture_output=True, text=True)
        seconds = time.perf_counter() - start
        failed += done.returncode != 0
        print(f"| `{command}` | {done.returncode} | {seconds:.1f} |", flush=True)
        if done.returncode != 0:
            print(f"\n```\n{done.stderr[-1500:]}\n```\n", flush=True)
    print(f"\n{failed} command(s) failed. Python {sys.version.split()[0]}; {os.cpu_count()} cores.")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
