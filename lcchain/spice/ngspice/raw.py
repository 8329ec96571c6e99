"""ngspice's binary raw file, read with numpy (no copy of the data block)."""

from __future__ import annotations

import os
from pathlib import Path
from typing import TYPE_CHECKING

from ...core.errors import SimulationError
from ..text import canonical_vector_name

if TYPE_CHECKING:
    import numpy as np

__all__ = ["read_raw"]


#: The plots lcchain reads, by the start of their name in the raw file, and whether their data are complex.
PLOTS = {"transient": False, "ac": True}


def read_raw(source: str | os.PathLike[str] | bytes, plot: str = "transient", *, joined: bool = False
             ) -> dict[str, np.ndarray]:
    """Read the transient (or AC) plot of an ngspice binary raw file.

    Parameters
    ----------
    source : path-like or bytes
        Raw file written by ``ngspice -b -r``, or its content.
    plot : {"transient", "ac"}
        Which analysis: a transient's real columns, or an AC analysis's complex ones.

    Returns
    -------
    dict[str, numpy.ndarray]
        Normalised vector name (``"time"`` or ``"frequency"``, ``"i(l1)"``, ``"v(n3)"``) ->
        read-only float64 (transient) or complex128 (AC) column. When the file holds several plots, the
        last one of that analysis is returned; with ``joined``, every plot of that analysis one after the other
        (in the file's order), which must have the same vectors.

    Raises
    ------
    SimulationError
        Not a binary raw file, truncated, or without a plot of that analysis.
    """
    import numpy as np

    if plot not in PLOTS:
        raise SimulationError(f"lcchain reads transient and AC plots, not {plot!r}")
    complex_data = PLOTS[plot]
    data = source if isinstance(source, bytes) else Path(source).read_bytes()
    offset = 0
    chosen: dict[str, np.ndarray] | None = None
    plots: list[dict[str, np.ndarray]] = []
    while offset < len(data):
        header_end = data.find(b"Binary:\n", offset)
        if header_end < 0:
            if b"Values:" in data[offset:]:
                raise SimulationError("the raw file is ASCII; lcchain reads binary raw files only")
            raise SimulationError("the raw file has no 'Binary:' section")
        header = data[offset:header_end].decode("latin-1")
        plotname, flags, nvars, npoints, names = _parse_raw_header(header)
        is_complex = "complex" in flags
        wanted = plotname.lower().startswith(plot)
        if wanted and is_complex != complex_data:
            raise SimulationError(f"the raw plot {plotname!r} is {'complex' if is_complex else 'real'}; lcchain "
                                  f"reads {'complex' if complex_data else 'real'} data for a {plot} analysis")
        start = header_end + len(b"Binary:\n")
        width = 16 if is_complex else 8
        nbytes = nvars * npoints * width
        if start + nbytes > len(data):
            raise SimulationError(
                f"the raw file is truncated: {npoints} points x {nvars} variables announced, "
                f"{(len(data) - start) // width} values present"
            )
        dtype = np.complex128 if is_complex else np.float64
        block = np.frombuffer(data, dtype=dtype, count=nvars * npoints, offset=start).reshape(npoints, nvars)
        if wanted:
            chosen = {canonical_vector_name(name): block[:, i] for i, name in enumerate(names)}
            plots.append(chosen)
        offset = start + nbytes
    if chosen is None:
        raise SimulationError(f"the raw file holds no {plot} analysis")
    if not joined or len(plots) == 1:
        return chosen
    if any(set(columns) != set(chosen) for columns in plots):
        raise SimulationError(f"the raw file's {plot} plots do not hold the same vectors")
    out = {name: np.concatenate([columns[name] for columns in plots]) for name in chosen}
    for column in out.values():
        column.flags.writeable = False
    return out


def _parse_raw_header(header: str) -> tuple[str, str, int, int, list[str]]:
    fields: dict[str, str] = {}
    names: list[str] = []
    in_variables = False
    for line in header.splitlines():
        if in_variables and line[:1] in ("\t", " ") and line.strip():
            parts = line.split()
            names.append(parts[1])
            continue
        key, sep, value = line.partition(":")
        if sep:
            fields[key.strip().lower()] = value.strip()
            in_variables = key.strip().lower() == "variables"
    try:
        nvars = int(fields["no. variables"])
        npoints = int(fields["no. points"])
    except (KeyError, ValueError) as exc:
        raise SimulationError(f"unreadable raw file header ({exc})") from exc
    if len(names) != nvars:
        raise SimulationError(f"raw file header lists {len(names)} variables, announces {nvars}")
    return fields.get("plotname", ""), fields.get("flags", "").lower(), nvars, npoints, names
