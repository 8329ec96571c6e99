"""``lcchain check --engine gnucap``: gnucap against the exact response of the linear circuits of test_check.py.

gnucap runs a netlist lcchain writes from the foreign netlist's numbers (:mod:`lcchain.spice.gnucap_check`); its
vectors come back by the user's names.  Its waveforms are compared here with the independent references of
test_check.py (the state equations written by hand and integrated by ``scipy.linalg.expm``), and its error
with the trapezoidal prediction at its fixed step, within :data:`PREDICTION_BAND` (measured 0.96 .. 1.02 on these
circuits: gnucap's extra steps are at its start and at the sources' corners only).  ngspice's error on the same
netlist is reported beside it.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest
import scipy.linalg
from helpers.tolerances import RTOL_CHECK_AC_GNUCAP
from test_check import (
    BANDPASS,
    BUTTERWORTH,
    PREDICTION_BAND,
    _bandpass_state,
    _butterworth_sine_state,
    _expm_response,
    _pulse_pieces,
    _write,
)

from lcchain.cli.main import main
from lcchain.runs.check import CheckOptions, check_text, source_function
from lcchain.spice.element_values import SourceCard, read_cards
from lcchain.spice.engines import find_engine
from lcchain.spice.foreign import allowed_netlist, analysis_of
from lcchain.spice.gnucap_check import check_netlist, run_check

pytestmark = pytest.mark.gnucap

SINE = BUTTERWORTH.format(drive="SIN(0 1 700 0 0 0)", tstop="5m", tmax="1u")
#: gnucap's waveform against the independent reference, and lcchain's reported error: the same error, up to the
#: two exact references' rounding (1e-13 .. 1e-11 of the scale, test_check.RTOL_EXACT) next to errors ~1e-5.
SAME_ERROR = 1e-3


def _gnucap_waveforms(text: str) -> tuple[np.ndarray, dict[str, np.ndarray]]:
    """gnucap's own run of the netlist lcchain writes from the text (time, vectors by the user's names)."""
    allowed = allowed_netlist(text, "netlist", None)
    analysis = analysis_of(allowed, "netlist")
    cards = read_cards(allowed)
    functions = {c.name: source_function(c, analysis) for c in cards.elements if isinstance(c, SourceCard)}
    written = check_netlist(cards, functions, analysis.step, analysis.stop, 0.0,  # type: ignore[arg-type]
                            ["v(n3)", "i(l2)", "i(v1)"] if "n3" in text else ["v(out)", "i(v1)", "i(l1)"])
    assert all(line.split()[0] in ("V1", "R1", "R2", "L1", "L2", "C1", "C2", "C3") or line.startswith((".", "*"))
               for line in written.text.splitlines())  # every card written here, by lcchain's names
    run = run_check(written, analysis.stop, simulator=find_engine("gnucap"), timeout=60)
    return run.time, dict(run.vectors)


def _stepped_response(A: np.ndarray, b: np.ndarray, pieces: list[tuple[float, float, float]], t: np.ndarray
                      ) -> np.ndarray:
    """test_check._expm_response on a grid of equal steps whose pieces start on it: expm of one step, applied
    in turn inside each piece (the same exact solution, faster than an expm per point)."""
    h = float(t[1] - t[0])
    n = A.shape[0]
    M = np.zeros((n + 2, n + 2))
    M[:n, :n], M[:n, n], M[n, n + 1] = A, b, 1.0
    step = scipy.linalg.expm(M * h)
    out = np.zeros((n, t.size))
    starts = [p[0] for p in pieces] + [math.inf]
    ends = _expm_response(A, b, pieces, np.array(starts[1:-1])) if len(pieces) > 1 else np.zeros((n, 0))
    for k, (start, value, slope) in enumerate(pieces):
        inside = np.flatnonzero((t >= start - h / 2) & (t < starts[k + 1] - h / 2))
        if inside.size:
            x = np.zeros(n) if k == 0 else ends[:, k - 1]
            z = scipy.linalg.expm(M * (t[inside[0]] - start)) @ np.concatenate([x, [value, slope]])
            for i in inside:
                out[:, i] = z[:n]
                z = step @ z
    return out


def _by_name(result: object) -> dict[str, object]:
    return {v.name: v for v in result.vectors}  # type: ignore[attr-defined]


def test_bandpass_pulse_in_gnucap_errs_as_predicted() -> None:
    gnucap = check_text(BANDPASS, "bandpass.cir", options=CheckOptions(engine="gnucap"))
    ngspice = check_text(BANDPASS, "bandpass.cir", options=CheckOptions(engine="ngspice"))
    assert gnucap.engine == "gnucap" and gnucap.reference == "" and gnucap.run_step == pytest.approx(1e-7)
    mine, theirs = _by_name(gnucap), _by_name(ngspice)
    assert set(mine) == set(theirs) == {"v(in)", "v(a)", "v(b)", "v(out)", "i(v1)", "i(l1)"}
    for name, vector in mine.items():
        if name != "v(in)":  # the source's node: exact in both
            for v in (vector, theirs[name]):
                assert PREDICTION_BAND[0] <= v.max_abs_error / v.predicted_error <= PREDICTION_BAND[1], name
    # gnucap's waveform against the state equations' exponential (i = i_L through V1 - R1 - L1 - C1 - R2)
    t, vectors = _gnucap_waveforms(BANDPASS)
    A, b = _bandpass_state()
    x = _stepped_response(A, b, _pulse_pieces(0, 1, 1e-6, 20e-6, 1e-6, 100e-6, 200e-6), t)
    for name, exact in (("i(l1)", x[0]), ("v(out)", 10.0 * x[0]), ("i(v1)", -x[0])):  # SPICE's sign for i(v1)
        error = float(np.max(np.abs(vectors[name] - exact)))
        assert error == pytest.approx(mine[name].max_abs_error, rel=SAME_ERROR), name


def test_butterworth_sine_in_gnucap_errs_as_predicted(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    path = _write(tmp_path, SINE, "butterworth.cir")
    assert main(["check", str(path), "--engine", "gnucap", "--json"]) == 0
    gnucap = json.loads(capsys.readouterr().out)
    assert main(["check", str(path), "--json"]) == 0
    ngspice = json.loads(capsys.readouterr().out)
    assert gnucap["engine"] == "gnucap" and ngspice["engine"] == "ngspice"
    names = {v["name"] for v in gnucap["vectors"]}
    assert names == {v["name"] for v in ngspice["vectors"]} == {"v(n1)", "v(n2)", "v(n3)", "i(l2)", "i(l4)",
                                                                 "i(v1)"}
    for data in (gnucap, ngspice):
        assert PREDICTION_BAND[0] <= data["max_abs_error"] / data["predicted_error"] <= PREDICTION_BAND[1]
    # gnucap's waveforms against the state equations' exponential with the sine's generator
    t, vectors = _gnucap_waveforms(SINE)
    M, z0 = _butterworth_sine_state(700)
    step = scipy.linalg.expm(M * (t[1] - t[0]))
    z = scipy.linalg.expm(M * t[0]) @ z0
    x = np.empty((7, t.size))
    for k in range(t.size):  # gnucap's times are multiples of its step: expm of one step, applied in turn
        x[:, k] = z
        z = step @ z
    reported = {v["name"]: v["max_abs_error"] for v in gnucap["vectors"]}
    for name, exact in (("v(n3)", x[4]), ("i(l2)", x[1]), ("i(v1)", -(x[5] - x[0]))):  # RS = 1 ohm
        error = float(np.max(np.abs(vectors[name] - exact)))
        assert error == pytest.approx(reported[name], rel=SAME_ERROR), name


@pytest.mark.parametrize(("change", "named"), [
    (("SIN(0 1 700 0 0 0)", "SIN(0 1 700 0 0 30)"), "SIN with a phase"),
    ((".tran 1u 5m 0 1u", ".tran 1u 5m 0 1u uic"), "uic"),
    (("RL n3 0 {r0}", "RL n3 0 {r0}\n.ic v(n3)=0.1"), ".ic"),
    (("RL n3 0 {r0}", "RL n3 0 {r0}\n.options method=gear"), "method=gear"),
    (("C5 n3 0 {0.618/(wc*r0)}", "C5 n3 0 {0.618/(wc*r0)} ic=0.1"), "ic= on C5"),
    ((".tran 1u 5m 0 1u", ".tran 1u 5m 1m 1u"), "start time"),
    ((".tran 1u 5m 0 1u", ".ac dec 10 10 10k"), "an AC phase"),
    (("RL n3 0 {r0}", "RL n3 0 {r0}\nD1 n3 0 dmod\n.model dmod d"), "no exact reference"),
])
def test_what_gnucap_cannot_run_exactly_is_refused_in_one_line(tmp_path: Path, capsys: pytest.CaptureFixture[str],
                                                                 change: tuple[str, str], named: str) -> None:
    text = SINE.replace(*change)
    assert text != SINE
    path = _write(tmp_path, text.replace("SIN(0 1 700 0 0 0)", "DC 0 AC 1 30") if "AC" in named else text)
    assert main(["check", str(path), "--engine", "gnucap"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and named in err, err


def test_ac_sweep_in_gnucap_is_the_transfer_function(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """gnucap's phasors at its own frequencies against 1 / Z of the band-pass, written here."""
    text = BANDPASS.replace("PULSE(0 1 0 1u 1u 20u 100u)", "DC 0 AC 1").replace(".tran 0.1u 200u 0 0.1u",
                                                                                 ".ac dec 20 100 1meg")
    allowed = allowed_netlist(text, "netlist", None)
    written = check_netlist(read_cards(allowed), {}, 0.0, 0.0, 0.0, ["v(out)", "i(v1)"], sweep=("dec", 20, 100.0,
                                                                                                  1e6))
    run = run_check(written, 0.0, simulator=find_engine("gnucap"), timeout=60)
    f = run.time
    assert f.size == 81 and f[0] == pytest.approx(100) and f[-1] == pytest.approx(1e6)
    s = 2j * np.pi * f
    current = 1.0 / (60.0 + s * 1e-3 + 1 / (s * 100e-9))
    np.testing.assert_allclose(run.vectors["v(out)"], 10.0 * current, rtol=RTOL_CHECK_AC_GNUCAP)
    np.testing.assert_allclose(run.vectors["i(v1)"], -current, rtol=RTOL_CHECK_AC_GNUCAP)  # SPICE's sign
    assert main(["check", str(_write(tmp_path, text)), "--engine", "gnucap", "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["engine"] == "gnucap" and data["analysis"] == "ac" and data["points"] == 81
    assert data["max_rel_error"] < RTOL_CHECK_AC_GNUCAP and data["predicted_error"] is None
