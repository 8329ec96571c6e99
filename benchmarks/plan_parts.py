"""Where a batch's plan spends its time per netlist, beside reading and splitting the file (issue 35 item 1).

Run from the repository root::

    .venv/bin/python benchmarks/plan_parts.py [--sizes 10 100 1000] [--count 200] [--rounds 7]

For each N it writes ``count`` netlists as :mod:`bench_plan` does and times, in this process, fastest of
``rounds`` rounds over all of them, per netlist: reading and splitting the file into lines, the allow-list
(:func:`lcchain.spice.foreign.allowed_netlist`), the price's split into bodies (``pricing._scopes``), what the
netlist holds (:func:`lcchain.spice.pricing.read_contents`: the bodies and the tally of their elements), the
analysis, saves and price (:func:`lcchain.spice.foreign.read_foreign`, which reads the contents) and the whole
plan (:func:`lcchain.studies.plan.batch_plan`).  Each is printed in ms and as a multiple of reading and splitting.
"""

from __future__ import annotations

import argparse
import os
import sys
import tempfile
import time
from collections.abc import Callable
from pathlib import Path

HERE = Path(__file__).resolve().parent


def _parts(paths: list[Path]) -> dict[str, Callable[[], object]]:
    """Each part of the plan of ``paths``, as work to time (the first: reading and splitting each file)."""
    from lcchain.spice.foreign import allowed_netlist, read_foreign
    from lcchain.spice.pricing import _scopes, read_contents
    from lcchain.spice.result import read_include
    from lcchain.studies.plan import batch_plan

    texts = [read_include(p, "NETLIST") for p in paths]
    checked = [allowed_netlist(t, str(p), p.parent, read_include) for t, p in zip(texts, paths, strict=True)]
    return {
        "split": lambda: [p.read_text().split("\n") for p in paths],
        "allow": lambda: [allowed_netlist(t, str(p), p.parent, read_include)
                          for t, p in zip(texts, paths, strict=True)],
        "bodies": lambda: [_scopes(c) for c in checked],
        "contents": lambda: [read_contents(c) for c in checked],
        "foreign": lambda: [read_foreign(c, "netlist", lambda: "39") for c in checked],
        "plan": lambda: batch_plan([str(p) for p in paths], engine_version=lambda: "39"),
    }


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--sizes", type=int, nargs="+", default=[10, 100, 1000])
    parser.add_argument("--count", type=int, default=200)
    parser.add_argument("--rounds", type=int, default=7)
    args = parser.parse_args()
    sys.path.insert(0, str(HERE))
    from bench_batch import write_netlists

    print(f"Load average (1 min): {os.getloadavg()[0]:.2f}; fastest of {args.rounds} rounds of {args.count} netlists.")
    print()
    print("| N | read + split (ms) | allow-list | bodies | contents (bodies + tally) | analysis, saves, price | "
          "`batch_plan` |")
    print("|---:|---:|---:|---:|---:|---:|---:|")
    with tempfile.TemporaryDirectory() as folder:
        for N in args.sizes:
            paths = [Path(p) for p in write_netlists(Path(folder) / f"N{N}", N, args.count)]
            parts = _parts(paths)
            best: dict[str, float] = {}
            for _ in range(args.rounds):
                for name, work in parts.items():
                    start = time.perf_counter()
                    work()
                    best[name] = min(best.get(name, float("inf")), (time.perf_counter() - start) / len(paths))
            split = best.pop("split")
            cells = " | ".join(f"{1e3 * v:.3f} ({v / split:.1f}x)" for v in best.values())
            print(f"| {N} | {1e3 * split:.3f} | {cells} |")
    print(f"\nLoad average (1 min) after: {os.getloadavg()[0]:.2f}.")
    return 0


if __name__ == "__main__":
    sys.exit(main())
