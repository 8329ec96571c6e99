"""``lcchain check`` (issue 31 item 5): ngspice against the exact response of linear circuits nobody here wrote.

Each circuit is a netlist written here, from a textbook: a series RLC band-pass driven by a PULSE, a doubly
terminated 5th-order Butterworth LC ladder (normalised values 0.618, 1.618, 2, 1.618, 0.618 from the table of
Butterworth prototypes, e.g. Zverev, *Handbook of Filter Synthesis*, 1967; Matthaei, Young & Jones, 1964, Table
4.05-1) driven by a SIN and a PWL, and a lumped transmission line of 200 LC sections driven by a step through its
matching resistor (Z0 = sqrt(L/C)).

Every exact reference of lcchain (:mod:`lcchain.circuit.linear`) is checked against one computed here
independently: the state equations written by hand from Kirchhoff's laws and integrated by ``scipy.linalg.expm``
of the state matrix augmented with the input's generator states (a ramp: two states; a sine: two), or a closed
form (the AC transfer function).  ngspice's measured error is then compared with the error lcchain predicts
from the step, within :data:`PREDICTION_BAND`.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest
import scipy.linalg
from helpers.tolerances import (
    ATOL_IC_CURRENT,
    ATOL_IC_VOLTAGE,
    RTOL_CHECK_AC,
    RTOL_CHECK_AC_BY_HAND,
    RTOL_ONE_OPERATION,
    RTOL_PRINTED,
    RTOL_STORED_CHECK_ERROR,
)

from lcchain.cli.main import main
from lcchain.core.errors import ParameterError
from lcchain.runs.check import CheckOptions, check_text, circuit_of
from lcchain.spice.element_values import ElementCard, read_cards
from lcchain.spice.expressions import evaluate_expression, param_values
from lcchain.spice.foreign import allowed_netlist, analysis_of

#: lcchain's exact reference against the independent one (relative to the signal's scale): both are exact, so
#: only rounding separates them (expm's and the modal sum's, measured 1e-13 .. 1e-11).
RTOL_EXACT = 1e-9
#: The same for the line of 200 sections driven through a 1 ns ramp: the ramp's particular solution (its slope
#: times the line's delays, 1e3 times the signal) cancels against 400 modes at the ramp's start, which leaves
#: 1.8e-8 of the source current's scale at t = 0 (measured; 1e-12 elsewhere).
RTOL_EXACT_LINE = 1e-7
#: ngspice's measured error over lcchain's predicted one (the trapezoidal model at the run's largest step) must
#: lie in this band (measured 0.6 .. 1.0 on these circuits; ngspice's start-up steps and its breakpoints make
#: it a little smaller than the model).
PREDICTION_BAND = (0.3, 3.0)

BANDPASS = """series RLC band-pass (f0 = 1/(2 pi sqrt(LC)) = 15.9 kHz, Q = 2.5) driven by a PULSE
V1 in 0 PULSE(0 1 0 1u 1u 20u 100u)
R1 in a 50
L1 a b 1m
C1 b out 100n
R2 out 0 10
.tran 0.1u 200u 0 0.1u
.end
"""

#: The Butterworth ladder: 1 ohm, cutoff 1 kHz (values from the normalised prototype, wc = 2 pi 1 kHz).
BUTTERWORTH = """5th-order Butterworth LC ladder, doubly terminated
.param wc = 6283.185307179586 r0 = 1
V1 in 0 {drive}
RS in n1 {{r0}}
C1 n1 0 {{0.618/(wc*r0)}}
L2 n1 n2 {{1.618*r0/wc}}
C3 n2 0 {{2/(wc*r0)}}
L4 n2 n3 {{1.618*r0/wc}}
C5 n3 0 {{0.618/(wc*r0)}}
RL n3 0 {{r0}}
.save v(n1) v(n2) v(n3) i(l2) i(l4) i(v1)
.tran 1u {tstop} 0 {tmax}
.end
"""


def _write(tmp_path: Path, text: str, name: str = "circuit.cir") -> Path:
    path = tmp_path / name
    path.write_text(text)
    return path


def _reference(text: str, names: list[str], t: np.ndarray) -> np.ndarray:
    """lcchain's exact reference of the named vectors at t."""
    from lcchain.circuit.linear import linear_response

    allowed = allowed_netlist(text, "netlist", None)
    analysis = analysis_of(allowed, "netlist")
    response = linear_response(circuit_of(read_cards(allowed), analysis))
    y, _ = response.transient([response.output(n) for n in names], t, analysis.tstop)
    return y


def _expm_response(A: np.ndarray, b: np.ndarray, pieces: list[tuple[float, float, float]], t: np.ndarray,
                   x0: np.ndarray | None = None) -> np.ndarray:
    """x(t) of x' = A x + b u with u piecewise linear: pieces (start, value, slope); the state augmented with
    (u, u') and carried across each piece by expm of the augmented matrix (exact)."""
    n = A.shape[0]
    M = np.zeros((n + 2, n + 2))
    M[:n, :n], M[:n, n], M[n, n + 1] = A, b, 1.0
    out = np.zeros((n, t.size))
    x = np.zeros(n) if x0 is None else x0
    starts = [p[0] for p in pieces] + [math.inf]
    for k, (start, value, slope) in enumerate(pieces):
        z0 = np.concatenate([x, [value, slope]])
        inside = (t >= start) & (t < starts[k + 1])
        for i in np.flatnonzero(inside):
            out[:, i] = (scipy.linalg.expm(M * (t[i] - start)) @ z0)[:n]
        if starts[k + 1] < math.inf:
            x = (scipy.linalg.expm(M * (starts[k + 1] - start)) @ z0)[:n]
    return out


def _bandpass_state() -> tuple[np.ndarray, np.ndarray]:
    """States (i_L, v_C) of V1 - R1 - L1 - C1 - R2: L i' = u - (R1 + R2) i - v_C, C v_C' = i."""
    R, L, C = 60.0, 1e-3, 100e-9
    return np.array([[-R / L, -1 / L], [1 / C, 0.0]]), np.array([1 / L, 0.0])


def _pulse_pieces(v1: float, v2: float, rise: float, width: float, fall: float, period: float, stop: float
                  ) -> list[tuple[float, float, float]]:
    pieces: list[tuple[float, float, float]] = []
    start = 0.0
    while start < stop:
        pieces += [(start, v1, (v2 - v1) / rise), (start + rise, v2, 0.0), (start + rise + width, v2, (v1 - v2) / fall),
                   (start + rise + width + fall, v1, 0.0)]
        start += period
    return pieces


# --------------------------------------------------------------------------- expressions (no simulator)


def test_param_expressions_evaluate_as_ngspice_reads_them() -> None:
    values = param_values({"c": ("l*1meg", "x", ""), "wc": ("6283.185307179586", "x", ""),
                           "l": ("1.618/wc", "x", "")})  # a name used before the card that defines it
    assert values["l"] == pytest.approx(1.618 / 6283.185307179586, rel=RTOL_ONE_OPERATION)
    assert values["c"] == pytest.approx(values["l"] * 1e6, rel=RTOL_ONE_OPERATION)
    assert evaluate_expression("2*r+1k", {"r": 3.0}) == 1006.0
    assert evaluate_expression("1 < 2 ? 3 : 4", {}) == 3.0
    with pytest.raises(ParameterError, match="finite value"):
        evaluate_expression("1/0", {})


def _ngspice_resistances(tmp_path: Path, expressions: list[str]) -> list[float]:
    """The resistance ngspice 39 gives ``R {expression}`` in a real run, from the current it measures at 1 V."""
    import re
    import subprocess

    lines = ["expressions"]
    for k, expression in enumerate(expressions):
        lines += [f"V{k} n{k} 0 DC 1", f"R{k} n{k} 0 {{{expression}}}"]
    lines += [".tran 1u 2u"] + [f".meas tran i{k} find i(V{k}) at=1u" for k in range(len(expressions))]
    lines += [".end"]
    netlist = tmp_path / "expressions.cir"
    netlist.write_text("\n".join(lines) + "\n")
    printed = subprocess.run(["ngspice", "-b", netlist.name], cwd=tmp_path, capture_output=True, text=True,
                             stdin=subprocess.DEVNULL, timeout=60).stdout
    found = [re.search(rf"^i{k}\s*=\s*(\S+)", printed, re.MULTILINE) for k in range(len(expressions))]
    assert all(match is not None for match in found), printed
    return [-1.0 / float(match.group(1)) for match in found if match is not None]


@pytest.mark.ngspice
def test_powers_evaluate_as_ngspice_reads_them(tmp_path: Path) -> None:
    """ngspice 39 reads ``2^3^2`` left to right (64), not as (2^(3^2)) = 512: the resistor each expression makes,
    found from the current ngspice measures through it at 1 V, is the value lcchain's evaluator gives."""
    expressions = ["2^3^2", "2**3**2", "2^-1", "-2^2+10", "2*3^2", "(2^3)^2", "2^(3^2)/64", "4^0.5^2"]
    for expression, resistance in zip(expressions, _ngspice_resistances(tmp_path, expressions), strict=True):
        # ngspice prints 7 significant digits; 2^3^2 read right to left (512) is 8 times off
        assert resistance == pytest.approx(evaluate_expression(expression, {}), rel=RTOL_PRINTED), expression


@pytest.mark.ngspice
def test_the_remainder_evaluates_as_ngspice_reads_it(tmp_path: Path) -> None:
    """``%`` as ngspice 39 reads it: C's fmod (the dividend's sign), as tight as * and /, looser than ^.  Each
    remainder is offset by 1000 ohm (a resistor > 0), and the two readings of each differ by 0.5 at least."""
    expressions = ["-7 % 3", "7.5 % 2", "7 % -3", "2 + 7 % 3 * 2", "2 * 7 % 4", "2^3 % 5", "-7.5 % 2", "7 % 3 % 2",
                   "10 / 4 % 2"]
    resistances = _ngspice_resistances(tmp_path, [f"1000 + ({expression})" for expression in expressions])
    for expression, resistance in zip(expressions, resistances, strict=True):
        assert resistance == pytest.approx(1000 + evaluate_expression(expression, {}), rel=RTOL_PRINTED), expression
    with pytest.raises(ParameterError, match="finite value"):  # ngspice stops the run with an error
        evaluate_expression("7 % 0", {})


# --------------------------------------------------------------------------- the exact references, independently


def test_bandpass_reference_is_the_state_equations_exponential() -> None:
    t = np.linspace(0.0, 200e-6, 201)
    mine = _reference(BANDPASS, ["i(l1)", "v(out)"], t)
    A, b = _bandpass_state()
    x = _expm_response(A, b, _pulse_pieces(0, 1, 1e-6, 20e-6, 1e-6, 100e-6, 200e-6), t)
    np.testing.assert_allclose(mine[0], x[0], rtol=0, atol=RTOL_EXACT * np.max(np.abs(x[0])))
    np.testing.assert_allclose(mine[1], 10.0 * x[0], rtol=0, atol=RTOL_EXACT * 10 * np.max(np.abs(x[0])))


def _butterworth_state() -> tuple[np.ndarray, np.ndarray]:
    """States (v1, i2, v3, i4, v5) of the ladder, RS = RL = 1 ohm, from Kirchhoff's laws."""
    wc = 2 * math.pi * 1e3
    C1, L2, C3, L4, C5 = 0.618 / wc, 1.618 / wc, 2 / wc, 1.618 / wc, 0.618 / wc
    A = np.array([[-1 / C1, -1 / C1, 0, 0, 0], [1 / L2, 0, -1 / L2, 0, 0], [0, 1 / C3, 0, -1 / C3, 0],
                  [0, 0, 1 / L4, 0, -1 / L4], [0, 0, 0, 1 / C5, -1 / C5]])
    return A, np.array([1 / C1, 0, 0, 0, 0])


def _butterworth_sine_state(hertz: float) -> tuple[np.ndarray, np.ndarray]:
    """The ladder driven by u = sin(w t): its state augmented with (sin, cos), whose generator is
    [[0, w], [-w, 0]]; (matrix, state at t = 0)."""
    A, b = _butterworth_state()
    w = 2 * math.pi * hertz
    M = np.zeros((7, 7))
    M[:5, :5], M[:5, 5] = A, b
    M[5, 6], M[6, 5] = w, -w
    z0 = np.zeros(7)
    z0[6] = 1.0  # (sin, cos) = (0, 1) at t = 0
    return M, z0


def test_butterworth_sine_reference_is_the_state_equations_exponential() -> None:
    """u = sin(w t): the state augmented with (sin, cos), whose generator is [[0, w], [-w, 0]]."""
    text = BUTTERWORTH.format(drive="SIN(0 1 700 0 0 0)", tstop="5m", tmax="1u")
    t = np.linspace(0.0, 5e-3, 401)
    mine = _reference(text, ["v(n3)", "i(l2)"], t)
    M, z0 = _butterworth_sine_state(700)
    x = np.array([scipy.linalg.expm(M * tk) @ z0 for tk in t]).T
    for row, state in ((0, 4), (1, 1)):
        np.testing.assert_allclose(mine[row], x[state], rtol=0, atol=RTOL_EXACT * np.max(np.abs(x[state])))


def test_butterworth_pwl_reference_is_the_state_equations_exponential() -> None:
    text = BUTTERWORTH.format(drive="PWL(0 0 0.1m 1 1m 1 1.2m -0.5 2m 0)", tstop="4m", tmax="1u")
    t = np.linspace(0.0, 4e-3, 161)
    mine = _reference(text, ["v(n1)", "i(l4)"], t)
    A, b = _butterworth_state()
    pieces = [(0.0, 0.0, 1e4), (1e-4, 1.0, 0.0), (1e-3, 1.0, -1.5 / 2e-4), (1.2e-3, -0.5, 0.5 / 8e-4),
              (2e-3, 0.0, 0.0)]
    x = _expm_response(A, b, pieces, t)
    for row, state in ((0, 0), (1, 3)):
        np.testing.assert_allclose(mine[row], x[state], rtol=0, atol=RTOL_EXACT * np.max(np.abs(x[state])))


# --------------------------------------------------------------------------- ngspice against the reference


@pytest.mark.ngspice
def test_bandpass_error_is_the_predicted_one(tmp_path: Path) -> None:
    result = check_text(BANDPASS, "bandpass.cir")
    assert result.reference == "" and result.method == "trap" and result.states == 2
    assert {v.name for v in result.vectors} >= {"v(out)", "i(l1)", "i(v1)", "v(b)"}
    for vector in result.vectors:
        if vector.name != "v(in)":  # the source's node: exact in both
            assert PREDICTION_BAND[0] <= vector.max_abs_error / vector.predicted_error <= PREDICTION_BAND[1]
    assert result.max_abs_error == max(v.max_abs_error for v in result.vectors)


@pytest.mark.ngspice
def test_butterworth_sine_error_is_predicted_and_the_suggested_step_reaches_the_accuracy(tmp_path: Path) -> None:
    text = BUTTERWORTH.format(drive="SIN(0 1 700 0 0 0)", tstop="5m", tmax="1u")
    accuracy = 1e-6
    result = check_text(text, "butterworth.cir", options=CheckOptions(accuracy=accuracy))
    worst = max(result.vectors, key=lambda v: v.max_abs_error or 0.0)
    assert PREDICTION_BAND[0] <= worst.max_abs_error / worst.predicted_error <= PREDICTION_BAND[1]
    assert result.suggested_step is not None and result.suggested_step < 1e-6
    finer = check_text(BUTTERWORTH.format(drive="SIN(0 1 700 0 0 0)", tstop="5m", tmax=repr(result.suggested_step)), "butterworth.cir", options=CheckOptions(accuracy=accuracy))
    assert finer.passed and finer.max_rel_error <= accuracy


@pytest.mark.ngspice
def test_check_json_and_exit_codes(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    path = _write(tmp_path, BUTTERWORTH.format(drive="PWL(0 0 0.1m 1 1m 1 1.2m -0.5 2m 0)", tstop="4m",
                                               tmax="1u"))
    assert main(["check", str(path), "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["exact_reference"] and data["method"] == "trap" and data["states"] == 5
    assert data["max_abs_error"] == max(v["max_abs_error"] for v in data["vectors"])
    assert data["predicted_error"] > 0 and data["suggested_step"] > 0 and data["reference_seconds"] > 0
    assert PREDICTION_BAND[0] <= data["max_abs_error"] / data["predicted_error"] <= PREDICTION_BAND[1]
    assert main(["check", str(path), "--accuracy", "1e-9"]) == 1  # ngspice's error at 1 us is ~1e-6
    said = capsys.readouterr().out
    assert "exceeds --accuracy" in said
    # the step it suggests is the card's TMAX, its TSTART the user's own (not a 0 in its place)
    assert "(the .tran card's TMAX: .tran TSTEP TSTOP TSTART " in said and ".tran TSTEP TSTOP 0 " not in said


@pytest.mark.ngspice
def test_ac_sweep_is_the_transfer_function(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    text = BANDPASS.replace("PULSE(0 1 0 1u 1u 20u 100u)", "DC 0 AC 1").replace(".tran 0.1u 200u 0 0.1u",
                                                                                 ".ac dec 20 100 1meg")
    from lcchain.circuit.linear import linear_response

    allowed = allowed_netlist(text, "netlist", None)
    response = linear_response(circuit_of(read_cards(allowed), analysis_of(allowed, "netlist", lambda: "39")))
    f = np.geomspace(100, 1e6, 81)
    mine = response.ac([response.output("v(out)")], f)[0]
    s = 2j * np.pi * f
    hand = 10.0 / (60.0 + s * 1e-3 + 1 / (s * 100e-9))  # v(out) = R2 I, I = 1 / Z
    np.testing.assert_allclose(mine, hand, rtol=RTOL_CHECK_AC_BY_HAND)
    assert main(["check", str(_write(tmp_path, text)), "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["analysis"] == "ac" and data["points"] == 81 and data["max_rel_error"] < RTOL_CHECK_AC
    assert data["predicted_error"] is None
    assert main(["check", str(_write(tmp_path, text))]) == 0  # no step, no integration method to name
    assert "method" not in capsys.readouterr().out.splitlines()[0]


# --------------------------------------------------------------------------- what has no exact reference, refusals


@pytest.mark.ngspice
@pytest.mark.parametrize(("card", "reason"), [
    ("B1 out 0 V=v(a)*v(a)", "behavioural source: B1"),
    ("V2 out 0 SFFM(0 1 10k 5 1k)", "source V2: SFFM"),
])
def test_what_is_not_linear_runs_with_no_reference(tmp_path: Path, capsys: pytest.CaptureFixture[str], card: str,
                                                   reason: str) -> None:
    text = f"not linear\nV1 a 0 PULSE(0 1 0 1u 1u 20u 100u)\nR1 a 0 1k\nR2 out 0 1k\n{card}\n.tran 1u 100u\n.end\n"
    assert main(["check", str(_write(tmp_path, text))]) == 0
    assert f"no exact reference ({reason}" in capsys.readouterr().out


@pytest.mark.ngspice
def test_a_diode_runs_with_no_reference(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    text = ("diode clipper\nV1 in 0 SIN(0 2 10k)\nR1 in a 1k\nD1 a 0 dmod\n.model dmod d\n.tran 1u 200u\n.end\n")
    path = _write(tmp_path, text)
    assert main(["check", str(path), "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert not data["exact_reference"] and data["no_reference_reason"] == "nonlinear: D1"
    assert data["max_abs_error"] is None and data["points"] > 0
    control = _write(tmp_path, text.replace(".end", ".control\nrun\n.endc\n.end"), "control.cir")
    assert main(["check", str(control)]) == 2  # the allow-list: no .control block
    assert "line 7" in capsys.readouterr().err
    assert main(["check", str(control), "--allow-control"]) == 0  # as it is, in the sandbox
    assert "no exact reference (nonlinear: D1)" in capsys.readouterr().out


@pytest.mark.parametrize(("cards", "names"), [
    ("V1 a 0 1\nC1 a b 1u\nC2 b 0 1u\nR1 a 0 1k\n.tran 1u 10u uic\n", "V1 C1 C2"),
    ("V1 a 0 1\nV2 a 0 2\nR1 a 0 1k\n.tran 1u 10u\n", "V2 V1"),
    ("V1 a 0 1\nR1 a b 1k\nC1 b c 1u\nC2 c 0 1u\n.tran 1u 10u\n", "C1"),
    ("I1 0 a 1m\nR1 a 0 100\nL1 a 0 1m\nL2 a 0 2m\n.tran 1u 10u\n", "L2 L1"),  # ngspice: an arbitrary split
    ("V1 a 0 1\nR1 a b 20\nL1 b c 100u\nC1 c 0 1u\n.tran 1u 10u\n", "double pole"),  # critically damped
])
def test_an_ill_posed_circuit_is_refused_naming_its_elements(tmp_path: Path, capsys: pytest.CaptureFixture[str],
                                                             cards: str, names: str) -> None:
    path = _write(tmp_path, "ill posed\n" + cards + ".end\n")
    assert main(["check", str(path)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and names.split()[0] in err and "Traceback" not in err


def test_bad_input_is_one_line(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    path = _write(tmp_path, "bad analysis\nV1 a 0 1\nR1 a 0 1k\n.tran 1u\n.end\n")
    assert main(["check", str(path)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "line 4" in err
    assert main(["check", str(path), "--accuracy", "2"]) == 2
    assert "--accuracy" in capsys.readouterr().err
    assert main(["check", str(path), "--engine", "gnucap"]) == 2  # read before any engine runs
    assert "line 4" in capsys.readouterr().err
    assert main(["check", str(tmp_path / "missing.cir")]) == 2


# --------------------------------------------------------------------------- the slow one: a transmission line


def _line(sections: int) -> str:
    lines = ["lumped transmission line, Z0 = sqrt(250n/100p) = 50 ohm, driven through its matching resistor",
             "V1 in 0 PULSE(0 1 0 1n 1n 1 1)", "RS in n0 50"]
    for k in range(sections):
        lines += [f"L{k + 1} n{k} n{k + 1} 250n", f"C{k + 1} n{k + 1} 0 100p"]
    lines += [f"RL n{sections} 0 50", f".save v(n0) v(n{sections // 2}) v(n{sections}) i(v1)",
              ".tran 1n 2u", ".end"]
    return "\n".join(lines) + "\n"


@pytest.mark.slow
@pytest.mark.ngspice
def test_transmission_line_of_200_sections() -> None:
    """States (i_1 .. i_200, v_1 .. v_200), the source's node n0 eliminated: v0 = u - 50 i_1."""
    N, L, C, R = 200, 250e-9, 100e-12, 50.0
    text = _line(N)
    A = np.zeros((2 * N, 2 * N))
    b = np.zeros(2 * N)
    for k in range(N):  # L i_k' = v_{k-1} - v_k
        if k == 0:
            A[0, 0], b[0] = -R / L, 1 / L
        else:
            A[k, N + k - 1] = 1 / L
        A[k, N + k] = -1 / L
    for k in range(N):  # C v_k' = i_k - i_{k+1} (the last: - v_N / R)
        A[N + k, k] = 1 / C
        if k + 1 < N:
            A[N + k, k + 1] = -1 / C
        else:
            A[N + k, N + k] = -1 / (R * C)
    t = np.linspace(0.0, 2e-6, 81)
    x = _expm_response(A, b, [(0.0, 0.0, 1e9), (1e-9, 1.0, 0.0)], t)
    mine = _reference(text, ["v(n100)", "v(n200)", "i(v1)"], t)
    for row, state in ((0, N + 99), (1, 2 * N - 1), (2, 0)):
        np.testing.assert_allclose(mine[row], -x[0] if row == 2 else x[state], rtol=0,
                                   atol=RTOL_EXACT_LINE * np.max(np.abs(x[state])))
    result = check_text(text, "line.cir")
    assert result.states == 2 * N
    worst = max(result.vectors, key=lambda v: v.max_abs_error or 0.0)
    assert PREDICTION_BAND[0] <= worst.max_abs_error / worst.predicted_error <= PREDICTION_BAND[1]


@pytest.mark.ngspice
def test_batch_check_stores_the_error_as_a_measurement(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    linear = _write(tmp_path, BANDPASS, "bandpass.cir")
    behavioural = _write(tmp_path, "behavioural\nV1 a 0 1\nR1 a 0 1k\nB1 b 0 V=v(a)*v(a)\nR2 b 0 1k\n"
                         ".tran 1u 10u\n.end\n", "b.cir")
    store = tmp_path / "batch.sqlite"
    assert main(["batch", str(linear), str(behavioural), "--check", "--store", str(store)]) == 0
    capsys.readouterr()
    assert main(["results", str(store), "--json"]) == 0
    runs = json.loads(capsys.readouterr().out)
    errors = {Path(r["params"]["netlist"]).name: r["measurements"]["check_max_abs_error"] for r in runs}
    assert errors["b.cir"] is None
    direct = check_text(BANDPASS, "bandpass.cir")
    assert errors["bandpass.cir"] == pytest.approx(direct.max_abs_error, rel=RTOL_STORED_CHECK_ERROR)


@pytest.mark.ngspice
def test_gear_is_named_and_its_prediction_is_said_to_be_rough() -> None:
    result = check_text(BANDPASS.replace(".end", ".options method=gear\n.end"), "gear.cir")
    assert result.method == "gear" and "rough" in result.prediction
    assert result.max_abs_error is not None and result.predicted_error is not None


@pytest.mark.ngspice
def test_ic_holds_a_node_for_the_operating_point() -> None:
    """V1 = 1 V through 10 ohm into C || 1 kohm, .ic v(b) = 0.3: the operating point holds v(b) at 0.3, then
    v(b) = v_inf + (0.3 - v_inf) exp(-t / tau), v_inf = 1000/1010 V, tau = C (10 || 1000) (first-order RC)."""
    text = "ic\nV1 a 0 1\nR1 a b 10\nC1 b 0 1u\nR2 b 0 1k\n.ic v(b)=0.3\n.tran 0.1u 40u\n.end\n"
    t = np.linspace(0.0, 40e-6, 41)
    v_inf, tau = 1000 / 1010, 1e-6 * 10 * 1000 / 1010
    np.testing.assert_allclose(_reference(text, ["v(b)"], t)[0], v_inf + (0.3 - v_inf) * np.exp(-t / tau),
                               rtol=0, atol=RTOL_EXACT)
    result = check_text(text, "ic.cir")
    assert PREDICTION_BAND[0] <= result.max_abs_error / result.predicted_error <= PREDICTION_BAND[1]


@pytest.mark.ngspice
def test_uic_starts_from_the_elements_initial_conditions() -> None:
    """uic: the capacitor at its IC= (0.5 V), the coil at its IC= (1 mA); the series RLC then rings from there."""
    text = ("uic\nV1 a 0 PULSE(0 1 0 1u 1u 5u 20u)\nR1 a b 10\nL1 b c 1m IC=1m\nC1 c 0 1u IC=0.5\n"
            ".tran 0.1u 40u uic\n.end\n")
    t = np.array([0.0, 1e-6, 10e-6, 33e-6])
    y = _reference(text, ["v(c)", "i(l1)"], t)
    assert y[0, 0] == pytest.approx(0.5, abs=ATOL_IC_VOLTAGE) and y[1, 0] == pytest.approx(1e-3, abs=ATOL_IC_CURRENT)
    A = np.array([[-10 / 1e-3, -1 / 1e-3], [1 / 1e-6, 0.0]])  # (i, v_C): L i' = u - R i - v_C, C v_C' = i
    x = _expm_response(A, np.array([1 / 1e-3, 0.0]), _pulse_pieces(0, 1, 1e-6, 5e-6, 1e-6, 20e-6, 40e-6), t,
                       x0=np.array([1e-3, 0.5]))
    np.testing.assert_allclose(y[0], x[1], rtol=0, atol=RTOL_EXACT)
    result = check_text(text, "uic.cir")
    assert PREDICTION_BAND[0] <= result.max_abs_error / result.predicted_error <= PREDICTION_BAND[1]


@pytest.mark.ngspice
def test_a_capacitor_across_a_source_is_compared_from_its_operating_point() -> None:
    """The source's current C du/dt jumps as the PULSE starts: at t = 0 ngspice reports the operating point's."""
    text = ("cap across V\nV1 a 0 PULSE(0 1 0 1u 1u 5u 20u)\nC0 a 0 1u\nR1 a b 10\nC1 b 0 1u\n"
            ".tran 0.1u 40u\n.end\n")
    result = check_text(text, "capv.cir")
    worst = max(result.vectors, key=lambda v: v.max_abs_error or 0.0)
    assert PREDICTION_BAND[0] <= worst.max_abs_error / worst.predicted_error <= PREDICTION_BAND[1]


@pytest.mark.ngspice
def test_coupled_coils_are_the_state_equations_exponential() -> None:
    """A transformer (k = 0.9) loaded by 50 ohm: [L1 M; M L2] (i1, i2)' = (u - R1 i1, -R2 i2), M = k sqrt(L1 L2)."""
    text = ("transformer\nV1 a 0 PULSE(0 1 0 1u 1u 5u 20u)\nR1 a b 10\nL1 b 0 1m\nL2 c 0 1m\nR2 c 0 50\n"
            "K1 L1 L2 0.9\n.tran 0.1u 40u\n.end\n")
    t = np.linspace(0.0, 40e-6, 81)
    inductance = np.array([[1e-3, 0.9e-3], [0.9e-3, 1e-3]])
    A = np.linalg.solve(inductance, np.diag([-10.0, -50.0]))
    b = np.linalg.solve(inductance, np.array([1.0, 0.0]))
    x = _expm_response(A, b, _pulse_pieces(0, 1, 1e-6, 5e-6, 1e-6, 20e-6, 40e-6), t)
    mine = _reference(text, ["i(l1)", "i(l2)"], t)
    for row in (0, 1):
        np.testing.assert_allclose(mine[row], x[row], rtol=0, atol=RTOL_EXACT * np.max(np.abs(x[row])))
    result = check_text(text, "transformer.cir")
    worst = max(result.vectors, key=lambda v: v.max_abs_error or 0.0)
    assert PREDICTION_BAND[0] <= worst.max_abs_error / worst.predicted_error <= PREDICTION_BAND[1]


def test_the_check_and_a_batchs_check_are_priced_with_their_exact_reference(tmp_path: Path,
                                                                            capsys: pytest.CaptureFixture[str]) -> None:
    """The dense reference grows as the cube of the circuit's unknowns: a 1000-section line is refused under a
    30 s budget before anything runs, naming the reference; the run alone (a batch without --check) fits."""
    from lcchain.runs.check import check_estimate
    from lcchain.spice.foreign import foreign_price
    from lcchain.spice.text import saved_vectors

    line = _write(tmp_path, _line(1000), "line.cir")
    assert main(["check", str(line), "--max-time", "30s"]) == 2
    err = capsys.readouterr().err
    assert "exact reference (2003 unknowns)" in err and "--max-time" in err and len(err.strip().splitlines()) == 1
    store = tmp_path / "b.sqlite"
    assert main(["batch", str(line), "--check", "--store", str(store), "--max-time", "30s"]) == 2
    assert "exact reference (2003 unknowns)" in capsys.readouterr().err  # its only netlist refused: nothing ran
    text = allowed_netlist(_line(1000), "line.cir", None)
    analysis = analysis_of(text, "line.cir", lambda: "39")
    price = foreign_price(text, analysis, len(saved_vectors(text)))
    assert check_estimate(price, text, analysis).seconds > 10 * price.seconds  # the reference, not the run


def test_a_coil_of_a_kilohenry_beside_a_femtofarad_keeps_both_poles() -> None:
    # E's entries 1e18 apart: its rank, counted before balancing, lost the capacitor's pole, and the check refused
    # a consistent start ("1.0e+00 of it outside the circuit's modes").  The reference is the series RLC's state
    # equations in balanced units (sqrt(L) i, sqrt(C) v_C), their exponential exact.
    R, L, C = 1e3, 1e3, 1e-15
    text = ("series RLC, values far apart\nV1 in 0 PULSE(0 1 0 1n 1n 2u 4u)\nR1 in a 1e3\nL1 a out 1e3\n"
            "C1 out 0 1e-15\n.tran 10n 8u\n.end\n")
    t = np.linspace(0.0, 8e-6, 161)
    mine = _reference(text, ["i(l1)", "v(out)"], t)
    w0 = 1.0 / math.sqrt(L * C)
    A = np.array([[-R / L, -w0], [w0, 0.0]])
    x = _expm_response(A, np.array([1.0 / math.sqrt(L), 0.0]), _pulse_pieces(0, 1, 1e-9, 2e-6, 1e-9, 4e-6, 8e-6), t)
    current, voltage = x[0] / math.sqrt(L), x[1] / math.sqrt(C)
    np.testing.assert_allclose(mine[0], current, rtol=0, atol=RTOL_EXACT * np.max(np.abs(current)))
    np.testing.assert_allclose(mine[1], voltage, rtol=0, atol=RTOL_EXACT * np.max(np.abs(voltage)))


def test_a_sine_off_a_resonance_of_values_far_apart_is_solved_equilibrated() -> None:
    # 1 MH, 1e-20 F and 1e-6 ohm driven at 1 MHz, off their 1.59 MHz resonance: the particular solution's matrix
    # (entries 1e26 apart) is ill-conditioned for LAPACK until its rows and columns are scaled; it was refused as
    # "a source term at one of the circuit's poles".  Reference: the balanced state with (sin, cos) beside it.
    R, L, C, hertz = 1e-6, 1e6, 1e-20, 1e6
    text = "far apart, driven\nV1 in 0 SIN(0 1 1meg)\nR1 in a 1e-6\nL1 a out 1e6\nC1 out 0 1e-20\n.tran 10n 4u\n.end\n"
    t = np.linspace(0.0, 4e-6, 81)
    mine = _reference(text, ["i(l1)", "v(out)"], t)
    w0, w = 1.0 / math.sqrt(L * C), 2 * math.pi * hertz
    M = np.zeros((4, 4))
    M[:2, :2] = [[-R / L, -w0], [w0, 0.0]]
    M[0, 2], M[2, 3], M[3, 2] = 1.0 / math.sqrt(L), w, -w
    x = np.array([(scipy.linalg.expm(M * tk) @ np.array([0.0, 0.0, 0.0, 1.0]))[:2] for tk in t]).T
    current, voltage = x[0] / math.sqrt(L), x[1] / math.sqrt(C)
    np.testing.assert_allclose(mine[0], current, rtol=0, atol=RTOL_EXACT * np.max(np.abs(current)))
    np.testing.assert_allclose(mine[1], voltage, rtol=0, atol=RTOL_EXACT * np.max(np.abs(voltage)))


def test_a_netlists_options_are_read_whatever_its_ic_card_holds() -> None:
    # the .ic card's loop reused the netlist text's name: its last value ("0") was read for the options, so a
    # netlist with a .ic ran gear and was predicted (and reported) as trap
    text = ("tank\n.options method=gear reltol=1e-4\nL1 a 0 10u IC=1m\nC1 a 0 1n\nR1 a 0 1k\n.ic v(a)=0\n"
            ".tran 1n 20u uic\n.end\n")
    cards = read_cards(allowed_netlist(text, "tank.cir", None), "tank.cir")
    assert cards.method == "gear" and dict(cards.options)["reltol"] == "1e-4"
    assert cards.initial == (("a", 0.0),)


@pytest.mark.ngspice
def test_a_nodeset_is_run_and_leaves_the_linear_reference_alone() -> None:
    # .nodeset, as engineers' decks carry it, was refused by the allow-list; it guesses the operating point for the
    # solver, which a linear circuit's unique operating point does not need
    text = ("nodeset\nI1 0 a SIN(0 1m 100k 1u 1e4 30)\nR1 a 0 1k\nC1 a 0 1n\nL1 a b 1m\nR2 b 0 10\n"
            ".nodeset v(a)=0.1\n.tran 10n 50u\n.end\n")
    result = check_text(text, "nodeset.cir")
    assert result.max_abs_error is not None and result.predicted_error is not None
    assert PREDICTION_BAND[0] <= result.max_abs_error / result.predicted_error <= PREDICTION_BAND[1]


# --------------------------------------------------------------------------- sub-circuits, flattened as ngspice does

SUBCKTS = """coil models as sub-circuits, one inside another
.param lv = 10u
.global gnd2
.subckt coil a b params: l=1u rs=0.1 cp=1p
L1 a mid {l}
R1 mid b {rs}
C1 a mid {cp}
.subckt unused c
.param rs = 1meg
R9 c 0 {rs}
.ends
.ends
.subckt pair a b
.param half = {lv/2}
X1 a m coil l={2*lv}
X2 m b coil l={half} rs=0.5
RG m gnd2 1k
RH m gnd 1meg
.ends
V1 in 0 PULSE(0 1 0 10n 10n 1u 2u)
XA in out pair
R2 out 0 50
C2 out 0 1n
RG2 gnd2 0 10
.tran 5n 4u
.end
"""
#: The same circuit written flat, by hand: each element of SUBCKTS's and its name in ngspice's flattening.
FLAT = """the same circuit, flat
V1 in 0 PULSE(0 1 0 10n 10n 1u 2u)
L1 in x1mid 20u
R1 x1mid m 0.1
C1 in x1mid 1p
L2 m x2mid 5u
R3 x2mid out 0.5
C3 m x2mid 1p
RG m gnd2 1k
RH m 0 1meg
R2 out 0 50
C2 out 0 1n
RG2 gnd2 0 10
.tran 5n 4u
.end
"""
FLATTENED = {"i(l.xa.x1.l1)": "i(l1)", "i(l.xa.x2.l1)": "i(l2)", "v(xa.m)": "v(m)", "v(xa.x1.mid)": "v(x1mid)",
             "v(xa.x2.mid)": "v(x2mid)", "v(out)": "v(out)", "v(gnd2)": "v(gnd2)", "i(v1)": "i(v1)", "v(in)": "v(in)"}


def test_a_subcircuit_is_flattened_as_ngspice_names_it() -> None:
    """Each instance's elements with ngspice 39's names (``l.xa.x1.l1``, node ``xa.x1.mid``), its ports wired to
    the instance's nodes, a .global node and ground (``gnd`` too) shared, its values read in its own scope (an
    instance's parameters over the .subckt card's defaults, a body's .param over the netlist's, a nested
    definition's .param its own): the same response as the circuit written flat by hand."""
    cards = read_cards(allowed_netlist(SUBCKTS, "netlist", None))
    by_name = {card.name: card for card in cards.elements}
    assert set(by_name) == {"v1", "l.xa.x1.l1", "r.xa.x1.r1", "c.xa.x1.c1", "l.xa.x2.l1", "r.xa.x2.r1",
                            "c.xa.x2.c1", "r.xa.rg", "r.xa.rh", "r2", "c2", "rg2"}
    assert by_name["r.xa.rh"].b == "gnd"  # ground inside a sub-circuit, as ngspice reads "gnd"
    coil, second = by_name["l.xa.x1.l1"], by_name["l.xa.x2.l1"]
    assert (coil.a, coil.b) == ("in", "xa.x1.mid") and (second.a, second.b) == ("xa.m", "xa.x2.mid")
    assert coil.value == pytest.approx(20e-6, rel=RTOL_ONE_OPERATION)  # {2*lv}
    assert second.value == pytest.approx(5e-6, rel=RTOL_ONE_OPERATION)  # {lv/2}
    assert (by_name["r.xa.x2.r1"].value, by_name["r.xa.rg"].b) == (0.5, "gnd2")
    t = np.linspace(0.0, 4e-6, 201)
    mine = _reference(SUBCKTS, list(FLATTENED), t)
    flat = _reference(FLAT, list(FLATTENED.values()), t)
    for k, name in enumerate(FLATTENED):
        np.testing.assert_allclose(mine[k], flat[k], rtol=0, atol=RTOL_EXACT * np.max(np.abs(flat[k])), err_msg=name)


@pytest.mark.ngspice
def test_a_netlist_of_subcircuits_is_checked_vector_by_vector() -> None:
    result = check_text(SUBCKTS, "subckts.cir")
    assert result.reference == ""  # an exact reference, not "no exact reference (sub-circuit ...)"
    assert {v.name for v in result.vectors} == set(FLATTENED)  # every vector ngspice saves, by its own name
    flat = {v.name: v for v in check_text(FLAT, "flat.cir").vectors}
    for vector in result.vectors:  # the same circuit: the same errors, as the same prediction says
        assert vector.predicted_error == pytest.approx(flat[FLATTENED[vector.name]].predicted_error, rel=RTOL_EXACT)
        assert vector.max_abs_error <= PREDICTION_BAND[1] * vector.predicted_error or vector.name == "v(in)"


#: Picofarads, microhenries and a kilohm between them (a resistive node between capacitive ones), and the same
#: circuit with its time stretched a million times (every L and C, and the source's times, times 1e6).
REALISTIC = FLAT.replace("RH m 0 1meg\n", "")  # the sub-circuits' circuit written flat, without its 1 Mohm
STRETCHED = (REALISTIC.replace("PULSE(0 1 0 10n 10n 1u 2u)", "PULSE(0 1 0 10m 10m 1 2)")
             .replace("20u", "20").replace("5u\n", "5\n").replace("1p", "1u").replace("1n\n", "1m\n")
             .replace(".tran 5n 4u", ".tran 5m 4"))


def test_a_realistic_circuits_reference_does_not_depend_on_its_units() -> None:
    """The pencil's rows and columns are equilibrated before its modes are found: with picofarads, microhenries and
    a kilohm the modes were 2e-5 off, and the check refused a consistent initial state.  The response is the same
    as the circuit's whose time is stretched 1e6 times, where every value is of one size."""
    from lcchain.circuit.linear import linear_response

    assert "L2 m x2mid 5\n" in STRETCHED and "C2 out 0 1m\n" in STRETCHED  # the stretch replaced every value
    allowed = allowed_netlist(REALISTIC, "netlist", None)
    response = linear_response(circuit_of(read_cards(allowed), analysis_of(allowed, "netlist")))
    assert response.initial_mismatch() < RTOL_EXACT
    names = ["i(l1)", "i(l2)", "v(m)", "v(gnd2)", "v(out)"]
    t = np.linspace(0.0, 4e-6, 401)
    mine, stretched = _reference(REALISTIC, names, t), _reference(STRETCHED, names, t * 1e6)
    for k, name in enumerate(names):
        scale = np.max(np.abs(stretched[k]))
        np.testing.assert_allclose(mine[k], stretched[k], rtol=0, atol=RTOL_EXACT * scale, err_msg=name)


FUNCS = """values from user functions
.param rs = 50 lval = {10u} cval = 1n
.func res(x) {x*2}
.func tank_c(c, k) = {c*k}
.func twice_res(x) = {res(res(x))/2}
V1 in 0 SIN(0 1 1.5meg) AC 1
R1 in mid {res(rs)/2}
L1 mid 0 {lval}
C1 mid 0 {tank_c(cval, 1.1)}
R2 mid out {twice_res(500)}
C2 out 0 100p
.tran 10n 20u
.end
"""


def test_user_functions_are_called_as_ngspice_calls_them() -> None:
    cards = read_cards(allowed_netlist(FUNCS, "netlist", None))
    values = {card.name: card.value for card in cards.elements if isinstance(card, ElementCard)}
    assert values["r1"] == 50.0 and values["r2"] == 1000.0
    assert values["c1"] == pytest.approx(1.1e-9, rel=RTOL_ONE_OPERATION)
    with pytest.raises(ParameterError, match="takes 2 arguments, not 1"):
        evaluate_expression("tank_c(1)", {}, functions={"tank_c": (("c", "k"), "c*k")})
    with pytest.raises(ParameterError, match="more than"):  # a function that calls itself: ngspice 39 crashes
        evaluate_expression("f(1)", {}, functions={"f": (("x",), "f(x)")})


@pytest.mark.ngspice
def test_a_netlist_of_user_functions_is_checked() -> None:
    result = check_text(FUNCS, "funcs.cir")
    assert result.reference == "" and {"v(out)", "v(mid)", "i(l1)"} <= {v.name for v in result.vectors}
    for vector in result.vectors:
        if vector.name != "v(in)":  # the source's node: exact in both
            assert PREDICTION_BAND[0] <= vector.max_abs_error / vector.predicted_error <= PREDICTION_BAND[1]


@pytest.mark.ngspice
@pytest.mark.parametrize("keywords", ["R=0", "R=1u", "TD=0.5u", "R=1u TD=0.5u", "TD=0.5u R=0"])
def test_a_repeated_or_delayed_pwl_is_the_source_ngspice_runs(keywords: str) -> None:
    """A PWL's ``R=`` (its part from time R repeated after its last point, jumping back to R's value) and ``TD=``
    (its delay, its first value held before): the source's own node is the source, so its reference matches
    ngspice at every time point ngspice took, across three repetitions and their jumps."""
    text = (f"pwl {keywords}\nV1 in 0 PWL(0 0.2 1u 1 2u 1 3u 0 {keywords})\nR1 in out 100\nC1 out 0 1n\n"
            ".tran 10n 10u\n.end\n")
    result = check_text(text, "pwl.cir")
    assert result.reference == ""
    source = next(v for v in result.vectors if v.name == "v(in)")
    assert source.max_abs_error < RTOL_EXACT * source.scale
    assert {v.name for v in result.vectors} == {"v(in)", "v(out)", "i(v1)"}


@pytest.mark.ngspice
def test_a_pwl_repeated_from_no_time_of_its_own_has_no_reference() -> None:
    # ngspice stops the run ("repeat start time value ... does not match any time point"); lcchain says why first
    text = "pwl\nV1 in 0 PWL(0 0.2 1u 1 2u 1 3u 0 R=1.5u)\nR1 in out 100\nC1 out 0 1n\n.tran 10n 10u\n.end\n"
    allowed = allowed_netlist(text, "netlist", None)
    assert "not one of its time points" in str(circuit_of(read_cards(allowed), analysis_of(allowed, "netlist")))


# --------------------------------------------------------------------------- linear controlled sources

CONTROLLED = """controlled sources, each linear
V1 in 0 PULSE(0 1 0 100n 100n 1u 2u)
R1 in a 1k
C1 a 0 1n
E1 b 0 a 0 2
R3 b 0 1k
V2 b c 0
R4 c 0 1k
F1 d 0 V2 3
R5 d 0 100
H1 e 0 V2 500
R6 e 0 100
G1 f 0 a 0 1m
R7 f 0 1k
G2 a 0 a 0 1m
.tran 10n 4u
.end
"""


def test_controlled_sources_are_the_relations_they_state() -> None:
    """E: v(b) = 2 v(a); F: 3 i(V2) from d through it to ground, so v(d) = -300 i(V2); H: v(e) = 500 i(V2); G:
    1 mA/V from f through it, v(f) = -v(a); and G2, a VCCS of a node's own voltage, is a resistor of 1 kohm."""
    t = np.linspace(0.0, 4e-6, 81)
    v_a, v_b, v_d, v_e, v_f, i_v2 = _reference(CONTROLLED, ["v(a)", "v(b)", "v(d)", "v(e)", "v(f)", "i(v2)"], t)
    scale = np.max(np.abs(v_b))
    for found, expected in ((v_b, 2 * v_a), (v_d, -300 * i_v2), (v_e, 500 * i_v2), (v_f, -v_a)):
        np.testing.assert_allclose(found, expected, rtol=0, atol=RTOL_EXACT * scale)
    as_resistor = CONTROLLED.replace("G2 a 0 a 0 1m", "R8 a 0 1k")
    np.testing.assert_allclose(v_a, _reference(as_resistor, ["v(a)"], t)[0], rtol=0, atol=RTOL_EXACT * scale)
    # priced as ngspice solves it: 7 nodes, and the branch currents of V1, V2, E1 and H1
    from lcchain.spice.foreign import foreign_price

    allowed = allowed_netlist(CONTROLLED, "netlist", None)
    assert "11 unknowns" in foreign_price(allowed, analysis_of(allowed, "netlist"), 1).what


@pytest.mark.ngspice
def test_a_netlist_of_controlled_sources_is_checked() -> None:
    result = check_text(CONTROLLED, "controlled.cir")
    assert result.reference == ""
    assert {"i(e1)", "i(h1)", "i(v2)", "v(d)", "v(e)", "v(f)"} <= {v.name for v in result.vectors}
    for vector in result.vectors:
        if vector.name != "v(in)":  # the source's node: exact in both
            assert PREDICTION_BAND[0] <= vector.max_abs_error / vector.predicted_error <= PREDICTION_BAND[1]


@pytest.mark.ngspice
def test_a_nonlinear_controlled_source_runs_with_no_reference(tmp_path: Path, capsys) -> None:
    text = CONTROLLED.replace("E1 b 0 a 0 2", "E1 b 0 poly(1) a 0 0 2 0.1")
    assert "nonlinear form" in str(circuit_of(read_cards(allowed_netlist(text, "netlist", None)),
                                              analysis_of(allowed_netlist(text, "netlist", None), "netlist")))
    path = _write(tmp_path, CONTROLLED)
    assert main(["check", str(path), "--engine", "gnucap"]) == 2  # gnucap's copy writes no controlled source
    assert "the controlled source E1" in capsys.readouterr().err


def test_the_help_of_check_and_batch_names_every_element_the_allow_list_takes(capsys) -> None:
    from lcchain.spice.foreign import ELEMENTS

    for command in ("check", "batch"):
        assert main([command, "--help"]) == 0
        said = " ".join(capsys.readouterr().out.split())
        letters = said.split(" elements")[0].rsplit(":", 1)[-1].split()
        assert set(ELEMENTS) - {"D", "Q", "M", "J", "S", "W", "X"} <= set(letters), (command, letters)


def test_a_zero_argument_function_and_a_sub_circuits_own_function_are_called() -> None:
    text = ("funcs\n.func rval() {2k}\n.subckt att a b\n.func half(x) {x/2}\nR1 a b {half(rval())}\n.ends\n"
            "V1 in 0 SIN(0 1 100k)\nR0 in mid {rval()}\nX1 mid out att\nC1 out 0 1n\n.tran 10n 20u\n.end\n")
    cards = read_cards(allowed_netlist(text, "netlist", None))
    values = {card.name: card.value for card in cards.elements if isinstance(card, ElementCard)}
    assert values["r0"] == 2000.0 and values["r.x1.r1"] == 1000.0


def test_a_sub_circuits_param_stays_in_it_and_a_global_port_is_the_global_node() -> None:
    # a body's .param is the body's (it took the netlist's name and value), and a port named like a .global node is
    # that node, as ngspice 39 expands it (r.x1.r1 between vcc and o, whatever X1's first node)
    text = ("scopes\n.param rv=1k\n.global vcc\n.subckt div a b\n.param rv=10\nR1 a b {rv}\n.ends\n"
            ".subckt stage vcc out\nR2 vcc out 1k\n.ends\nVcc vcc 0 DC 5\nV1 in 0 SIN(0 1 100k)\nR0 in mid {rv}\n"
            "X1 mid out div\nX2 in o stage\nR9 out 0 {rv}\nR8 o 0 1k\n.tran 10n 20u\n.end\n")
    cards = read_cards(allowed_netlist(text, "netlist", None))
    by_name = {card.name: card for card in cards.elements if isinstance(card, ElementCard)}
    assert by_name["r0"].value == 1000.0 and by_name["r9"].value == 1000.0 and by_name["r.x1.r1"].value == 10.0
    assert (by_name["r.x2.r2"].a, by_name["r.x2.r2"].b) == ("vcc", "o")


def test_a_repeated_pwl_drives_the_circuit_as_the_same_pwl_written_out() -> None:
    """Its repetitions are jumps at one time each (never two times a rounding apart, which left the modal solution
    1.7e-4 off with a rounding estimate of 0.05): the response is the one of the waveform written out by hand."""
    circuit = "R1 in a 100\nL1 a b 10u\nC1 b 0 1n\nR2 b 0 1k\n.tran 10n 15u\n.end\n"
    repeated = f"pwl\nV1 in 0 PWL(0 0 1u 1 2u 1 3u 0) R=1u\n{circuit}"
    points = "0 0 1u 1 2u 1 3u 0 " + " ".join(f"{3 + 2 * k}u 1 {4 + 2 * k}u 1 {5 + 2 * k}u 0" for k in range(6))
    written = f"pwl\nV1 in 0 PWL({points})\n{circuit}"
    t = np.array([2.5e-6, 4e-6, 7.5e-6, 10.2e-6, 14.9e-6])  # off the jumps
    mine, theirs = _reference(repeated, ["v(b)", "i(l1)"], t), _reference(written, ["v(b)", "i(l1)"], t)
    np.testing.assert_allclose(mine, theirs, rtol=0, atol=RTOL_EXACT)


@pytest.mark.ngspice
def test_a_capacitor_current_at_a_pulse_corner_is_compared_on_ngspices_side() -> None:
    # the corner at TD + TR + PW is (TD + TR) + PW, as ngspice sums it: 3.5e-6 exactly, where ngspice takes a point
    text = ("corner\nV1 in 0 PULSE(0 1 1u 0.5u 0.5u 2u 6u)\nC1 in 0 1n\nR1 in out 1k\nC2 out 0 1n\n"
            ".tran 10n 8u\n.end\n")
    current = next(v for v in check_text(text, "corner.cir").vectors if v.name == "i(v1)")
    assert current.max_abs_error <= PREDICTION_BAND[1] * current.predicted_error


@pytest.mark.ngspice
def test_an_algebraic_circuit_through_a_large_gain_is_checked() -> None:
    # a capacitor whose voltage H fixes through a gain of 1000: no state at all, and no "inconsistent initial state"
    text = "h gain\nV1 a 0 SIN(0 1 1k)\nR1 a 0 1k\nH1 o 0 V1 1k\nRo o 0 1k\nCo o 0 1u\n.tran 10u 3m\n.end\n"
    result = check_text(text, "hgain.cir")
    assert result.reference == "" and result.states == 0
    output = next(v for v in result.vectors if v.name == "v(o)")
    assert output.max_abs_error < RTOL_EXACT * output.scale


def test_a_node_voltage_in_braces_is_refused_saying_what_it_is(tmp_path: Path, capsys) -> None:
    path = _write(tmp_path, "x\nV1 a 0 SIN(0 1 1k)\nR1 a 0 1k\nE1 o 0 value={v(a)*2}\nRo o 0 1k\n.tran 10u 3m\n.end\n")
    assert main(["check", str(path)]) == 2
    said = capsys.readouterr().err
    assert "not a;" in said and "behavioural value" in said and "Traceback" not in said


@pytest.mark.ngspice
@pytest.mark.parametrize("circuit", [
    "R1 in a 10k\nR2 a b 10k\nC1 a out 1n\nC2 b 0 1n\nE1 out 0 b 0 1\n",  # Sallen-Key, equal parts: a double pole
    "R1 in a 1k\nL1 a 0 1u\nL2 a 0 2u\n",  # coils in a loop: no operating point, phasors all the same
    "C1 in a 1n\nC2 a 0 2n\n",  # a node of capacitors only
    "R2 in c 1meg\nC2 c 0 1p\nE1 e 0 c 0 1e6\nR4 e f 1\nC4 f 0 1m\n",  # ill-conditioned without equilibration
])
def test_an_ac_sweep_needs_no_operating_point_nor_modes(circuit: str, capsys) -> None:
    result = check_text(f"ac\nV1 in 0 DC 0 AC 1\n{circuit}.ac dec 10 1k 1meg\n.end\n", "ac.cir")
    assert result.reference == "" and result.max_rel_error is not None and result.max_rel_error < RTOL_EXACT
    assert "warning" not in capsys.readouterr().err


@pytest.mark.ngspice
def test_a_vector_zero_by_symmetry_has_no_relative_error_of_its_own() -> None:
    # a balanced bridge: the current through VD is rounding (1e-20 A); its scale is a millionth of the largest
    # current, so neither it nor the step suggested for an accuracy is rounding's
    text = ("bridge\nV1 in 0 SIN(0 1 100k)\nR1 in a 1k\nC1 a 0 1.3n\nR2 in b 2k\nC2 b 0 0.65n\nR3 a m 3.3k\nVD m b 0\n"
            ".tran 10n 30u\n.end\n")
    result = check_text(text, "bridge.cir", options=CheckOptions(accuracy=1e-3))
    bridge = next(v for v in result.vectors if v.name == "i(vd)")
    largest = max(v.scale for v in result.vectors if v.unit == "A" and v.scale is not None)
    assert bridge.scale == pytest.approx(1e-6 * largest, rel=RTOL_ONE_OPERATION) and result.passed
    assert result.suggested_step is not None and result.suggested_step > 1e-9


def test_an_ic_of_ground_is_refused() -> None:
    text = "ic\nR0 top 0 100\nC1 top 0 1n\n.ic v(gnd)=1\n.tran 1n 5u uic\n.end\n"
    with pytest.raises(ParameterError, match="nodes other than ground"):
        read_cards(allowed_netlist(text, "netlist", None))


@pytest.mark.ngspice
@pytest.mark.parametrize("pwl", ["PWL(0 0 1u 1 1u 0 2u 0) r=0", "PWL(0 0 1u 1 2u 0) R=-1"])
def test_a_step_written_in_a_repeated_pwl_and_no_repetition_are_ngspices(pwl: str) -> None:
    # a step of the PWL itself is its value before at that time (only a repetition's jump back is the new value);
    # R=-1 repeats nothing
    result = check_text(f"pwl\nV1 in 0 {pwl}\nR1 in x 1k\nC1 x 0 1n\n.tran 10n 10u\n.end\n", "pwl.cir")
    source = next(v for v in result.vectors if v.name == "v(in)")
    assert result.reference == "" and source.max_abs_error < RTOL_EXACT * source.scale
