"""What a circuit's spectrum fit resolves, mode by mode: the measurement behind
:data:`lcchain.compare.poles.MERGED_BELOW_Q` and :func:`lcchain.compare.poles.merged_poles`.

Runs ngspice's AC analysis of one- and two-mass circuits (N = 8 to 16) with an ESR, a winding resistance, and
either with a coil's capacitance or a capacitor's ESL, R = 0.03 to 5 sqrt(L0/C0), and sets each of the circuit's
exact modes (weight |P_n| >= 1e-6) beside what the fit found for it, merged or not: how close its half-power band
comes to another's (r = min |p_n - p_m| / (h_n + h_m)), how many times it rings (Q_n = omega_n / gamma_n), and
whether it was seen and how far off.  Prints the table recorded in ``benchmarks/merged_poles.md``.

    .venv/bin/python benchmarks/bench_merged_poles.py
"""

from __future__ import annotations

import warnings

import numpy as np

from lcchain.circuit.effects import CapacitorESL, CapacitorESR, CoilCapacitance, CoilResistance, Effect
from lcchain.compare.poles import CircuitModes, measurable, merged_poles
from lcchain.core.errors import ParameterError
from lcchain.runs.execute import circuit_modes, execute, sweep_omega
from lcchain.runs.request import AC, Request, plan_request
from lcchain.runs.spec import SpectrumTheory
from lcchain.theory.cases import chain_for_case

RESISTANCES = (0.03, 0.1, 0.3, 0.6, 1.0, 2.0, 5.0)
CHAINS = (("two-mass", 8), ("two-mass", 16), ("one-mass", 12))


def overlap(modes: CircuitModes) -> np.ndarray:
    """r of each mode: its pole's nearest distance to another's over the sum of their half-widths."""
    omega, gamma = modes.omega, modes.gamma
    half = 0.5 * gamma
    pole = np.where(omega == 0, -gamma, -half + 1j * np.sqrt(np.maximum((omega - half) * (omega + half), 0.0)))
    width = np.abs(pole.real)
    ratio = np.abs(pole[:, None] - pole[None, :]) / np.maximum(width[:, None] + width[None, :], 1e-300)
    np.fill_diagonal(ratio, np.inf)
    return np.asarray(np.min(ratio, axis=1, initial=np.inf))


def main() -> None:
    warnings.simplefilter("ignore")
    rows: list[tuple[float, float, bool, float, bool]] = []  # r, Q_n, seen, error, merged
    for R in RESISTANCES:
        for case, N in CHAINS:
            parts: tuple[tuple[Effect, ...], ...] = ((CapacitorESR(R),), (CoilResistance(R),),
                                                     (CoilCapacitance(0.05), CapacitorESR(R)),
                                                     (CapacitorESL(0.04), CoilResistance(R)))
            for effects in parts:
                try:
                    plan = plan_request(Request(chain_for_case(case, N), AC(), effects=effects))
                except ParameterError:  # every mode overdamped: refused, nothing to measure
                    continue
                spec = plan.specs[0]
                record = execute(spec)
                theory = spec.theory
                assert isinstance(theory, SpectrumTheory) and theory.circuit is not None
                assert record.ok and record.run is not None and record.spectrum is not None
                modes = measurable(circuit_modes(theory.circuit, N, theory.time_unit, theory.impedance),
                                   float(np.max(sweep_omega(theory, record.run))))
                metrics, merged, r = record.spectrum, merged_poles(modes), overlap(modes)
                fitted = np.full(modes.N, np.nan)  # the fit's pole for every mode, merged or not (the metrics
                assert metrics.fit is not None and metrics.seen is not None  # hold none for a merged one)
                fitted[metrics.seen] = metrics.fit.omega
                for n in range(modes.N):
                    if abs(modes.last[n]) * float(theory.chain.masses[0]) < 1e-6:
                        continue
                    found = float(fitted[n])
                    error = abs(found - modes.omega[n]) / (modes.omega[n] if modes.omega[n] > 0 else 1.0)
                    Q = modes.omega[n] / modes.gamma[n] if modes.gamma[n] > 0 else np.inf
                    rows.append((float(r[n]), float(Q), bool(np.isfinite(found)), error, bool(merged[n])))
    print(f"{len(rows)} modes; merged {sum(row[4] for row in rows)}")
    print("| modes | Q_n | bands overlap (r < 1) | count | unseen | largest error of omega_n |")
    print("|---|---|---|---:|---:|---:|")
    for name, keep in (("resolved", False), ("merged", True)):
        for label, low, high in (("< 8", 0.0, 8.0), ("8 to 16", 8.0, 16.0), (">= 16", 16.0, np.inf)):
            for overlapping in (True, False):
                chosen = [row for row in rows
                          if row[4] == keep and low <= row[1] and (row[1] < high or high == np.inf)
                          and (row[0] < 1) == overlapping]  # a zero mode rings for ever: Q_n infinite
                if not chosen:
                    continue
                seen = [row[3] for row in chosen if row[2]]
                print(f"| {name} | {label} | {'yes' if overlapping else 'no'} | {len(chosen)} | "
                      f"{sum(not row[2] for row in chosen)} | {max(seen) if seen else float('nan'):.1e} |")


if __name__ == "__main__":
    main()
