"""The paper's algebra checked symbolically (issue 32, item 6).

Sec. II.C's N = 3 and N = 4 secular equations and solutions, Sec. III's u_k (Eqs. e.uk1 -> e.uk, e.z0,
e.tudef), App. A (N = 5), App. C (Eqs. e.tukz0, e.tu2, e.Pk1, e.wr), Sec. IV's psi_k' (Eq. e.psiprime and its
expansion), Sec. V.A's expansions of R_k and I_k.  Every difference printed must be 0.  Needs sympy, which is
not a dependency of lcchain (``pip install sympy``); see benchmarks/paper_reading.md.

    python benchmarks/paper_algebra.py
"""

import sympy as sp

mu, w, r, x, y, z, t, E = sp.symbols("mu w r x y z t E")
k, q, D = sp.symbols("k q Delta", positive=True)


def show(label: str, value: object) -> None:
    print(f"{label:40s} {value}")


# Sec. II.C, N = 3 (Eq. e.N3): det(mu - B) = mu (mu - x^2)(mu - 2 - x^2)
B3 = sp.Matrix([[x**2, -x, 0], [-x, 2, -x], [0, -x, x**2]])
show("N = 3 secular equation", sp.factor((mu * sp.eye(3) - B3).det()))
# Sec. II.C, N = 4 (Eq. e.N4): both lines of the secular equation, the linear system and its solution
B4 = sp.Matrix([[w, -x, 0, 0], [-x, 2, -y**2, 0], [0, -y**2, 2, -x], [0, 0, -x, w]])
det4 = sp.expand((mu * sp.eye(4) - B4).det())
first = sp.expand(((mu - w) * (mu - 2) - x**2) ** 2 - (mu - w) ** 2 * y**4)
show("N = 4 first line - det", sp.simplify(det4 - first))
second = mu * (mu - (w + r)) * (mu**2 - mu * (w + 4 - r) + 2 * w * (2 - r))
show("N = 4 second line - det", sp.simplify(sp.expand(det4.subs({y: sp.sqrt(2 - r), x: sp.sqrt(w * r)}) - second)))
a = sp.symbols("a", positive=True)  # mu_2; mu_n = (n - 1)^2 a
roots = sp.solve([sp.Eq(w + 4 - r, 10 * a), sp.Eq(2 * w * (2 - r), 9 * a**2), sp.Eq(w + r, 4 * a)], [w, r, a],
                 dict=True)
show("N = 4 from mu_n = (n-1)^2 mu_2", roots)
r4, w4 = roots[0][r], roots[0][w]
show("N = 4 m1, m2, K12", (r4**2 / (w4 * r4 * (2 - r4)), 1 / (2 - r4), r4 / (2 - r4)))
show("N = 4 x, spacing, t_4", (sp.sqrt(w4 * r4), sp.sqrt(w4 + r4) / 2, sp.N(2 * sp.pi / sp.sqrt(w4 + r4))))
# Sec. III.A: e.uk1 written out is e.uk (E = e^{-ik}, lambda = 2 cos k = 1/E + E)
lam = 1 / E + E
uk1 = E**2 * ((lam**2 - z * lam - x**2) - (lam - z) * y**2 * E)
uk = 1 - z * E + (2 - x**2 - y**2) * E**2 - z * (1 - y**2) * E**3 + (1 - y**2) * E**4
show("e.uk1 - e.uk", sp.simplify(sp.expand(uk1 - uk)))
# Sec. III.B: u_0 = 0 at z0 (e.z0), and u_k = (1 - E) tu_k (e.tudef) there
z0, w0 = 2 - x**2 / (2 - y**2), x**2 / (2 - y**2)
tu = 1 - (1 - w0) * E - (1 - w0) * (y**2 - 1) * E**2 + (y**2 - 1) * E**3
show("u at k = 0, z = z0", sp.simplify(uk.subs({z: z0, E: 1})))
show("u_k - (1 - E) tu_k at z0", sp.simplify(sp.expand(uk.subs(z, z0) - (1 - E) * tu)))
# App. A: the 5-mass matrix is Eq. e.BN's, det = P Q, and the perfect chain of Eq. e.N5
m1, m2, K = sp.symbols("m1 m2 K12", positive=True)
masses, springs = [m1, m2, 1, m2, m1], [K, 1, 1, K]
Kmat = sp.zeros(5)
for i, spring in enumerate(springs):
    Kmat[i, i] += spring
    Kmat[i + 1, i + 1] += spring
    Kmat[i, i + 1] -= spring
    Kmat[i + 1, i] -= spring
B5 = sp.Matrix(5, 5, lambda i, j: Kmat[i, j] / sp.sqrt(masses[i] * masses[j]))
perfect = {m1: sp.Rational(35, 18), m2: sp.Rational(10, 9), K: sp.Rational(7, 9)}
show("N = 5, Eq. e.N5: 5 mu_n", sorted(5 * e for e in B5.subs(perfect).eigenvals()))
values = {w: K / m1, t: (1 + K) / m2, x: K / sp.sqrt(m1 * m2), y: 1 / sp.sqrt(m2)}
Bapp = sp.Matrix([[w, -x, 0, 0, 0], [-x, t, -y, 0, 0], [0, -y, 2, -y, 0], [0, 0, -y, t, -x], [0, 0, 0, -x, w]])
show("App. A matrix - e.BN", sp.simplify(Bapp.subs(values) - B5) == sp.zeros(5))
P = (mu - w) * (mu - t) - x**2
Q = (mu - 2) * ((mu - w) * (mu - t) - x**2) - 2 * (mu - w) * y**2
show("App. A det - P Q", sp.simplify(sp.expand((mu * sp.eye(5) - Bapp).det() - P * Q)))
rA = t - y**2
show("App. A P - its second line", sp.simplify(sp.expand(P - (mu**2 - (w + t) * mu + w * y**2)).subs(x**2, w * rA)))
show("App. A Q - its second line", sp.simplify(
    sp.expand(Q - mu * (mu**2 - (w + t + 2) * mu + w * y**2 + 2 * (w + rA))).subs(x**2, w * rA)))
show("App. A w, t, x^2, y^2, r", [sp.nsimplify(v.subs(perfect)) for v in (K / m1, (1 + K) / m2, K**2 / (m1 * m2),
                                                                          1 / m2, (1 + K) / m2 - 1 / m2)])
# App. C: Eq. e.tukz0 and Eq. e.tu2 (k = 2q)
tuq = 1 - (1 - w) * sp.exp(-2 * sp.I * q) - (1 - w) * (1 - r) * sp.exp(-4 * sp.I * q) \
    + (1 - r) * sp.exp(-6 * sp.I * q)
re_, im_ = (2 - r) * (w - 4 * sp.sin(q) ** 2) * sp.cos(q), r * (2 - w - 4 * sp.cos(q) ** 2) * sp.sin(q)
show("e.tukz0", sp.simplify(sp.expand((sp.exp(3 * sp.I * q) * tuq - re_ + sp.I * im_).rewrite(sp.exp))))
den = (2 - r) ** 2 * w**2 + r**2 * (2 - w) ** 2 * sp.tan(q) ** 2 \
    - 32 * (1 - r) * (w - 2 * sp.sin(q) ** 2) * sp.sin(q) ** 2
show("e.tu2", sp.simplify(sp.expand(re_**2 + im_**2 - den * sp.cos(q) ** 2)))
# Sec. V.A: Eq. e.wr solves Eq. e.quarticP (both forms), its series, and Eq. e.Pk1's denominator
w_r = 2 / r**2 * (1 - sp.sqrt(1 - r)) ** 4
show("e.quarticP at e.wr", sp.simplify(sp.expand(r**2 * (2 - w_r) ** 2 - 32 * (1 - r) * w_r)))
show("e.wr first - second form", sp.simplify(2 * ((1 - sp.sqrt(1 - r)) / (1 + sp.sqrt(1 - r))) ** 2 - w_r))
show("e.wr series", sp.series(w_r, r, 0, 4))
den1 = (2 - r) ** 2 * w**2 + 32 * (1 - r) * (w * sp.tan(q) ** 2 + 2 * sp.sin(q) ** 2) * sp.sin(q) ** 2
show("e.Pk1 den - e.Pk den - quartic tan^2", sp.simplify(
    sp.expand(den - den1) - sp.expand((r**2 * (2 - w) ** 2 - 32 * (1 - r) * w) * sp.tan(q) ** 2)))
# Sec. IV: Eq. e.psiprime from Eq. e.psiDelta, and its small-k expansion
psi = sp.atan(sp.tan(k / 2) / D) - k / 2
T = sp.tan(k / 2) ** 2
show("e.psiprime", sp.simplify(2 * sp.diff(psi, k) - (1 - D) * (D - T) / (D**2 + T)))
show("2 psi' expansion", sp.simplify(
    sp.series(2 * sp.diff(psi, k), k, 0, 4).removeO() - ((1 - D) / D - (1 - D**2) / (4 * D**3) * k**2)))
# Sec. V.A: I_k ~ k r and R_k ~ 2w - 2k^2 to leading order in small r, w ~ r^2
Rk = 1 - (1 - w) * sp.cos(k) - (1 - w) * (1 - r) * sp.cos(2 * k) + (1 - r) * sp.cos(3 * k)
Ik = (1 - w) * sp.sin(k) + (1 - w) * (1 - r) * sp.sin(2 * k) - (1 - r) * sp.sin(3 * k)
show("R_k to k^2", sp.expand(sp.series(Rk, k, 0, 3).removeO()))
show("I_k to k", sp.expand(sp.series(Ik, k, 0, 2).removeO()))
