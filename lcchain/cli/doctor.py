"""``lcchain doctor``: check ngspice, its shared library and PySpice (:func:`lcchain.app.doctor.doctor`)."""

from __future__ import annotations

import argparse

from .common import EXIT_MISSING, EXIT_OK, Parser, Subcommands

__all__ = ["add_parser", "cmd_doctor"]


def add_parser(sub: Subcommands, budget: list[Parser]) -> None:
    p = sub.add_parser("doctor", help="check ngspice, its shared library and PySpice")
    p.set_defaults(func=cmd_doctor)


def cmd_doctor(args: argparse.Namespace) -> int:
    from ..app.doctor import doctor

    checks = doctor()
    for check in checks:
        mark = "ok  " if check.ok else "FAIL" if check.required else "warn"
        print(f"[{mark}] {check.name}: {check.detail}")
        if not check.ok and check.fix:
            print(f"       fix: {check.fix}")
    return EXIT_OK if all(c.ok for c in checks if c.required) else EXIT_MISSING
