"""An independent state-space solution of a circuit from its netlist cards (not lcchain's circuit code): the
nodal matrices parsed from the text, a series R folded into its coil's branch, then ``scipy.linalg.expm`` of the
state matrix or DOP853 at rtol 1e-12.  Every node must touch a capacitor (no capacitor ESL here)."""

from __future__ import annotations

import numpy as np
import scipy.integrate
import scipy.linalg

from helpers.tolerances import ATOL_DOP853_CARDS, RTOL_DOP853_CARDS
from lcchain.circuit.elements import Pulse


def state_space(cards: list[str]) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, list[str], int]:
    """(F, x0, b, c, coil names, node count) of x' = F x + b u(t) + c u'(t), from the element cards (independent
    of lcchain's circuit code): a pulse source's node is folded into its other node, its voltage entering its
    coil's branch (b) and, through a capacitor at that node, the other node's current (c)."""
    rows = [card.split() for card in cards]
    source = next((r for r in rows if r[0][0] in "BbVv"), None)
    rows = [r for r in rows if r is not source]
    through: list[tuple[str, float]] = []  # (node, C): a capacitor from the source's node injects C u' there
    if source is not None:  # fold the source's node s into its other node: v(s) = v(other) + u
        for r in rows:
            if r[0][0] in "Cc" and source[1] in r[1:3]:
                other = r[2] if r[1] == source[1] else r[1]
                through += [(other, float(r[3])), (source[2], -float(r[3]))]
        rows = [[r[0], source[2] if r[1] == source[1] else r[1], source[2] if r[2] == source[1] else r[2], *r[3:]]
                if source[1] in r[1:3] else r for r in rows]
    resistors = {r[0]: (r[1], r[2], float(r[3])) for r in rows if r[0][0] in "Rr"}
    nodes: list[str] = []
    for r in rows:
        if r[0][0] in "LlCcRr":
            nodes += [n for n in r[1:3] if n != "0" and n not in nodes]
    # a node met only by one coil and one resistor is folded away: that coil's branch carries the resistor
    series: dict[str, float] = {}
    folded: dict[str, str] = {}
    for ra, rb, value in resistors.values():
        for inner, outer in ((ra, rb), (rb, ra)):
            users = [r for r in rows if inner in r[1:3] and r[0][0] not in "Kk"]
            coils = [r for r in users if r[0][0] in "Ll"]
            if len(users) == 2 and len(coils) == 1:
                series[coils[0][0].lower()] = value
                folded[inner] = outer
    nodes = [n for n in nodes if n not in folded]
    index = {n: k for k, n in enumerate(nodes)}
    coils = [r for r in rows if r[0][0] in "Ll"]
    n, m = len(nodes), len(coils)
    Cn, G, A = np.zeros((n, n)), np.zeros((n, n)), np.zeros((n, m))
    Lm, R = np.zeros((m, m)), np.zeros((m, m))
    v0, i0 = np.zeros(n), np.zeros(m)
    for r in rows:
        if r[0][0] in "CcRr" and not (r[1] in folded or r[2] in folded):
            ia, ib, c = index.get(r[1]), index.get(r[2]), float(r[3])
            target, c = (Cn, c) if r[0][0] in "Cc" else (G, 1.0 / c)
            for p, sp in ((ia, 1), (ib, -1)):
                for q, sq in ((ia, 1), (ib, -1)):
                    if p is not None and q is not None:
                        target[p, q] += sp * sq * c
            if len(r) > 4:
                v0[index[r[1]]] = float(r[4].split("=")[1])
    for k, r in enumerate(coils):
        na, nb = folded.get(r[1], r[1]), folded.get(r[2], r[2])
        if na in index:
            A[index[na], k] += 1
        if nb in index:
            A[index[nb], k] -= 1
        Lm[k, k] = float(r[3])
        R[k, k] = series.get(r[0].lower(), 0.0)
        if len(r) > 4:
            i0[k] = float(r[4].split("=")[1])
    names = [r[0].lower() for r in coils]
    for r in rows:
        if r[0][0] in "Kk":
            k1, k2 = names.index(r[1].lower()), names.index(r[2].lower())
            Lm[k1, k2] = Lm[k2, k1] = float(r[3]) * np.sqrt(Lm[k1, k1] * Lm[k2, k2])
    # [Cn 0; 0 Lm] x' = [-G -A; A^T -R] x + [0; e_coil] u
    state = np.block([[-G, -A], [A.T, -R]])
    mass = scipy.linalg.block_diag(Cn, Lm)
    entry, slope = np.zeros(n + m), np.zeros(n + m)
    if source is not None:
        entry[n + next(k for k, r in enumerate(coils) if source[2] in r[1:3] and r[0] == "L1")] = 1.0
    for node, c in through:
        if node in index:
            slope[index[node]] += c
    return (np.linalg.solve(mass, state), np.concatenate((v0, i0)), np.linalg.solve(mass, entry),
            np.linalg.solve(mass, slope), names, n)


def expm_currents(cards: list[str], times: np.ndarray, probes: list[str]) -> np.ndarray:
    """Coil currents from the element cards, by the matrix exponential of the state matrix (independent)."""
    F, x0, _, _, names, n = state_space(cards)
    out = np.array([scipy.linalg.expm(F * t) @ x0 for t in times])
    return out[:, [n + names.index(p.lower()) for p in probes]].T


def dop853_currents(cards: list[str], pulse: Pulse, times: np.ndarray, probes: list[str]) -> np.ndarray:
    """Coil currents driven by ``pulse``, by DOP853 at rtol 1e-12 on the cards' own state equations."""
    F, x0, b, c, names, n = state_space(cards)
    end = pulse.corners()[-1]
    sigma, centre = pulse.width, 4.0 * pulse.width  # a gaussian: u' = -u (t - centre) / sigma^2

    def rate(t: float, x: np.ndarray) -> np.ndarray:
        if t >= end:
            return F @ x
        u = float(pulse.voltage(np.array(t)))
        return F @ x + b * u - c * u * (t - centre) / sigma ** 2

    # the gaussian starts at u(0) = exp(-8) of its peak: a step, which c u' turns into a jump of the state
    start = x0 + c * float(pulse.voltage(np.array(0.0)))
    solution = scipy.integrate.solve_ivp(rate, (0.0, float(times[-1])), start, method="DOP853", rtol=RTOL_DOP853_CARDS,
                                         atol=ATOL_DOP853_CARDS, t_eval=times, max_step=end / 50)
    return solution.y[[n + names.index(p.lower()) for p in probes], :]
