"""The LC ladder equivalent to a chain, as SPICE netlist text (pure).

Mapping (last section of the paper, Fig. LCcircuit): mass m_i -> inductor
L_i = m_i L0, spring K_{i,i+1} -> capacitor C_{i,i+1} = C0 / K_{i,i+1}; the
loop charges Q_i play the coordinates and the loop currents I_i the
velocities; the time unit is sqrt(L0 C0).

Topology: nodes n0..nN along the top rail, ground below.  L_i joins
n(i-1) to n(i); the spring between masses i and i+1 is a capacitor from n(i)
to ground, shared by loops i and i+1, and carries Q_i - Q_{i+1}.  A wall
spring is a capacitor from n0 (nN) to ground; a free end (K = 0, infinite
capacitance) closes its loop with a wire: n0 (nN) *is* the ground node.

Excitations:

* kick: an initial current I0 in L_1 (``IC=`` on the inductor);
* displacement: an initial charge Q0 in loop 1, i.e. the capacitor
  voltages it implies, V(n1) = Q0 / C_12 and V(n0) = -Q0 / C_01.

Netlist text is deterministic (same inputs, same bytes), every number is a
plain float at full precision (``repr(float(v))``: never a SPICE suffix, where
``m`` is milli and ``F`` femto, never a numpy repr), ``.save`` lists only the
requested probes, ``.tran`` always has an explicit maximum step, and every
option is written out.  Text a user supplies (the title) cannot add a line.
"""

from __future__ import annotations

import hashlib
import math
from dataclasses import dataclass

from .chain import Chain
from .errors import ParameterError
from .types import GAUSSIAN_CENTRE, EXCITATION_KINDS, METHODS, PROBES, PULSE_SHAPES, ExcitationKind, Method, Probes, PulseShape

__all__ = [
    "Ladder",
    "SimulationOptions",
    "netlist_text",
    "check_user_text",
    "probe_names",
    "number",
    "netlist_hash",
    "Probes",
]



def number(value: float) -> str:
    """A float as SPICE reads it exactly: ``repr(float(value))``, no suffix."""
    value = float(value)
    if not math.isfinite(value):
        raise ParameterError("value", value, "a finite number in a netlist")
    return repr(value)


def check_user_text(field_name: str, text: object, max_length: int = 200) -> str:
    """Validate text a user puts in a netlist (a title, a name).

    It must be one printable line that cannot be read as a command: no
    control characters (newline, carriage return, ...), no leading ``.``
    (a dot-command), no ``.control``/``.endc``, no leading ``shell``.

    Raises
    ------
    ParameterError
    """
    allowed = f"one printable line of at most {max_length} characters, not a SPICE command"
    if not isinstance(text, str):
        raise ParameterError(field_name, text, allowed)
    if len(text) > max_length or any(ord(ch) < 32 or ord(ch) == 127 for ch in text):
        raise ParameterError(field_name, text, allowed)
    lowered = text.strip().lower()
    if lowered.startswith(".") or lowered.startswith("shell") or ".control" in lowered or ".endc" in lowered:
        raise ParameterError(field_name, text, allowed)
    return text


@dataclass(frozen=True)
class Ladder:
    """A chain in physical units: the LC ladder's component values.

    Parameters
    ----------
    chain : Chain
        Masses and springs in bulk units.
    L0 : float
        Bulk inductance in henry (the bulk mass), > 0.
    C0 : float
        Bulk capacitance in farad (1 / bulk spring), > 0.
    """

    chain: Chain
    L0: float = 10e-6
    C0: float = 10e-9

    def __post_init__(self) -> None:
        for name in ("L0", "C0"):
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, (int, float)) or not (math.isfinite(value) and value > 0):
                raise ParameterError(name, value, f"a finite number > 0 ({'henry' if name == 'L0' else 'farad'})")
            object.__setattr__(self, name, float(value))

    @property
    def time_unit(self) -> float:
        """sqrt(L0 C0) in seconds: the circuit's unit of dimensionless time."""
        return math.sqrt(self.L0 * self.C0)

    @property
    def impedance(self) -> float:
        """sqrt(L0 / C0) in ohm: the bulk characteristic impedance."""
        return math.sqrt(self.L0 / self.C0)

    def inductances(self) -> list[float]:
        """L_i = m_i L0, henry."""
        return [float(m) * self.L0 for m in self.chain.masses]

    def capacitances(self) -> list[float | None]:
        """C_{i,i+1} = C0 / K_{i,i+1}, farad (index 0 and N are the walls); None = wire."""
        return [None if k == 0 else self.C0 / float(k) for k in self.chain.springs]

    def node(self, i: int) -> str:
        """Name of rail node i (0..N); a free end's node is ground."""
        N = self.chain.N
        if (i == 0 and self.chain.springs[0] == 0) or (i == N and self.chain.springs[N] == 0):
            return "0"
        return f"n{i}"


@dataclass(frozen=True)
class SimulationOptions:
    """Transient-analysis settings, all written out in the netlist.

    Parameters
    ----------
    dt : float
        Maximum (and print) step in units of sqrt(L0 C0), > 0.
    tstop : float
        Stop time in units of sqrt(L0 C0), > dt.
    method : {"trap", "gear"}
        Integration method (trapezoidal keeps energy; gear damps it).
    reltol : float
        ngspice's relative tolerance (it drives the step control).
    maxord : int
        Maximum order (2: trap is second order; higher changes nothing here).
    """

    dt: float
    tstop: float
    method: Method = "trap"
    reltol: float = 1e-3
    maxord: int = 2

    def __post_init__(self) -> None:
        for name in ("dt", "tstop", "reltol"):
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, (int, float)) or not (math.isfinite(value) and value > 0):
                raise ParameterError(name, value, "a finite number > 0")
            object.__setattr__(self, name, float(value))
        if self.dt > 1.0:
            raise ParameterError("dt", self.dt, "0 < dt <= 1 (in units of sqrt(L0*C0); the bulk period is 2 pi)")
        if self.tstop <= self.dt:
            raise ParameterError("tstop", self.tstop, f"a stop time > dt = {self.dt!r}")
        if self.method not in METHODS:
            raise ParameterError("method", self.method, " | ".join(METHODS))
        if self.maxord not in (1, 2, 3, 4, 5, 6):
            raise ParameterError("maxord", self.maxord, "an integer from 1 to 6")


def probe_names(N: int, probes: Probes = "ends") -> list[str]:
    """ngspice vectors saved for the probes: inductor currents ``i(l1)``..."""
    if probes not in PROBES:
        raise ParameterError("probes", probes, " | ".join(PROBES))
    loops = [1, N] if probes == "ends" else list(range(1, N + 1))
    return [f"i(l{i})" for i in loops]


def netlist_text(
    ladder: Ladder,
    options: SimulationOptions,
    *,
    excitation: ExcitationKind = "kick",
    I0: float = 1e-3,
    probes: Probes = "ends",
    title: str = "lcchain LC ladder",
    comments: tuple[str, ...] = (),
    Q: float | None = None,
    pulse: tuple[PulseShape, float] | None = None,
) -> str:
    """The SPICE netlist of the ladder and its transient analysis.

    Parameters
    ----------
    ladder : Ladder
        Chain and bulk values L0 (H), C0 (F).
    options : SimulationOptions
        Step, stop time (units of sqrt(L0 C0)) and integrator settings.
    excitation : {"kick", "displacement", "pulse"}
        Initial current I0 in L_1, initial charge Q0 = I0 sqrt(L0 C0) in
        loop 1, or (with ``pulse``) a voltage source in loop 1.
    I0 : float
        Scale of the excitation, ampere (> 0).
    probes : {"ends", "all"}
        Save the two end-loop currents, or every loop current.
    title : str
        First line of the netlist (validated by :func:`check_user_text`).
    comments : tuple of str
        Extra ``*`` comment lines after the title (validated likewise).
    Q : float, optional
        Losses: a resistor R_i = L_i / (Q sqrt(L0 C0)) in series with every
        inductor (every mode then decays at the same rate).  None: no resistor.
    pulse : (shape, width), optional
        With ``excitation="pulse"``: a voltage source in loop 1,
        v(t) = L_1 I0 g(t), g of unit area in units of sqrt(L0 C0):
        ``"gaussian"`` (standard deviation ``width``, centred at 4 width, a
        B-source) or ``"rect"`` (1/width on [0, width), a PWL source whose
        fall takes 1e-9 width).  None: no source.

    Returns
    -------
    str
        Deterministic text ending in ``.end`` and a newline.
    """
    if excitation not in EXCITATION_KINDS:
        raise ParameterError("excitation", excitation, " | ".join(EXCITATION_KINDS))
    if (excitation == "pulse") != (pulse is not None):
        raise ParameterError("pulse", pulse, "(shape, width) exactly when excitation is 'pulse'")
    if pulse is not None:
        shape, width = pulse
        if shape not in PULSE_SHAPES:
            raise ParameterError("pulse shape", shape, " | ".join(PULSE_SHAPES))
        if isinstance(width, bool) or not isinstance(width, (int, float)) or not (math.isfinite(width) and width > 0):
            raise ParameterError("pulse width", width, "a finite number > 0 (units of sqrt(L0*C0))")
    if Q is not None and (isinstance(Q, bool) or not isinstance(Q, (int, float)) or not (math.isfinite(Q) and Q > 0)):
        raise ParameterError("Q", Q, "a finite quality factor > 0")
    if isinstance(I0, bool) or not isinstance(I0, (int, float)) or not (math.isfinite(I0) and I0 > 0):
        raise ParameterError("I0", I0, "a finite current > 0 (ampere)")
    title = check_user_text("title", title)
    for line in comments:
        check_user_text("comment", line, max_length=400)
    chain = ladder.chain
    N = chain.N
    unit = ladder.time_unit
    L = ladder.inductances()
    C = ladder.capacitances()
    Q0 = I0 * unit

    lines = [title]
    lines += [f"* {line}" for line in comments]
    lines.append(
        f"* N={N} L0={number(ladder.L0)} H C0={number(ladder.C0)} F time unit={number(unit)} s "
        f"excitation={excitation} I0={number(I0)} A"
    )
    for i in range(1, N + 1):
        ic = f" IC={number(I0)}" if (excitation == "kick" and i == 1) else ""
        left, right = ladder.node(i - 1), ladder.node(i)
        if i == 1 and pulse is not None:
            left = "s1"  # the source sits between the rail node n0 (or ground) and L1
        if Q is not None:
            lines.append(f"L{i} {left} m{i} {number(L[i - 1])}{ic}")
            lines.append(f"R{i} m{i} {right} {number(L[i - 1] / (Q * unit))}")
        else:
            lines.append(f"L{i} {left} {right} {number(L[i - 1])}{ic}")
        if i < N:
            ic = f" IC={number(Q0 / C[i])}" if (excitation == "displacement" and i == 1) else ""
            lines.append(f"C{i}_{i + 1} n{i} 0 {number(C[i])}{ic}")
    for wall in (0, N):
        if C[wall] is not None:
            ic = f" IC={number(-Q0 / C[0])}" if (excitation == "displacement" and wall == 0) else ""
            lines.append(f"C{wall}_{wall + 1} {ladder.node(wall)} 0 {number(C[wall])}{ic}")
    if pulse is not None:
        shape, width = pulse
        area = L[0] * I0  # volt-seconds: the source gives L_1 the current I0
        if shape == "gaussian":
            sigma, centre = width * unit, GAUSSIAN_CENTRE * width * unit
            peak = area / (sigma * math.sqrt(2 * math.pi))
            lines.append(f"B1 s1 {ladder.node(0)} V={number(peak)}*exp(-0.5*((time-{number(centre)})/{number(sigma)})^2)")
        else:
            duration = width * unit
            level = area / duration
            lines.append(f"V1 s1 {ladder.node(0)} PWL(0 {number(level)} {number(duration)} {number(level)} "
                         f"{number(duration * (1 + 1e-9))} 0)")
    # Tolerances scaled to the circuit's own current, voltage and charge, so
    # that results do not depend on the unit scale (nH/pF/uA as 1 H/1 F/1 A).
    V0 = I0 * ladder.impedance
    lines.append(
        f".options method={options.method} maxord={options.maxord} reltol={number(options.reltol)} "
        f"abstol={number(1e-12 * I0)} vntol={number(1e-12 * V0)} chgtol={number(1e-15 * Q0)} trtol=7.0"
    )
    step = options.dt * unit
    lines.append(f".tran {number(step)} {number(options.tstop * unit)} 0 {number(step)} uic")
    lines.append(".save " + " ".join(probe_names(N, probes)))
    lines.append(".end")
    return "\n".join(lines) + "\n"


def netlist_hash(text: str) -> str:
    """SHA-256 of the netlist text (UTF-8), as recorded with every run."""
    return hashlib.sha256(text.encode("utf-8")).hexdigest()
