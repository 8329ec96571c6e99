"""Theory computed under a fixed BLAS thread limit: the same bits in any process.

OpenBLAS splits a matrix product over its threads, and the order of the
additions follows the split: with one and two threads the modal sums of an
N = 400 chain differ in 16,099 of 40,002 values (by up to 1e-16).  A study
computes theory in a parent, in pool workers and on Dask workers, and its
results must be bit-identical whichever ran them, so every public theory
entry point runs under ``threadpoolctl``'s limit of one BLAS thread.  One
thread is also faster here: the work is many small products, where threads
cost more than they give (N = 20000 two-mass design: 4.0 s against 17.4 s on
this 2-core machine under load).

Only the outermost call sets the limit; nested decorated calls see that it
is in force and run straight through.  Finding the BLAS libraries (threadpoolctl
reads /proc/self/maps and opens each one) cost 1-2 ms, once per Monte Carlo
sample, so the controller that found them is kept and found again only when
the process has loaded or unloaded a shared object since (glibc's counters
``dlpi_adds`` and ``dlpi_subs``): setting the limit with it costs about 0.02 ms.
Where those counters cannot be read, the libraries are found at every
outermost call, as before.

The limit holds only for libraries loaded when it is set.  scipy ships an
OpenBLAS of its own, loaded with ``scipy.linalg``; theory imports scipy's
submodules on first use, so the first theory call of a process used to load
it inside the limit, where it ran with its default threads: with numpy 2.4 and
scipy 1.17 (OpenBLAS 0.3.30 and 0.3.31) the first N = 400 modes then differed
between a process started with one BLAS thread and one with two.  So
``scipy.linalg`` is loaded before the first limit is set.
"""

from __future__ import annotations

import functools
import threading
from collections.abc import Callable
from typing import TYPE_CHECKING, ParamSpec, Protocol, TypeVar

if TYPE_CHECKING:  # imported by the first limit: a command's --help sets none
    from threadpoolctl import ThreadpoolController

__all__ = ["BLAS_THREADS", "fixed_blas_threads"]

#: Threads every theory computation gives BLAS.
BLAS_THREADS = 1

P = ParamSpec("P")
R = TypeVar("R")

_state = threading.local()


class _Counters(Protocol):
    adds: int
    subs: int


class _Pointer(Protocol):
    """A ctypes pointer to :class:`_Objects`' ``ObjectInfo``, as the visitor reads it."""

    @property
    def contents(self) -> _Counters: ...


class _Objects:
    """glibc's ``dl_iterate_phdr`` and the ctypes types that read its counters, made the first time a limit is set
    (ctypes and ``dlopen(NULL)`` cost a command's start 2 ms: most commands set no limit)."""

    def __init__(self) -> None:
        import ctypes

        class ObjectInfo(ctypes.Structure):
            """The head of glibc's ``struct dl_phdr_info`` (<link.h>)."""

            _fields_ = [("addr", ctypes.c_void_p), ("name", ctypes.c_char_p), ("phdr", ctypes.c_void_p),
                        ("phnum", ctypes.c_uint16), ("adds", ctypes.c_ulonglong), ("subs", ctypes.c_ulonglong)]

        self.size = ctypes.sizeof(ObjectInfo)
        self.visit_type = ctypes.CFUNCTYPE(ctypes.c_int, ctypes.POINTER(ObjectInfo), ctypes.c_size_t,
                                           ctypes.c_void_p)
        try:
            self.iterate: Callable[..., int] | None = ctypes.CDLL(None).dl_iterate_phdr
        except (OSError, AttributeError, TypeError):  # no such function (macOS, Windows)
            self.iterate = None

    def counters(self) -> tuple[int, int] | None:
        """How many shared objects the process has loaded and unloaded so far, or None where unknown."""
        if self.iterate is None:
            return None
        found: list[tuple[int, int]] = []

        def visit(info: _Pointer, size: int, _: object) -> int:
            if size >= self.size:
                found.append((info.contents.adds, info.contents.subs))
            return 1  # every object carries the same counters: the first is enough

        self.iterate(self.visit_type(visit), None)
        return found[0] if found else None


@functools.cache
def _objects() -> _Objects:
    return _Objects()


def _loaded_objects() -> tuple[int, int] | None:
    """How many shared objects the process has loaded and unloaded so far, or None where unknown."""
    return _objects().counters()


_controller: tuple[tuple[int, int], ThreadpoolController] | None = None


def _blas_controller() -> ThreadpoolController:
    """threadpoolctl's controller of the loaded libraries, kept while no shared object comes or goes."""
    from threadpoolctl import ThreadpoolController

    global _controller
    loaded = _loaded_objects()
    if loaded is not None and _controller is not None and _controller[0] == loaded:
        return _controller[1]
    controller = ThreadpoolController()
    _controller = None if loaded is None else (loaded, controller)
    return controller


def load_blas() -> None:
    """Load every BLAS library the theory calls (scipy's own OpenBLAS comes with ``scipy.linalg``) before a
    limit is set, so that none is loaded inside it with its default threads."""
    import scipy.linalg  # noqa: F401  (loaded once; later imports are a dictionary look-up)


def fixed_blas_threads(function: Callable[P, R]) -> Callable[P, R]:
    """Run ``function`` with BLAS limited to :data:`BLAS_THREADS` threads."""

    @functools.wraps(function)
    def limited(*args: P.args, **kwargs: P.kwargs) -> R:
        if getattr(_state, "depth", 0):
            return function(*args, **kwargs)
        load_blas()
        _state.depth = 1
        try:
            with _blas_controller().limit(limits=BLAS_THREADS, user_api="blas"):
                return function(*args, **kwargs)
        finally:
            _state.depth = 0

    return limited
