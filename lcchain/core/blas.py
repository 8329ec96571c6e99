"""Theory computed under a fixed BLAS thread limit: the same bits in any process.

OpenBLAS splits a matrix product over its threads, and the order of the
additions follows the split: with one and two threads the modal sums of an
N = 400 chain differ in 16,099 of 40,002 values (by up to 1e-16).  A study
computes theory in a parent, in pool workers and on Dask workers, and its
results must be bit-identical whichever ran them, so every public theory
entry point runs under ``threadpoolctl.threadpool_limits(1)``.  One thread is
also faster here: the work is many small products, where threads cost more
than they give (N = 20000 two-mass design: 4.0 s against 17.4 s on this 2-core
machine under load).

Only the outermost call pays for the limit (about 0.3 ms); nested decorated
calls see that it is in force and run straight through.
"""

from __future__ import annotations

import functools
import threading
from collections.abc import Callable
from typing import ParamSpec, TypeVar

from threadpoolctl import threadpool_limits

__all__ = ["BLAS_THREADS", "fixed_blas_threads"]

#: Threads every theory computation gives BLAS.
BLAS_THREADS = 1

P = ParamSpec("P")
R = TypeVar("R")

_state = threading.local()


def fixed_blas_threads(function: Callable[P, R]) -> Callable[P, R]:
    """Run ``function`` with BLAS limited to :data:`BLAS_THREADS` threads."""

    @functools.wraps(function)
    def limited(*args: P.args, **kwargs: P.kwargs) -> R:
        if getattr(_state, "depth", 0):
            return function(*args, **kwargs)
        _state.depth = 1
        try:
            with threadpool_limits(limits=BLAS_THREADS, user_api="blas"):
                return function(*args, **kwargs)
        finally:
            _state.depth = 0

    return limited
