"""Counts of the bad-input catalogue per family and class: ``python tests/catalogue.py [-k TEXT]``.

Runs every case of the test modules that hold a ``CASES`` dict (the same
cases the tests run, with real ngspice) and prints one row per family with
how many cases ended in each class of :mod:`helpers.catalogue`, then the
cases that were not clean.
"""

from __future__ import annotations

import argparse
import importlib
import sys
import tempfile
from collections import Counter
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

from helpers.catalogue import CLASSES, run_case  # noqa: E402

from lcchain.cli import main as lcchain_main  # noqa: E402

MODULES = ("test_bad_inputs", "test_boundary_netlists", "test_boundary_inputs", "test_boundary_stores",
           "test_boundary_pricing", "test_canonical_text", "test_foreign_cards")


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("-k", default="", help="only the cases whose name holds this text")
    args = parser.parse_args()
    counts: dict[str, Counter[str]] = {}
    bad: list[str] = []
    for module_name in MODULES:
        try:
            module = importlib.import_module(module_name)
        except ModuleNotFoundError:
            continue
        for name, case in getattr(module, "CASES", {}).items():
            if args.k not in name:
                continue
            with tempfile.TemporaryDirectory() as folder:
                outcome = run_case(case, Path(folder), lcchain_main)
            counts.setdefault(case.family, Counter())[outcome.kind] += 1
            if outcome.kind != "clean":
                bad.append(f"{module_name}::{name}: {outcome.kind}: {outcome.detail}")
    width = max((len(f) for f in counts), default=6)
    print(f"{'family':<{width}}  " + "  ".join(f"{c:>9}" for c in CLASSES))
    for family, counter in counts.items():
        print(f"{family:<{width}}  " + "  ".join(f"{counter[c]:>9}" for c in CLASSES))
    total = sum(counts.values(), Counter())
    print(f"{'total':<{width}}  " + "  ".join(f"{total[c]:>9}" for c in CLASSES))
    for line in bad:
        print(line)
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
