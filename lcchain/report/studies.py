"""The figure of a study, rebuilt from its store alone (no ngspice).

* a sweep over N: the paper's Fig. delta (δ* against N, theory as curves)
  with ngspice's measured first-arrival loss, 1 - peak, on top;
* tolerance samples: the histogram of the transmitted peaks.
"""

from __future__ import annotations

from collections import defaultdict
from typing import Any

from ..core.errors import ParameterError
from ..studies.store import Store
from .figures import delta_data, delta_figure, design_grid
from .plots import histogram

__all__ = ["study_figure"]


def study_figure(store: Store) -> Any:
    """The figure a study's results call for (see the module docstring)."""
    runs = [run for run in store.runs() if run.status == "ok" and run.metrics]
    if not runs:
        raise ParameterError("--plot", str(store.path), "a store with finished runs to draw")
    peaks = [run.metrics["arrivals"][0]["peak_sim"] for run in runs if run.metrics and run.metrics.get("arrivals")]
    if any("sample" in run.params for run in runs):
        return histogram(peaks, title=f"transmitted peak over {len(peaks)} samples ({store.path.name})")
    Ns = sorted({run.params["N"] for run in runs if "N" in run.params})
    if len(Ns) >= 2 and all("case" in run.params for run in runs):
        measured: dict[str, list[tuple[int, float]]] = defaultdict(list)
        for run in runs:
            arrivals = (run.metrics or {}).get("arrivals") or []
            if arrivals:
                measured[run.params["case"]].append((run.params["N"], 1.0 - arrivals[0]["peak_sim"]))
        grid = sorted(set(design_grid(max(Ns))) | set(Ns))
        return delta_figure(delta_data(grid), measured, title=f"δ* against N: theory and ngspice ({store.path.name})")
    raise ParameterError("--plot", str(store.path), "a sweep over two or more N (with --case), or tolerance samples")
