"""ngspice's binary raw file, read with numpy (no copy of the data block)."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from ..core.errors import SimulationError
from .text import canonical_vector_name

__all__ = ["read_raw"]


def read_raw(source: str | os.PathLike[str] | bytes) -> dict[str, np.ndarray]:
    """Read the transient plot of an ngspice binary raw file.

    Parameters
    ----------
    source : path-like or bytes
        Raw file written by ``ngspice -b -r``, or its content.

    Returns
    -------
    dict[str, numpy.ndarray]
        Normalised vector name (``"time"``, ``"i(l1)"``, ``"v(n3)"``) ->
        read-only float64 column. When the file holds several plots, the
        last transient one is returned.

    Raises
    ------
    SimulationError
        Not a binary real raw file, truncated, or without a transient plot.
    """
    data = source if isinstance(source, bytes) else Path(source).read_bytes()
    offset = 0
    chosen: dict[str, np.ndarray] | None = None
    while offset < len(data):
        header_end = data.find(b"Binary:\n", offset)
        if header_end < 0:
            if b"Values:" in data[offset:]:
                raise SimulationError("the raw file is ASCII; lcchain reads binary raw files only")
            raise SimulationError("the raw file has no 'Binary:' section")
        header = data[offset:header_end].decode("latin-1")
        plotname, flags, nvars, npoints, names = _parse_raw_header(header)
        if "complex" in flags:
            raise SimulationError(f"the raw plot {plotname!r} is complex; lcchain reads real data only")
        start = header_end + len(b"Binary:\n")
        nbytes = nvars * npoints * 8
        if start + nbytes > len(data):
            raise SimulationError(
                f"the raw file is truncated: {npoints} points x {nvars} variables announced, "
                f"{(len(data) - start) // 8} values present"
            )
        block = np.frombuffer(data, dtype=np.float64, count=nvars * npoints, offset=start).reshape(npoints, nvars)
        if plotname.lower().startswith("transient"):
            chosen = {canonical_vector_name(name): block[:, i] for i, name in enumerate(names)}
        offset = start + nbytes
    if chosen is None:
        raise SimulationError("the raw file holds no transient analysis")
    return chosen


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
