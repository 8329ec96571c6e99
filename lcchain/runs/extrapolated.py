"""The runs of an extrapolation, made into one record (:mod:`lcchain.compare.extrapolate` has the method).

Its members are ordinary runs (:class:`~lcchain.runs.spec.RunSpec` with aligned steps), executed anywhere like
any other (in this process, on a pool, on a Dask worker); :func:`combined_record` brings them together once they
are all back.
"""

from __future__ import annotations

import hashlib
from collections.abc import Sequence
from dataclasses import replace

import numpy as np

from ..compare.extrapolate import WEIGHTS, combine
from ..compare.waveforms import Signals
from ..core.blas import fixed_blas_threads
from ..core.errors import ParameterError
from ..theory.modes import Modes
from .execute import RunRecord, metrics_of, theory_at, waveform_digest
from .spec import Theory

__all__ = ["combined_record", "combined_key"]


def combined_key(keys: Sequence[str]) -> str:
    """The key of an extrapolation's result: its members' keys, coarsest first, hashed."""
    return hashlib.sha256("".join(keys).encode("ascii")).hexdigest()


@fixed_blas_threads
def combined_record(theory: Theory, members: Sequence[RunRecord], steps: Sequence[float], *,
                    predicted_error: float | None = None, modes: Modes | None = None,
                    sims: Sequence[tuple[np.ndarray, np.ndarray]] | None = None) -> RunRecord:
    """One record from the runs at h, h/2, h/4: their extrapolated signals against the theory.

    Parameters
    ----------
    theory : Theory
        The coarsest member's theory (its chain, excitation, transits).
    members : sequence of RunRecord
        The runs, coarsest first.
    steps : sequence of float
        Their steps, units of sqrt(L0 C0).
    predicted_error : float, optional
        The combination's predicted error (:func:`lcchain.compare.extrapolate.predicted_extrapolated_error`).
    modes : Modes, optional
        The chain's modes (else the theory's, or computed).
    sims : sequence of (t, sim), optional
        Each member's dimensionless times and loops (:func:`lcchain.runs.execute.loop_sims`), for members
        read back without their signals (a study's store); else the members' own signals.

    Returns
    -------
    RunRecord
        ``ok`` with the combined signals and metrics, the result of the coarsest run, a digest of the combined
        arrays and the members' summed times; or the first member's failure, its reason naming the run.
    """
    runs = len(members)
    if runs not in WEIGHTS or runs != len(steps) or (sims is not None and len(sims) != runs):
        raise ParameterError("members", runs, "1, 2 or 3 runs, one per step")
    key = combined_key([m.key for m in members])
    wall_s, total_s = sum(m.wall_s for m in members), sum(m.total_s for m in members)
    for i, member in enumerate(members):
        if not member.ok:
            return replace(member, key=key, reason=f"{member.reason} (the run at dt = {steps[i]:.4g}, {i + 1} of "
                           f"{runs})", wall_s=wall_s, total_s=total_s)
    if runs == 1 and sims is None:
        return members[0]
    signals = [m.signals for m in members]
    if sims is None:
        if any(s is None for s in signals):
            raise ParameterError("members", "runs without a theory", "runs compared with a theory")
        sims = [(s.t, s.sim) for s in signals if s is not None]
    grid, combined, keep = combine([t for t, _ in sims], [sim for _, sim in sims])
    first = signals[0]
    reference = first.theory[:, keep] if first is not None else theory_at(theory, grid, modes)
    result = Signals(grid, combined, reference, theory.excitation)
    metrics = metrics_of(replace(theory, predicted_error=predicted_error), result, split=False, modes=modes)
    digest = waveform_digest(grid, {f"loop{i}": row for i, row in enumerate(combined)})
    return replace(members[0], key=key, signals=result, metrics=metrics, digest=digest, wall_s=wall_s,
                   total_s=total_s)
