"""Rows of the paper's tables designed on every core, in the background (issue 23).

Each row of Tables I and II is one optimal design (:func:`lcchain.theory.design.optimal_design`), independent of
the others, and the cold report spends most of its time on them.  :class:`BackgroundDesigns` sends the rows to a
spawn process pool as soon as it is opened, largest first (so that the longest designs do not finish last, alone
on one core), and the caller goes on with something else (the report runs its circuit checks meanwhile);
:meth:`BackgroundDesigns.take` then waits for one row.  The theory runs under a fixed BLAS thread limit
(:mod:`lcchain.core.blas`), so a row designed in a worker is the one designed here, bit for bit.

The pool's workers are those of the study executors (:mod:`.executors`): they ignore Ctrl-C and die with their
parent; leaving the block by an exception (an interrupt included) kills them rather than waiting.
"""

from __future__ import annotations

import multiprocessing
import os
import time
from collections.abc import Iterable
from concurrent.futures import Future, ProcessPoolExecutor
from types import TracebackType
from typing import Any

from ..core.types import DesignCase
from ..theory.design import optimal_design
from .executors import _die_with_parent, _kill_pool, default_workers

__all__ = ["design_row", "BackgroundDesigns", "design_cost"]


def design_row(case: DesignCase, N: int) -> dict[str, Any]:
    """One row of Table I or II: ``Design.to_dict()`` and the ``seconds`` its design took."""
    start = time.perf_counter()
    row = optimal_design(case, N).to_dict()
    return {**row, "seconds": time.perf_counter() - start}


def design_cost(case: str, N: int) -> float:
    """A rough relative cost of a design, for the order rows are sent in (measured: two-mass N = 1e5 takes
    about as long as one-mass N = 5e5, and every design pays a fixed cost for its optimisation)."""
    return (5.0 if case == "two-mass" else 1.0) * N + 2000.0


class BackgroundDesigns:
    """Rows designed by a spawn process pool while the caller does other work; a context manager.

    Parameters
    ----------
    pairs : iterable of (case, N)
        The rows to design (repeats are designed once).
    workers : int, optional
        Processes (default: one per core this process may use); with one (or no rows), nothing is started
        and :meth:`take` designs the row here.
    """

    def __init__(self, pairs: Iterable[tuple[DesignCase, int]], workers: int | None = None):
        wanted = sorted(set(pairs), key=lambda pair: -design_cost(*pair))
        self.workers = min(workers or default_workers(), len(wanted))
        self._futures: dict[tuple[str, int], Future[dict[str, Any]]] = {}
        self._pool: ProcessPoolExecutor | None = None
        if self.workers <= 1:
            return
        context = multiprocessing.get_context("spawn")
        self._pool = ProcessPoolExecutor(max_workers=self.workers, mp_context=context,
                                         initializer=_die_with_parent, initargs=(os.getpid(),))
        try:
            for case, N in wanted:
                self._futures[(case, N)] = self._pool.submit(design_row, case, N)
        except BaseException:
            self.close(finished=False)
            raise

    def __contains__(self, pair: object) -> bool:
        return pair in self._futures

    def take(self, case: DesignCase, N: int) -> dict[str, Any]:
        """The row of (case, N): waits for it if it was sent to the pool, else designs it here."""
        future = self._futures.get((case, N))
        if future is None:
            return design_row(case, N)
        return future.result()

    def close(self, finished: bool = True) -> None:
        """Shut the pool down: waiting for it after a clean finish, killing its workers otherwise."""
        pool, self._pool = self._pool, None
        if pool is None:
            return
        if finished and all(future.done() for future in self._futures.values()):
            pool.shutdown(wait=True)
        else:  # interrupted, failed, or rows nobody took: nothing may keep running
            _kill_pool(pool)

    def __enter__(self) -> BackgroundDesigns:
        return self

    def __exit__(self, kind: type[BaseException] | None, error: BaseException | None,
                 traceback: TracebackType | None) -> None:
        self.close(finished=kind is None)
