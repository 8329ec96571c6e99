"""A netlist lcchain did not write is checked once: the allow-list's output is a :class:`CheckedText`, the plan
carries it to the runner, and the runner runs it as it is (issue 35: the second check of every run is gone).

The invariant "the text the allow-list checked is the text every transport runs" holds by construction: only
:func:`allowed_netlist` makes a ``CheckedText``, any edit of one is a plain ``str`` (checked again by the runner),
and one sent to another process is checked again where it lands.
"""

from __future__ import annotations

import pickle
from pathlib import Path

import pytest
from helpers.netlists import LADDER, RC_NETLIST

from lcchain.core.errors import ParameterError
from lcchain.spice.foreign import CheckedText, allowed_netlist
from lcchain.spice.job import RunJob
from lcchain.spice.ngspice import runner
from lcchain.studies.plan import batch_plan

ROOT = Path(__file__).resolve().parents[1]

#: Accepted netlists that the check rewrites (a continuation joined, an inline comment and a CRLF dropped, an
#: include inlined) beside ones it returns as they are.
INCLUDED = "* values\n.param rr=1000\n"
REWRITTEN = ("* rewritten\r\nV1 in 0 PULSE(0 1 0 1e-9\n+ 1e-9 1e-6 2e-6)\nR1 in out {rr} ; the load\n"
             ".include values.inc\nC1 out 0 1e-9\n.tran 1e-8 2e-6\n.end\n")


def _accepted(tmp_path: Path) -> list[CheckedText]:
    (tmp_path / "values.inc").write_text(INCLUDED)
    texts = [(LADDER, None), (RC_NETLIST, None), (REWRITTEN, tmp_path)]
    texts += [(path.read_text(), None) for path in sorted((ROOT / "netlists").glob("*.cir"))]
    return [allowed_netlist(text, "netlist", folder, runner.read_include) for text, folder in texts]


def test_only_the_allow_list_makes_one(tmp_path: Path) -> None:
    with pytest.raises(TypeError, match="allowed_netlist"):
        CheckedText(LADDER)
    for checked in _accepted(tmp_path):
        assert type(checked) is CheckedText
        assert type(checked + "") is str
        assert type(checked.replace("\n", "\n", 1)) is str
        assert type(checked[:]) is str


def test_a_checked_text_is_checked_again_where_it_is_unpickled(tmp_path: Path) -> None:
    """The check is idempotent on what it returns, so a pool worker runs the text the plan checked."""
    checked = _accepted(tmp_path)
    assert not any(line.startswith(".include") for line in checked[2].split("\n"))  # rewritten: inlined,
    assert "rr=1000" in checked[2] and "\r" not in checked[2] and "; the load" not in checked[2]  # LF, no comment
    for text in checked:
        again = pickle.loads(pickle.dumps(text))
        assert type(again) is CheckedText
        assert again == text


def test_a_batch_plan_carries_the_checked_text(tmp_path: Path) -> None:
    path = tmp_path / "rc.cir"
    path.write_text(RC_NETLIST)
    spec = batch_plan([path]).tasks[0].spec
    assert type(spec.netlist) is CheckedText
    assert spec.netlist == allowed_netlist(RC_NETLIST, str(path), tmp_path, runner.read_include)


def _refuse_all(text: str, source: str, folder: Path | None, read: object = None) -> CheckedText:
    raise ParameterError(source, "a second check", "no second check of a checked text")


@pytest.mark.ngspice
def test_the_runner_checks_only_what_the_allow_list_did_not(monkeypatch: pytest.MonkeyPatch) -> None:
    checked = allowed_netlist(RC_NETLIST, "netlist", None)
    monkeypatch.setattr(runner, "allowed_netlist", _refuse_all)
    result = runner.run(RunJob(checked, ["v(out)"], 2e-6))  # real ngspice, no second check
    assert result.points > 0
    with pytest.raises(ParameterError, match="second check"):  # any other text is checked
        runner.run(RunJob(str(checked), ["v(out)"], 2e-6))
