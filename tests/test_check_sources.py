"""``lcchain check``'s exact reference of a source reads its arguments as ngspice 39 does (vsrcload.c): a time or
frequency of 0 is ngspice's default, as when it is left out, and a PULSE whose period is shorter than the pulse
is cut short at each period (found by a review of netlists as engineers write them).

The source drives its node against ground, so that node's saved voltage is the source's own value: its error is
rounding, whatever the step, when lcchain reads the source as ngspice does (before: 0.33 V on ``EXP(0 1 0 5u 20u
5u)``, whose TD1 of 0 is TSTEP; 1 V on ``SIN(0 1 0)``, whose FREQ of 0 is 1/TSTOP, and on ``PULSE(0 1 0 1u 1u 0
50u)``, whose PW of 0 is TSTOP, cut every 50 us).
"""

from __future__ import annotations

import pytest

from lcchain.runs.check import CheckOptions, check_text

#: The source node's error against its scale: rounding only (measured 1e-14 .. 1e-16).
RTOL_SOURCE_NODE = 1e-9

CIRCUIT = """a source's defaults: {source}
V1 in 0 {source}
R1 in a 1k
C1 a 0 10n
.tran 2u 100u 0 0.1u
.end
"""


@pytest.mark.ngspice
@pytest.mark.parametrize("source", [
    "EXP(0 1 0 5u 20u 5u)",  # TD1 = 0: TSTEP
    "EXP(0 1 0 5u)",  # TD1 = 0, TD2 left out: TD1 + TSTEP
    "EXP(0 1)",  # every time left out: TSTEP
    "SIN(0 1 0)",  # FREQ = 0: 1 / TSTOP
    "SIN(0 1 0 10u 0 30)",
    "PULSE(0 1 0 1u 1u 0 50u)",  # PW = 0: TSTOP, longer than PER: each pulse cut short
    "PULSE(0 1 5u 1u 1u 30u 20u)",  # a period shorter than the pulse
    "PULSE(0 1 0 0 0 20u 0)",  # TR = TF = 0: TSTEP; PER = 0: one pulse
])
def test_the_source_node_follows_the_source_as_ngspice_reads_it(source: str) -> None:
    result = check_text(CIRCUIT.format(source=source), options=CheckOptions())
    node = next(vector for vector in result.vectors if vector.name == "v(in)")
    assert node.max_abs_error is not None and node.scale
    assert node.max_abs_error <= RTOL_SOURCE_NODE * node.scale, (source, node)


@pytest.mark.ngspice
def test_a_pole_at_minus_two_over_the_step_has_a_prediction() -> None:
    """RC = 1 us at a step of 2 us: the trapezoidal rule takes that mode to 0 in one step (its map's log is -inf);
    the step search read NaN from it and ended in a traceback, losing the comparison."""
    text = "RC at -2/h\nV1 in 0 PULSE(0 1 0 1u 1u 1m 2m)\nR1 in a 1\nC1 a 0 1u\n.tran 2u 1m 0 2u\n.end\n"
    result = check_text(text, options=CheckOptions(accuracy=1e-3))
    assert result.predicted_error is not None and result.suggested_step is not None
    assert all(vector.max_abs_error is not None for vector in result.vectors)


@pytest.mark.ngspice
def test_interpolated_output_is_noted_and_trapezoidal_is_trap() -> None:
    """.options interp puts ngspice's output on the TSTEP grid, an error the prediction does not hold (4500 times
    it, measured): said in a note; method=trapezoidal is ngspice's other name for trap, and is modelled as such."""
    base = "RC\nV1 in 0 PULSE(0 1 0 1u 1u 1m 2m)\nR1 in a 1k\nC1 a 0 1n\n.tran 2u 100u\n{options}\n.end\n"
    noted = check_text(base.format(options=".options interp"), options=CheckOptions())
    assert any("interp" in note for note in noted.notes)
    named = check_text(base.format(options=".options method=trapezoidal"), options=CheckOptions())
    assert named.method == "trap" and "no model" not in named.prediction


def test_a_value_with_digits_after_its_scale_is_said_as_ngspice_reads_it() -> None:
    """4k7 (a European 4.7k) is 4k to ngspice, which ignores what follows its scale: check has no reference for
    it and says why, and how to write 4.7k (it said "a .func call, a model name...")."""
    from lcchain.spice.element_values import OtherCard, read_cards

    cards = read_cards("r\nV1 in 0 1\nR1 in a 4k7\nC1 a 0 1n\n.tran 1u 20u\n.end\n")
    (resistor,) = [card for card in cards.elements if isinstance(card, OtherCard)]
    assert "ngspice reads as 4k" in resistor.why and "4.7k" in resistor.why
