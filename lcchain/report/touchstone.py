"""Touchstone v1 text of a two-port (``.s2p``): what circuit tools (scikit-rf, a VNA's software) read.

The option line ``# Hz S RI R <z0>``: frequencies in hertz, S-parameters as real and imaginary parts, in the
reference impedance z0 (ohms).  A two-port's data lines hold, per frequency, S11 S21 S12 S22 (Touchstone's
order for two-ports, not the row order of the matrix).  Numbers are written with full precision (``%.17g``).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

__all__ = ["touchstone_text"]


def touchstone_text(frequency: np.ndarray, S: np.ndarray, z0: float, comments: Sequence[str] = ()) -> str:
    """Touchstone v1 text of a two-port.

    Parameters
    ----------
    frequency : ndarray, shape (points,)
        Hz, ascending.
    S : ndarray of complex, shape (points, 2, 2)
        Scattering matrix in ``z0``.
    z0 : float
        Reference impedance of both ports, ohms.
    comments : sequence of str
        Lines written as ``!`` comments first (what the ports are, what made the file).
    """
    frequency = np.asarray(frequency, dtype=float)
    S = np.asarray(S, dtype=complex)
    if S.shape != (frequency.size, 2, 2):
        raise ValueError(f"S has shape {S.shape}: expected ({frequency.size}, 2, 2), one matrix per frequency")
    lines = [f"! {line}" for text in comments for line in str(text).splitlines()]
    lines.append(f"# Hz S RI R {float(z0):.17g}")
    for f, matrix in zip(frequency, S, strict=True):
        entries = (matrix[0, 0], matrix[1, 0], matrix[0, 1], matrix[1, 1])  # S11 S21 S12 S22
        lines.append(" ".join([f"{f:.17g}"] + [f"{v.real:.17g} {v.imag:.17g}" for v in entries]))
    return "\n".join(lines) + "\n"
