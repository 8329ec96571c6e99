"""The kicked uniform ladder between walls in closed form, with every effect but one at a time (independent of
lcchain's circuit code).

Masses 1, springs 1, walls of spring 1 (``chain_for_case("uniform-bounded", N)``): every matrix of the loop
(mesh) equations of its ladder is a polynomial in the Dirichlet Laplacian T = tridiag(-1, 2, -1), so the sine
vectors S_jn = sqrt(2/(N+1)) sin(pi n j/(N+1)) diagonalise all of them, with eigenvalue c_n = 2 - 2 cos(theta_n),
theta_n = pi n/(N+1), of T.  In bulk units (time sqrt(L0 C0), impedance sqrt(L0/C0)), each mode obeys

    mu_n a'' + rho_n a' + kappa_n a = 0,    a(0) = 0,  mu_n a'(0) = (1 + k (2 - c_n)) S_1n,

the kick: I0 in coil 1 alone, its flux (and coil 2's, k I0, when coupled) conserved where a capacitor's ESL must
take up the current at once,

* coupling k (mutual k between neighbouring coils): the loop inductance 1 - k (T - 2): mu_n += k (2 - c_n);
* capacitor ESL L (in series with every capacitor, walls too): mu_n += L c_n;
* losses Q (R_i = L_i/Q): rho_n += 1/Q;  coil resistance R: rho_n += R;  capacitor ESR R: rho_n += R c_n;
* coil capacitance r (r C0 across every coil; nodal picture: the coils' currents obey
  i'' = -T (1 + r T)^-1 i): kappa_n = c_n / (1 + r c_n), lossless only here.

Loop j's current (coil j's) is sum_n S_jn a_n'(t) I0 with
a'(t) = a'(0) exp(-g t) [cos(W t) - g sin(W t)/W], g = rho/(2 mu), W^2 = kappa/mu - g^2; overdamped (W = j q),
exp(-g t) sinh(q t)/q is written with expm1, which stays exact through critical damping (q -> 0) and never
overflows.
"""

from __future__ import annotations

import numpy as np


def uniform_currents(N: int, t: np.ndarray, loops: list[int], *, coupling: float = 0.0, esl: float = 0.0,
                     Q: float | None = None, coil_resistance: float = 0.0, esr: float = 0.0,
                     coil_capacitance: float = 0.0) -> np.ndarray:
    """Currents of ``loops`` (from 1) over I0, at bulk times ``t``, of the kicked uniform ladder between walls."""
    n = np.arange(1, N + 1)
    theta = np.pi * n / (N + 1)
    c = 2.0 - 2.0 * np.cos(theta)
    S = np.sqrt(2.0 / (N + 1)) * np.sin(np.outer(np.arange(1, N + 1), theta))
    mu = 1.0 + coupling * (2.0 - c) + esl * c
    rho = (1.0 / Q if Q else 0.0) + coil_resistance + esr * c
    kappa = c / (1.0 + coil_capacitance * c)
    g = rho / (2.0 * mu)
    W2 = kappa / mu - g * g
    a0 = S[0] * (1.0 + coupling * (2.0 - c)) / mu
    velocity = np.empty((N, t.size))
    for n_, (g_, w2) in enumerate(zip(g, W2, strict=True)):
        if w2 > 0:  # underdamped: exp(-g t) (cos W t - g sin(W t)/W)
            W = np.sqrt(w2)
            velocity[n_] = np.exp(-g_ * t) * (np.cos(W * t) - g_ * np.sin(W * t) / W)
        else:  # overdamped, q = sqrt(g^2 - W^2) <= g: exp(-g t) (cosh q t - g sinh(q t)/q), no overflow
            q = np.sqrt(-w2)
            slow = np.exp((q - g_) * t)
            # sinh(q t)/q exp(-g t) = slow (1 - exp(-2 q t))/(2 q), and t slow at q = 0
            sinh = slow * t if q == 0 else slow * -np.expm1(-2.0 * q * t) / (2.0 * q)
            velocity[n_] = 0.5 * (slow + np.exp(-(q + g_) * t)) - g_ * sinh
    return np.asarray(S[np.asarray(loops) - 1] @ (a0[:, None] * velocity))
