"""``lcchain figures`` as a function: the paper's figures, recomputed, one file per figure named by its label."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

from ..report.files import check_output_folder

__all__ = ["FiguresRequest", "figures", "cache_dir"]


@dataclass(frozen=True)
class FiguresRequest:
    """The folder (created if missing), ``quick`` (coarser N grids), the figures' ``format``, ``cache`` whether
    rows of Tables I and II computed once are kept and reused, ``progress(done, total, label)``."""

    out: str
    quick: bool = False
    format: str = "png"
    cache: bool = True
    progress: Callable[[int, int, str], None] | None = None


def cache_dir(cache: bool) -> Path | None:
    """Where design rows are kept ($XDG_CACHE_HOME/lcchain, or ~/.cache/lcchain), or None: recompute them all."""
    from ..report.figure_data import default_cache_dir

    return default_cache_dir() if cache else None


def figures(request: FiguresRequest) -> list[Path]:
    """Every figure of the paper into ``request.out``; returns their paths."""
    from ..report.build import build_figures

    check_output_folder("--out", request.out)
    return build_figures(request.out, quick=request.quick, fmt=request.format, cache=cache_dir(request.cache),
                         progress=request.progress)
