"""ngspice's ``"shared"`` transport: the shared library (``libngspice.so.0``) through PySpice, in a child.

The child (``python -m lcchain.spice.ngspice.shared_worker``) exits after one run, so no simulator state
survives between runs; PySpice is imported only there, so ``import lcchain`` never loads it.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from ...core.budget import show_bytes
from ...core.errors import SimulationError
from ..job import Progress, TransportJob
from ..log import failure_reason, useful_output
from ..simulator import Simulator
from ..text import canonical_vector_name
from .place import Place
from .shared_child import call_shared_worker, decode_worker_payload

if TYPE_CHECKING:
    import numpy as np

__all__ = ["run_shared"]


def run_shared(job: TransportJob, simulator: Simulator, place: Place,
               progress: Progress | None = None) -> tuple[dict[str, np.ndarray], str, float]:
    # One call in a child that exits after the run: no progress to report; its memory and output are watched.
    limit = job.max_output_bytes
    stdout, log, status = call_shared_worker(place.prefix, {"netlist": job.text, "library": simulator.executable},
                                             job.timeout, place.cwd, "run", place.env, limit, job.max_resident_bytes)
    if limit is not None and len(stdout) > limit:
        raise SimulationError(f"the ngspice shared-library child's vectors grew past {show_bytes(limit)}, the most "
                              "this run may write (its price, within --max-memory)", useful_output(log))
    try:
        meta, arrays = decode_worker_payload(stdout)
    except Exception as exc:  # noqa: BLE001 - a crashed child leaves empty or partial bytes
        raise SimulationError(f"the shared-library child (exit status {status}) returned no result ({exc})",
                              useful_output(log)) from None
    if meta.get("lines") != job.lines:
        raise SimulationError("the shared-library child handed ngspice other lines than the ones lcchain checked",
                              useful_output(log))
    if meta["errors"]:
        raise SimulationError(failure_reason(log, "the ngspice shared library failed: " + "; ".join(meta["errors"])),
                              useful_output(log))
    if status != 0:
        raise SimulationError(failure_reason(log, f"the shared-library child exited with status {status}"),
                              useful_output(log))
    if meta["complex"]:
        raise SimulationError("the transient plot holds complex vectors; lcchain reads real data only",
                              useful_output(log))
    columns = {canonical_vector_name(name): arr for name, arr in zip(meta["names"], arrays, strict=True)}
    return columns, log, float(meta["wall_s"])

