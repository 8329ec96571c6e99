"""``lcchain sweep --netlist FILE --vary NAME=...``: one's own netlist's ``.param`` and element values varied over
lists, grids and seeded distributions (issue 31, item 4), each variant checked, priced and run as a batch's
netlist, into the same store, on any executor.

Expected values are the closed forms of a first-order RC low-pass (any circuits text, e.g. Horowitz & Hill,
*The Art of Electronics*, 3rd ed., sec. 1.4): after a unit step v(t) = 1 - exp(-t / RC), so the 10-90 % rise
time is RC ln 9 and v(t0) = 1 - exp(-t0 / RC).  The distributions' moments are the textbook ones: a normal's
sample mean has the standard error sigma / sqrt(n); a uniform on [a, b] has mean (a + b) / 2 and standard
deviation (b - a) / sqrt(12).
"""

from __future__ import annotations

import csv
import io
import json
import math
import warnings
from pathlib import Path

import pytest
from helpers.tolerances import MAX_STANDARD_ERRORS, RTOL_MEASURE_TRAN, RTOL_SAMPLE_STD

from lcchain.cli import main
from lcchain.core.errors import ParameterError
from lcchain.spice.foreign import allowed_netlist
from lcchain.spice.variants import find_target, netlist_targets, with_values
from lcchain.studies.options import RunOptions
from lcchain.studies.plan import NetlistSweep, UnphysicalValueWarning, netlist_sweep_plan
from lcchain.studies.run import run_plan
from lcchain.studies.store import Store
from lcchain.studies.vary import parse_netlist_vary, variant_points

C = 2e-6  # farad: with R from 1k to 4.7k, RC from 2 to 9.4 ms, stepped at RC / 2000 or finer (RTOL_MEASURE_TRAN)
T0 = 1e-3  # s: where v_at measures

# R1's value field on a continuation line, C1's value a .param's, an inline comment, an included .param
RC = """\
RC step, R1 varied
.include parts.inc
V1 in 0 PULSE(0 1 0 1n 1n 1 2)
R1 in out
+ 1k ; the value varied
C1 out 0 {cv}
.tran 1u 25m
.meas tran trise trig v(out) val=0.1 rise=1 targ v(out) val=0.9 rise=1
.meas tran v_at FIND v(out) AT=1m
.end
"""
PARTS = ".param cv = 2u\n.param unused = {cv * 2}\n"


def _netlist(folder: Path, text: str = RC) -> Path:
    (folder / "parts.inc").write_text(PARTS, encoding="utf-8")
    path = folder / "rc.cir"
    path.write_text(text, encoding="utf-8")
    return path


def _checked(folder: Path) -> str:
    path = _netlist(folder)
    from lcchain.spice.result import read_include

    return allowed_netlist(path.read_text(), str(path), folder, read_include)


# ------------------------------------------------------------------ the variants' text


def test_a_variant_replaces_exactly_the_value_and_passes_the_allow_list_unchanged(tmp_path: Path) -> None:
    base = _checked(tmp_path)
    targets = netlist_targets(base)
    r1, cv = find_target(targets, "r1"), find_target(targets, "CV")
    variant = with_values(base, {r1: 2200.0, cv: 3.3e-6})
    changed = [(a, b) for a, b in zip(base.split("\n"), variant.split("\n"), strict=True) if a != b]
    assert changed == [(".param cv = 2u", ".param cv = 3.3e-06"), ("R1 in out 1k", "R1 in out 2200.0")]
    assert allowed_netlist(variant, "rc.cir", None) == variant  # the checked text is the text that runs


def test_one_of_several_assignments_a_coupling_and_a_title_that_looks_like_an_element() -> None:
    text = ("R1 is the title, not the element\n.param a=1 b = {a*2}   c=3\nr1 x 0 1k\nL1 x y 1u\nL2 y 0 1u\n"
            "K1 L1 L2 0.5\n.tran 1u 1m\n.end\n")
    base = allowed_netlist(text, "t.cir", None)
    targets = netlist_targets(base)
    variant = with_values(base, {find_target(targets, name): value
                                 for name, value in (("b", 5), ("a", -1), ("k1", 0.25), ("R1", 2e3))})
    assert variant == text.replace("a=1 b = {a*2}", "a=-1.0 b = 5.0").replace("0 1k", "0 2000.0").replace(
        "L2 0.5", "L2 0.25")
    assert allowed_netlist(variant, "t.cir", None) == variant


def test_a_value_cannot_inject_anything(tmp_path: Path) -> None:
    base = _checked(tmp_path)
    r1 = find_target(netlist_targets(base), "R1")
    for bad in (math.inf, math.nan):
        with pytest.raises(ParameterError, match="finite"):
            with_values(base, {r1: bad})
    with pytest.raises(ParameterError, match="--vary"):
        parse_netlist_vary("R1=1k\n.control")


def test_an_element_whose_value_is_an_expression_names_the_param_to_vary(tmp_path: Path) -> None:
    with pytest.raises(ParameterError, match=r"C1's value is the expression \{cv\}: vary the \.param it uses "
                                             r"instead: cv"):
        find_target(netlist_targets(_checked(tmp_path)), "C1", shown="C1=1u")


def test_a_name_the_netlist_lacks_is_refused_listing_what_it_has(tmp_path: Path) -> None:
    with pytest.raises(ParameterError) as refused:
        find_target(netlist_targets(_checked(tmp_path)), "R2", shown="R2=1k")
    assert "defines no R2" in str(refused.value)
    assert ".param names: cv, unused" in str(refused.value) and "elements: C1, R1" in str(refused.value)
    with pytest.raises(ParameterError, match="V1 is a V element"):
        find_target(netlist_targets(_checked(tmp_path)), "v1")


# ------------------------------------------------------------------ the values


def test_lists_and_grids_are_exact_spice_numbers() -> None:
    assert parse_netlist_vary("R1=1k,2.2k, 4.7k").values == (1000.0, 2200.0, 4700.0)  # 2.2 * 1e3 is not 2200.0
    assert parse_netlist_vary("C1=10n,1meg,25mil").values == (1e-8, 1e6, 25 * 25.4e-6)
    assert parse_netlist_vary("R1=lin:1k:10k:10").values == pytest.approx([1e3 * k for k in range(1, 11)])
    assert parse_netlist_vary("R1=log:1k:1meg:4").values == pytest.approx([1e3, 1e4, 1e5, 1e6])
    points = variant_points([parse_netlist_vary("R1=1k,2k"), parse_netlist_vary("rv=1,2,3")])
    assert points == [{"R1": r, "rv": v} for r in (1e3, 2e3) for v in (1.0, 2.0, 3.0)]
    assert variant_points([parse_netlist_vary("status=1,2")]) == [{"vary_status": 1.0}, {"vary_status": 2.0}]


def test_draws_are_seeded_and_independent_of_the_other_options() -> None:
    normal, uniform = parse_netlist_vary("C2=normal:10n:5%"), parse_netlist_vary("rv=uniform:1k:2k")
    first = variant_points([normal, uniform], samples=5, seed=3)
    assert first == variant_points([normal, uniform], samples=5, seed=3)
    # the same C2 draws whatever else varies, in whatever order, and however many samples
    alone = variant_points([parse_netlist_vary("R1=1k,2k"), normal], samples=8, seed=3)
    assert [p["C2"] for p in first] == [p["C2"] for p in alone[:5]] == [p["C2"] for p in alone[8:13]]
    assert [p["C2"] for p in first] != [p["C2"] for p in variant_points([normal], samples=5, seed=4)]
    assert [p["sample"] for p in first] == [1, 2, 3, 4, 5]


def test_draws_follow_their_distribution() -> None:
    n = 4000
    normal = [p["C2"] for p in variant_points([parse_netlist_vary("C2=normal:10n:5%")], samples=n, seed=1)]
    mean = sum(normal) / n
    std = math.sqrt(sum((v - mean) ** 2 for v in normal) / (n - 1))
    sigma = 0.5e-9  # 5 % of 10 nF
    assert abs(mean - 10e-9) < MAX_STANDARD_ERRORS * sigma / math.sqrt(n)
    assert std == pytest.approx(sigma, rel=RTOL_SAMPLE_STD)
    flat = [p["C2"] for p in variant_points([parse_netlist_vary("C2=tolerance:10n:5%")], samples=n, seed=1)]
    assert min(flat) >= 9.5e-9 and max(flat) <= 10.5e-9
    width = 1e-9  # 9.5 nF .. 10.5 nF, uniform: sigma = width / sqrt(12)
    assert abs(sum(flat) / n - 10e-9) < MAX_STANDARD_ERRORS * (width / math.sqrt(12)) / math.sqrt(n)


@pytest.mark.parametrize(("argv", "says"), [
    (["--vary", "R1=1k,,2k"], "value 2 of 3 is empty"),
    (["--vary", "R1=lin:1k:2k:1"], "N an integer from 2"),
    (["--vary", "R1=log:0:1k:3"], "0 < START"),
    (["--vary", "R1=gauss:1k:5%"], "one of lin | log | normal | uniform | tolerance"),
    (["--vary", "R1=normal:1k"], "normal:MEAN:SIGMA (2 values"),
    (["--vary", "R1=1M"], "write meg for mega"),
    (["--vary", "R1=tolerance:1k:5"], "in percent"),
    (["--vary", "R1=normal:1k:5%"], "--samples N with a distribution"),
    (["--vary", "R1=1k", "--samples", "3"], "a --vary with a distribution"),
    (["--vary", "R1=1k", "--vary", "r1=2k"], "each name once"),
    (["--vary", "R1=1k,1000,2k"], "each value once (value 2, 1000, is value 1, 1k: the same run)"),
    (["--vary", "R7=1k"], "defines no R7: it has .param names: cv, unused; C, K, L, R elements: C1, R1"),
    (["--vary", "C1=1u"], "vary the .param it uses instead: cv"),
    (["--vary", "R1=1k", "--N", "5"], "nothing with --netlist"),
    (["--vary", "R1=1k", "--tolerance", "0.05"], "nothing with --netlist"),
    (["--vary", "R1=1k", "--L0", "-5"], "--L0 = -5.0 is not allowed: expected nothing with --netlist"),
    (["--vary", "R1=1k", "--C0", "1e-9"], "--C0 = 1e-09 is not allowed: expected nothing with --netlist"),
    ([], "at least one --vary"),
])
def test_a_bad_vary_is_one_line_naming_the_option_and_nothing_is_stored(tmp_path: Path, capsys, argv: list[str],
                                                                      says: str) -> None:
    path = _netlist(tmp_path)
    store = tmp_path / "s.sqlite"
    assert main(["sweep", "--netlist", str(path), *argv, "--store", str(store)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and says in err and "Traceback" not in err, err
    assert err.startswith("lcchain: --") and "is not allowed" in err
    assert not store.exists()


# ------------------------------------------------------------------ run in ngspice


@pytest.mark.ngspice
def test_a_sweep_of_r_stores_each_variant_with_its_value_and_closed_form_measurements(tmp_path: Path,
                                                                                    capsys) -> None:
    path = _netlist(tmp_path)
    store = tmp_path / "s.sqlite"
    argv = ["sweep", "--netlist", str(path), "--vary", "R1=1k,2.2k,4.7k", "--store", str(store),
            "--executor", "serial"]
    assert main([*argv, "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["ok"] == 3
    assert main(["results", str(store), "--json"]) == 0
    runs = json.loads(capsys.readouterr().out)
    assert [run["params"] for run in runs] == [{"R1": 1e3}, {"R1": 2.2e3}, {"R1": 4.7e3}]
    for run in runs:
        rc = run["params"]["R1"] * C
        assert run["measurements"]["trise"] == pytest.approx(rc * math.log(9.0), rel=RTOL_MEASURE_TRAN)
        assert run["measurements"]["v_at"] == pytest.approx(1.0 - math.exp(-T0 / rc), rel=RTOL_MEASURE_TRAN)
    assert main(["results", str(store), "--csv"]) == 0
    rows = list(csv.DictReader(io.StringIO(capsys.readouterr().out)))
    assert [float(row["R1"]) for row in rows] == [1e3, 2.2e3, 4.7e3] and "trise" in rows[0]
    assert main(["results", str(store), "--summary", "--metric", "trise", "--json"]) == 0
    groups = json.loads(capsys.readouterr().out)
    assert [group["params"] for group in groups] == [{"R1": 1e3}, {"R1": 2.2e3}, {"R1": 4.7e3}]
    assert main([*argv, "--json"]) == 0  # the same command resumes: nothing runs again
    again = json.loads(capsys.readouterr().out)
    assert (again["skipped"], again["ran"], again["ok"]) == (3, 0, 3)


@pytest.mark.ngspice
def test_serial_and_pool_give_the_same_runs_and_digests_and_draws(tmp_path: Path) -> None:
    path = _netlist(tmp_path)
    varies = [parse_netlist_vary("R1=1k,2.2k"), parse_netlist_vary("cv=normal:2u:5%")]
    digests = {}
    for executor, workers in (("serial", 1), ("process", 2)):
        plan = netlist_sweep_plan(path, varies, NetlistSweep(samples=3, seed=11))
        store = tmp_path / f"{executor}.sqlite"
        assert run_plan(plan, store, RunOptions(executor=executor, workers=workers)).ok == 6
        with Store(store, "read") as opened:
            digests[executor] = [(run.params, run.digest) for run in opened.runs()]
    assert digests["serial"] == digests["process"]
    assert len({digest for _, digest in digests["serial"]}) == 6 and all(d for _, d in digests["serial"])


@pytest.mark.ngspice
@pytest.mark.slow  # a local cluster's start: 2.5 to 6 s here
def test_a_dask_cluster_gives_the_serial_digests(tmp_path: Path) -> None:
    pytest.importorskip("distributed")
    path = _netlist(tmp_path)
    varies = [parse_netlist_vary("R1=1k,2.2k,4.7k")]
    digests = {}
    for executor in ("serial", "dask"):
        store = tmp_path / f"{executor}.sqlite"
        assert run_plan(netlist_sweep_plan(path, varies), store, RunOptions(executor=executor, workers=2)).ok == 3
        with Store(store, "read") as opened:
            digests[executor] = [(run.params, run.digest) for run in opened.runs()]
    assert digests["serial"] == digests["dask"] and all(d for _, d in digests["dask"])


@pytest.mark.ngspice
def test_drawn_values_are_stored_and_grouped_as_samples(tmp_path: Path, capsys) -> None:
    path = _netlist(tmp_path, RC.replace(".tran 1u 25m", ".tran 1u 2m").replace(
        ".meas tran trise trig v(out) val=0.1 rise=1 targ v(out) val=0.9 rise=1\n", ""))
    store = tmp_path / "mc.sqlite"
    n, sigma = 12, 0.1e-6
    argv = ["sweep", "--netlist", str(path), "--vary", "R1=1k,2k", "--vary", "cv=normal:2u:5%", "--samples", str(n),
            "--seed", "5", "--store", str(store), "--workers", "2", "--json"]
    assert main(argv) == 0
    assert json.loads(capsys.readouterr().out)["ok"] == 2 * n
    assert main(argv) == 0  # drawn again, the same values: the same plan, resumed, runs nothing
    assert json.loads(capsys.readouterr().out)["ran"] == 0
    with Store(store, "read") as opened:
        runs = opened.runs()
    drawn = [run.params["cv"] for run in runs]
    assert drawn[:n] == drawn[n:]  # the same draws at each R
    assert drawn[:n] == [p["cv"] for p in variant_points([parse_netlist_vary("cv=normal:2u:5%")], samples=n,
                                                         seed=5)]
    assert abs(sum(drawn[:n]) / n - 2e-6) < MAX_STANDARD_ERRORS * sigma / math.sqrt(n)
    for run in runs:
        rc = run.params["R1"] * run.params["cv"]
        assert run.measurements["v_at"] == pytest.approx(1.0 - math.exp(-T0 / rc), rel=RTOL_MEASURE_TRAN)
    assert main(["results", str(store), "--summary", "--metric", "v_at", "--json"]) == 0
    groups = json.loads(capsys.readouterr().out)
    assert [(group["params"], group["n"]) for group in groups] == [({"R1": 1e3}, n), ({"R1": 2e3}, n)]
    pd = pytest.importorskip("pandas")
    with Store(store, "read") as opened:
        frame = opened.to_dataframe()
    assert isinstance(frame, pd.DataFrame)
    assert {"R1", "sample", "cv", "v_at"} <= set(frame.columns) and len(frame) == 2 * n
    pytest.importorskip("xarray")
    with Store(store, "read") as opened:
        dataset = opened.to_xarray()
    assert dict(dataset.sizes) == {"R1": 2, "sample": n} and "cv" in dataset.coords  # drawn: along the samples


@pytest.mark.ngspice
def test_a_variant_beyond_the_budget_is_refused_and_the_others_run(tmp_path: Path, capsys) -> None:
    """A lossless LC ringing at 5 GHz is priced at its fast dynamics (lcchain.spice.pricing): beyond a minute."""
    path = tmp_path / "lc.cir"
    path.write_text("LC ring\nV1 in 0 PULSE(0 1 0 1n 1n 1 2)\nR1 in a 1\nL1 a out 1m\nC1 out 0 1u\n.tran 1u 1m\n"
                    ".meas tran vmax MAX v(out)\n.end\n", encoding="utf-8")
    store = tmp_path / "lc.sqlite"
    argv = ["sweep", "--netlist", str(path), "--vary", "L1=1m,1f", "--store", str(store), "--max-time", "60",
            "--json"]
    assert main(argv) == 1
    summary = json.loads(capsys.readouterr().out)
    assert (summary["ok"], summary["refused"]) == (1, 1)
    assert summary["refusals"][0]["netlist"] == "lc.cir L1=1e-15" and "--max-time" in summary["refusals"][0]["reason"]
    assert main(argv) == 1
    again = json.loads(capsys.readouterr().out)
    assert (again["ran"], again["skipped"]) == (0, 2)  # neither run nor refused twice


def test_a_refused_netlist_is_not_offered_batchs_allow_control(tmp_path: Path, capsys) -> None:
    """A sweep has no --allow-control: its refusal says what the allow-list refused, without batch's hint."""
    netlist = _netlist(tmp_path, RC.replace(".end\n", ".control\nrun\n.endc\n.end\n"))
    code = main(["sweep", "--netlist", str(netlist), "--vary", "R1=1k,2k", "--store", str(tmp_path / "s.sqlite")])
    err = capsys.readouterr().err
    assert code == 2 and ".control" in err and "--allow-control" not in err and "allow-list accepts" in err
    assert not (tmp_path / "s.sqlite").exists()


@pytest.mark.ngspice
def test_a_summary_axis_named_as_a_statistic_keeps_its_own_column(tmp_path: Path, capsys) -> None:
    """A .param called mean, varied: its summary column is vary_mean, so that a CSV reader keeps both."""
    path = tmp_path / "rc.cir"
    path.write_text("RC step\n.param mean = 1k\nV1 in 0 PULSE(0 1 0 1n 1n 1 2)\nR1 in out {mean}\nC1 out 0 1u\n"
                    ".tran 10u 2m\n.meas tran v_at find v(out) at=1m\n.end\n")
    store = str(tmp_path / "s.sqlite")
    assert main(["sweep", "--netlist", str(path), "--vary", "mean=1k,2k", "--store", store]) == 0
    capsys.readouterr()
    assert main(["results", store, "--summary", "--metric", "v_at", "--csv"]) == 0
    rows = list(csv.DictReader(io.StringIO(capsys.readouterr().out)))
    assert [(float(row["vary_mean"]), int(row["n"])) for row in rows] == [(1e3, 1), (2e3, 1)]
    assert float(rows[0]["mean"]) == pytest.approx(1.0 - math.exp(-1.0), rel=RTOL_MEASURE_TRAN)


def test_a_sweep_that_gives_an_element_a_value_no_part_has_warns_and_plans_it(tmp_path: Path) -> None:
    """ngspice runs a resistor of -1k as written (a model's tool): the sweep plans it, and says so once; a .param
    (cv) may be any number, and a grid of real values says nothing."""
    path = _netlist(tmp_path)
    with pytest.warns(UnphysicalValueWarning, match=r"--vary R1=lin:-1k:1k:3: 2 of 3 runs give R1 a value no real "
                      r"part has \(a value > 0 is, and not -1000\)"):
        plan = netlist_sweep_plan(path, [parse_netlist_vary("R1=lin:-1k:1k:3")], NetlistSweep(engine_version=lambda: "39"))
    assert len(plan.tasks) == 3
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        netlist_sweep_plan(path, [parse_netlist_vary("R1=lin:1k:2k:3"), parse_netlist_vary("cv=-1u,1u")],
                           NetlistSweep(engine_version=lambda: "39"))


def test_an_element_inside_a_subckt_is_named_so_and_its_advice_holds() -> None:
    """R1 in a .subckt, valued by the sub-circuit's parameter r: the advice was to vary r, then r was no name of the
    netlist; now both refusals say R1 is the sub-circuit's, whose parameters its X lines set."""
    from lcchain.spice.variants import find_target, netlist_targets

    text = allowed_netlist("subckt\n.subckt rcstage a b params: r=1k\nR1 a b {r}\nC1 b 0 1n\n.ends\n"
                           "V1 in 0 PULSE(0 1 0 1n 1n 20u 40u)\nX1 in out rcstage r=2k\n.tran 20n 60u\n.end\n",
                           "netlist", None)
    targets = netlist_targets(text)
    with pytest.raises(ParameterError, match=r"it is in \.subckt rcstage, whose parameters \(r\) its X lines set"):
        find_target(targets, "R1")
    with pytest.raises(ParameterError, match=r"R1 \(in \.subckt rcstage\)"):
        find_target(targets, "r")
