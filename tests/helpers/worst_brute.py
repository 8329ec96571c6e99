"""A brute force over every corner of a small chain's tolerance box, independent of lcchain (issue 32, item 4):
the worst case search is checked against it (tests/test_worst_case_search.py) and measured beside it
(benchmarks/bench_worst_case.py)."""

from __future__ import annotations

import itertools

import numpy as np


def brute_force(masses: np.ndarray, springs: np.ndarray, tol: float, metric: str,
                chunk: int = 16384, grid: int = 200) -> tuple[np.ndarray, np.ndarray]:
    """The metric at every corner of a free chain's 2N - 1 parts (N masses, N - 1 inner springs).

    Masses m_i (1 +- tol); springs K_j / (1 +- tol) (a capacitor C = C0 / K at 1 +- tol).  The velocity of mass N
    after a unit kick of mass 1 is v_N(t) = sum_n w_n cos(omega_n t), w_n = U_Nn U_1n sqrt(m_1 / m_N) with U the
    eigenvectors of M^-1/2 K M^-1/2; the first arrival is its largest value in [T/2, 3T/2], T = pi / (median of
    the first five frequency spacings) (Sec. II.C: the transit time of the perfect chains), found on a grid and
    polished by Newton steps on v_N'(t) = 0.
    """
    N = masses.size
    signs = np.array(list(itertools.product((-1.0, 1.0), repeat=2 * N - 1)))
    out = np.empty(len(signs))
    idx = np.arange(N - 1)
    for a in range(0, len(signs), chunk):
        s = signs[a:a + chunk]
        m = masses * (1.0 + tol * s[:, :N])
        k = springs[1:-1] / (1.0 + tol * s[:, N:])
        K = np.zeros((len(s), N, N))
        K[:, idx, idx] += k
        K[:, idx + 1, idx + 1] += k
        K[:, idx, idx + 1] -= k
        K[:, idx + 1, idx] -= k
        r = 1.0 / np.sqrt(m)
        lam, U = np.linalg.eigh(K * r[:, :, None] * r[:, None, :])
        omega = np.sqrt(np.clip(lam, 0.0, None))
        w = U[:, -1, :] * U[:, 0, :] * (r[:, -1] / r[:, 0])[:, None]
        T = np.pi / np.median(np.diff(omega[:, :6], axis=1), axis=1)
        lo, hi = T / 2.0, 1.5 * T
        h = (hi - lo) / (grid - 1)
        phase, turn = np.exp(1j * omega * lo[:, None]), np.exp(1j * omega * h[:, None])
        best, at = np.full(len(s), -np.inf), np.zeros(len(s))
        for g in range(grid):  # the grid by rotation of the phases: no cosine per point
            v = np.einsum("bn,bn->b", w, phase.real)
            better = v > best
            best, at = np.where(better, v, best), np.where(better, lo + g * h, at)
            phase *= turn
        t = at
        for _ in range(8):
            slope = -np.sum(w * omega * np.sin(omega * t[:, None]), axis=1)
            curvature = -np.sum(w * omega**2 * np.cos(omega * t[:, None]), axis=1)
            step = np.where(curvature < 0, -slope / np.where(curvature < 0, curvature, 1.0), 0.0)
            t = np.clip(t + np.clip(step, -h, h), lo, hi)
        p = np.maximum(np.sum(w * np.cos(omega * t[:, None]), axis=1), best)
        out[a:a + chunk] = p if metric == "peak" else p**2 * m[:, -1] / m[:, 0]
    return out, signs
