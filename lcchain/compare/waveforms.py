"""ngspice's loop currents made dimensionless: the signals compared with theory (pure).

Time is in units of sqrt(L0 C0); a kick's or a pulse's signals are loop
currents over I0 (velocities), a displacement's are loop charges over
Q0 = I0 sqrt(L0 C0) (positions), the charges being the time integrals of the
currents by the trapezoidal rule on the simulator's own points (the rule the
trapezoidal integrator applies to its capacitor charges), plus Q0 in loop 1.
With ``uic`` ngspice's first point is after t = 0; the currents there are 0
for a displacement, which the integral uses.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import scipy  # its submodules load on first use: commands that need no theory never import them
from numpy.typing import ArrayLike

from ..core.checks import choice
from ..core.frozen import FrozenArrays, readonly
from ..core.types import EXCITATION_KINDS, EXCITATIONS, Excitation, ExcitationKind

__all__ = ["Waveforms", "Signals", "normalise", "loop_signals"]


@dataclass(frozen=True, eq=False)
class Waveforms(FrozenArrays):
    """Dimensionless end-loop signals at the simulator's time points.

    Attributes
    ----------
    t : ndarray
        Time in units of sqrt(L0 C0).
    first, last : ndarray
        Loop 1 and loop N: I/I_1(0) (kick) or Q/Q_1(0) (displacement).
    excitation : str
    """

    t: np.ndarray
    first: np.ndarray
    last: np.ndarray
    excitation: str

    def to_csv(self) -> str:
        """CSV text with columns t, first, last (full precision)."""
        rows = ["t,first,last"]
        rows += [f"{a!r},{b!r},{c!r}" for a, b, c in zip(self.t.tolist(), self.first.tolist(), self.last.tolist(),
                                                          strict=True)]
        return "\n".join(rows) + "\n"


@dataclass(frozen=True, eq=False)
class Signals(FrozenArrays):
    """Every saved loop's dimensionless signal, and the theory at the same times.

    Attributes
    ----------
    t : ndarray, shape (J,)
        Time in units of sqrt(L0 C0).
    sim : ndarray, shape (R, J)
        Simulated signals, one row per saved loop (first row loop 1, last row loop N).
    theory : ndarray, shape (R, J)
        The exact theory of the same loops at the same times.
    excitation : str
        ``"kick"``, ``"displacement"`` or ``"pulse"``.
    """

    t: np.ndarray
    sim: np.ndarray
    theory: np.ndarray
    excitation: str

    def waveforms(self) -> Waveforms:
        """Loops 1 and N as :class:`Waveforms` (a pulse's signals are velocities, as a kick's)."""
        kind = "displacement" if self.excitation == "displacement" else "kick"
        return Waveforms(self.t, self.sim[0], self.sim[-1], kind)


def _charges(t: np.ndarray, currents: np.ndarray) -> np.ndarray:
    """Time integral of each row from t = 0 (where the currents are 0), at every t."""
    tt = np.concatenate(([0.0], t))
    rows = np.atleast_2d(currents)
    padded = np.concatenate((np.zeros((rows.shape[0], 1)), rows), axis=1)
    return np.asarray(scipy.integrate.cumulative_trapezoid(padded, tt, axis=1))


def loop_signals(time_s: np.ndarray, currents: Sequence[np.ndarray] | np.ndarray, *, time_unit: float,
                 excitation: ExcitationKind, I0: float) -> tuple[np.ndarray, np.ndarray]:
    """Dimensionless time and loop signals from ngspice's loop currents.

    Parameters
    ----------
    time_s : array_like, shape (J,)
        Simulator time points, seconds.
    currents : array_like, shape (R, J)
        Loop currents in ampere, loop 1 first.
    time_unit : float
        sqrt(L0 C0), seconds.
    excitation : {"kick", "displacement", "pulse"}
    I0 : float
        Kick current (A); a displacement's charge is Q0 = I0 * time_unit.

    Returns
    -------
    t : ndarray, shape (J,)
    signals : ndarray, shape (R, J)
        I/I0 for a kick or a pulse; Q/Q0 for a displacement (loop 1 starts at 1).
    """
    choice("excitation", excitation, EXCITATION_KINDS)
    t = np.asarray(time_s, dtype=float) / time_unit
    rows = np.atleast_2d(np.asarray(currents, dtype=float)) / I0
    if excitation == "displacement":
        # Q/Q0 = (1/Q0) int I dt = int (I/I0) d(t/time_unit), since Q0 = I0 * time_unit.
        rows = _charges(t, rows)
        rows[0] += 1.0
    return t, rows


def normalise(time_s: ArrayLike, i_first: ArrayLike, i_last: ArrayLike, *, time_unit: float, excitation: Excitation,
              I0: float) -> Waveforms:
    """Turn ngspice's end-loop currents into the compared dimensionless signals.

    Parameters
    ----------
    time_s : array_like
        Simulator time points, seconds.
    i_first, i_last : array_like
        Currents of L_1 and L_N, ampere.
    time_unit : float
        sqrt(L0 C0), seconds.
    excitation : {"kick", "displacement"}
    I0 : float
        Kick current (A); a displacement's charge is Q0 = I0 * time_unit.
    """
    choice("excitation", excitation, EXCITATIONS)
    t, rows = loop_signals(np.asarray(time_s, dtype=float), np.vstack([i_first, i_last]), time_unit=time_unit,
                           excitation=excitation, I0=I0)
    return Waveforms(readonly(t), readonly(rows[0]), readonly(rows[1]), excitation)
