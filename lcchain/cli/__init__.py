"""Command line: ``lcchain <command> ...``, a thin layer over the package; nothing imports it.

Exit status: 0 ok, 1 simulation or comparison failed, 2 bad usage or bad
input, 3 simulator missing.
"""

from .main import main

__all__ = ["main"]
