"""Small netlists and store readers the tests share."""

from __future__ import annotations

import os
import sqlite3
from collections.abc import Callable
from pathlib import Path

#: Perfect N=3 chain of the paper: masses (1.5, 1, 1.5) -> inductors in H, unit springs -> 1 F.
#: Loop 1 is kicked with I(L1)(0) = 1 A; free ends are 0 V sources (wires) to ground.
LADDER = """\
* three-loop LC ladder, kick of loop 1
L1 n0 n1 1.5 IC=1.0
C12 n1 0 1.0
L2 n1 n2 1.0
C23 n2 0 1.0
L3 n2 n3 1.5
Vw0 n0 0 0
Vw3 n3 0 0
.options method=trap reltol=1e-6 abstol=1e-12 chgtol=1e-20 maxord=2
.tran 0.001 7.7 0 0.001 uic
.save i(l1) i(l3)
.end
"""


#: A netlist lcchain did not write, within the allow-list: what ``lcchain batch`` is for.
RC_NETLIST = """\
* an RC low-pass lcchain did not write
V1 in 0 PULSE(0 1 0 1e-9 1e-9 1e-6 2e-6)
R1 in out 1000
C1 out 0 1e-9
.tran 1e-8 2e-6
.end
"""


def stored_records(path: Path) -> int:
    """Runs a store holds so far, read-only (a missing store stays missing, for the driver to make whole)."""
    try:
        with sqlite3.connect(f"file:{path}?mode=ro", uri=True, timeout=5) as db:
            count = db.execute("SELECT COUNT(*) FROM records").fetchone()[0]
        db.close()
        return int(count)
    except sqlite3.Error:
        return 0


def fifo(name: str) -> Callable[[Path], None]:
    """Makes a FIFO ``name`` in the folder it is given (an include that would block ngspice forever)."""
    def make(folder: Path) -> None:
        os.mkfifo(folder / name)
    return make


def link(name: str, target: str) -> Callable[[Path], None]:
    """Makes a symbolic link ``name`` to ``target`` in the folder it is given (an include out of the tree)."""
    def make(folder: Path) -> None:
        (folder / name).symlink_to(target)
    return make
