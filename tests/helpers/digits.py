"""Comparing a computed value with a number printed in the paper.

A printed number stands for every value within half a unit of its last digit.
Rounding the computed value and comparing strings would depend on the last bits
of the computation (a value within 1e-15 of a rounding boundary rounds either
way on another BLAS build); measuring the distance in units of the last printed
digit does not.
"""

from __future__ import annotations

#: Slack beyond half a unit, in units of the last digit: covers the last bits of the computation.
SLACK_UNITS = 1e-6


def last_digit_units(value: float, printed: str) -> float:
    """(value - printed) in units of the printed number's last digit ("0.04551": 1e-5)."""
    decimals = len(printed.split(".")[1]) if "." in printed else 0
    return (value - float(printed)) * 10**decimals


def agrees_with_printed(value: float, printed: str, units: int = 0) -> bool:
    """True when ``printed`` is ``value`` rounded, give or take ``units`` units of its last digit."""
    return abs(last_digit_units(value, printed)) <= units + 0.5 + SLACK_UNITS
