"""What ``lcchain sweep --netlist FILE --vary NAME=SPEC`` varies: lists, grids and seeded distributions of values.

A ``--vary`` names a ``.param`` or an element of the netlist (:mod:`lcchain.spice.variants`) and its values:

=============================  ==================================================================================
``1k,2.2k,4.7k``               these values (SPICE numbers: ``f p n u m k meg g t`` and ``mil``; ``M`` is refused:
                               SPICE reads it as milli, write ``meg`` or ``m``); one value sets it for every run
``lin:START:STOP:N``           N values evenly spaced, both ends included
``log:START:STOP:N``           N values in geometric progression (``0 < START, STOP``), both ends included
``normal:MEAN:SIGMA``          drawn from a normal distribution; SIGMA a number or ``P%`` of ``|MEAN|``
``uniform:LO:HI``              drawn uniformly in [LO, HI]
``tolerance:NOMINAL:P%``       drawn uniformly in NOMINAL x (1 - P/100, 1 + P/100), ``0 <= P < 100``
=============================  ==================================================================================

The lists and grids of several ``--vary`` make their product; the distributions are drawn ``--samples`` times,
and each sample k is a run at every point of that product (the same draws at every point: a comparison across
the product's values is not blurred by different draws).  The draws are made here, in the driver, before
anything runs: sample k of a name draws from the k-th child of ``SeedSequence([seed, the name's hash])``, so
the same seed gives the same values whatever the executor, its workers, the other ``--vary`` options, their
order or the number of samples (:func:`variant_points`).
"""

from __future__ import annotations

import decimal
import hashlib
import itertools
import math
import re
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Literal

import numpy as np

from ..core.checks import integer
from ..core.errors import ParameterError
from ..core.limits import MAX_NETLIST_VARIANTS

__all__ = ["Distribution", "DistributionKind", "Vary", "SPREADS", "DRAWS", "parse_netlist_vary", "each_once",
           "variant_points", "spice_number_exact", "RESERVED", "DEFAULT_SEED"]

#: The seed of the draws when none is given (a resumed sweep must draw the same values).
DEFAULT_SEED = 0
#: What a distribution draws from.
DistributionKind = Literal["normal", "uniform"]
#: Columns a run's row has already (``lcchain results --csv``, ``to_dataframe``) or that a study reads in its
#: params (``sample``, ``member``, ``runs``): a varied name among them is stored as ``vary_NAME``.
RESERVED = frozenset({"index", "key", "kind", "status", "label", "digest", "points", "wall_s", "engine",
                      "engine_version", "error", "sample", "member", "runs", "netlist", "params", "measurements",
                      "measure_reasons", "parts", "max_abs_error", "predicted_error", "arrivals", "t_sim",
                      "t_theory", "peak_sim", "peak_theory", "energy_sim", "dt"})

_ALLOWED = ("NAME=VALUES: a .param or element name of the netlist and V1,V2,... (SPICE numbers such as 1k, 2.2k, "
            "10n, 1meg), lin:START:STOP:N, log:START:STOP:N, normal:MEAN:SIGMA (SIGMA may be P% of MEAN), "
            "uniform:LO:HI or tolerance:NOMINAL:P%")
_NUMBER = re.compile(r"^([-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)(meg|mil|[tgkmunpf])?([a-z]*)$", re.IGNORECASE)
_SCALE = {"t": "1e12", "g": "1e9", "meg": "1e6", "k": "1e3", "m": "1e-3", "mil": "25.4e-6", "u": "1e-6",
          "n": "1e-9", "p": "1e-12", "f": "1e-15"}


def spice_number_exact(text: str, option: str, spec: str) -> float:
    """A SPICE number (``2.2k`` is 2200.0 exactly: the decimal is scaled, not the float), finite; ``M`` alone is
    refused (SPICE reads it as milli, most readers as mega)."""
    match = _NUMBER.match(text.strip())
    allowed = (f"{_ALLOWED}; {text.strip()!r} is no SPICE number" if match is None else "")
    if match is not None and match.group(2) is not None and match.group(2) == "M":
        allowed = f"{_ALLOWED}; {text.strip()!r}: write meg for mega or m for milli (SPICE reads M as milli)"
    if allowed:
        raise ParameterError(option, spec, allowed)
    assert match is not None
    number = decimal.Decimal(match.group(1))
    if match.group(2):
        number *= decimal.Decimal(_SCALE[match.group(2).lower()])
    value = float(number)
    if not math.isfinite(value):
        raise ParameterError(option, spec, f"{_ALLOWED}; {text.strip()!r} is not finite")
    return value


@dataclass(frozen=True)
class Distribution:
    """Where a varied value is drawn from: ``normal`` (``a`` the mean, ``b`` the standard deviation) or
    ``uniform`` (``a`` to ``b``)."""

    kind: DistributionKind
    a: float
    b: float

    def draw(self, rng: np.random.Generator) -> float:
        return float(DRAWS[self.kind](rng, self.a, self.b))


#: How each distribution draws one value.
DRAWS: dict[str, Callable[[np.random.Generator, float, float], float]] = {
    "normal": lambda rng, mean, sigma: rng.normal(mean, sigma),
    "uniform": lambda rng, lo, hi: rng.uniform(lo, hi),
}


@dataclass(frozen=True)
class Vary:
    """One ``--vary``: a name of the netlist and its values, listed or drawn.

    Attributes
    ----------
    name : str
        The ``.param`` or element name as typed.
    spec : str
        The ``--vary`` as typed (``NAME=SPEC``), as refusals name it.
    values : tuple of float
        A list's or a grid's values (empty for a distribution).
    distribution : Distribution or None
    """

    name: str
    spec: str
    values: tuple[float, ...] = ()
    distribution: Distribution | None = None

    @property
    def column(self) -> str:
        """Its key in each run's params, and so its column in ``lcchain results``: the name, or ``vary_NAME``
        when the name is one of :data:`RESERVED`."""
        return f"vary_{self.name}" if self.name.lower() in RESERVED else self.name


def _count(text: str, option: str, spec: str) -> int:
    try:
        count = int(text)
    except ValueError:
        count = 0
    if not 2 <= count <= MAX_NETLIST_VARIANTS:
        raise ParameterError(option, spec, f"a grid of N values, N an integer from 2 to {MAX_NETLIST_VARIANTS} "
                             f"(not {text!r})")
    return count


def _lin(name: str, spec: str, args: list[str]) -> Vary:
    start, stop = (spice_number_exact(a, "--vary", spec) for a in args[:2])
    count = _count(args[2], "--vary", spec)
    if start == stop:
        raise ParameterError("--vary", spec, "lin:START:STOP:N with START != STOP")
    return Vary(name, spec, tuple(float(v) for v in np.linspace(start, stop, count)))


def _log(name: str, spec: str, args: list[str]) -> Vary:
    start, stop = (spice_number_exact(a, "--vary", spec) for a in args[:2])
    count = _count(args[2], "--vary", spec)
    if not (start > 0 and stop > 0 and start != stop):
        raise ParameterError("--vary", spec, "log:START:STOP:N with 0 < START, 0 < STOP and START != STOP")
    return Vary(name, spec, tuple(float(v) for v in np.geomspace(start, stop, count)))


def _normal(name: str, spec: str, args: list[str]) -> Vary:
    mean = spice_number_exact(args[0], "--vary", spec)
    sigma = _relative(args[1], spec, abs(mean)) if args[1].strip().endswith("%") else \
        spice_number_exact(args[1], "--vary", spec)
    if not sigma >= 0:
        raise ParameterError("--vary", spec, "normal:MEAN:SIGMA with SIGMA >= 0 (a number, or P% of |MEAN|)")
    return Vary(name, spec, distribution=Distribution("normal", mean, sigma))


def _uniform(name: str, spec: str, args: list[str]) -> Vary:
    lo, hi = (spice_number_exact(a, "--vary", spec) for a in args[:2])
    if not lo < hi:
        raise ParameterError("--vary", spec, "uniform:LO:HI with LO < HI")
    return Vary(name, spec, distribution=Distribution("uniform", lo, hi))


def _tolerance(name: str, spec: str, args: list[str]) -> Vary:
    nominal = spice_number_exact(args[0], "--vary", spec)
    if not args[1].strip().endswith("%"):
        raise ParameterError("--vary", spec, "tolerance:NOMINAL:P% with the tolerance in percent, e.g. 5%")
    spread = _relative(args[1], spec, abs(nominal))
    if not spread < abs(nominal) or nominal == 0:
        raise ParameterError("--vary", spec, "tolerance:NOMINAL:P% with NOMINAL != 0 and 0 <= P < 100")
    return Vary(name, spec, distribution=Distribution("uniform", nominal - spread, nominal + spread))


def _relative(text: str, spec: str, of: float) -> float:
    """``P%`` of ``of``."""
    number = text.strip()[:-1]
    try:
        percent = float(decimal.Decimal(number)) if re.fullmatch(r"\d+\.?\d*|\.\d+", number) else -1.0
    except decimal.InvalidOperation:
        percent = -1.0
    if not 0 <= percent < 100:
        raise ParameterError("--vary", spec, f"a percentage 0 <= P < 100 such as 5% (not {text.strip()!r})")
    return of * percent / 100


#: The spreads a ``--vary`` may name before its first colon: (its arguments, its parser). A bare list has none.
SPREADS: dict[str, tuple[int, Callable[[str, str, list[str]], Vary]]] = {
    "lin": (3, _lin), "log": (3, _log), "normal": (2, _normal), "uniform": (2, _uniform),
    "tolerance": (2, _tolerance),
}
_NAME = re.compile(r"[A-Za-z_][A-Za-z0-9_]*")
_FORMS = {"lin": "lin:START:STOP:N", "log": "log:START:STOP:N", "normal": "normal:MEAN:SIGMA",
          "uniform": "uniform:LO:HI", "tolerance": "tolerance:NOMINAL:P%"}


def parse_netlist_vary(text: str) -> Vary:
    """``NAME=SPEC`` (one ``--vary`` of ``sweep --netlist``) as a :class:`Vary`, or a refusal naming ``--vary``,
    the text and what is allowed."""
    name, sep, spec = (part.strip() for part in text.partition("="))
    if not sep or not _NAME.fullmatch(name) or not spec:
        raise ParameterError("--vary", text, _ALLOWED)
    head, colon, rest = spec.partition(":")
    if colon:
        known = SPREADS.get(head.strip().lower())
        if known is None:
            raise ParameterError("--vary", text, f"{_ALLOWED} (not {head.strip()!r}: one of "
                                 f"{' | '.join(SPREADS)})")
        count, parse = known
        args = rest.split(":")
        if len(args) != count or not all(a.strip() for a in args):
            raise ParameterError("--vary", text, f"{_FORMS[head.strip().lower()]} ({count} values after "
                                 f"{head.strip()}:, none empty)")
        return parse(name, text, args)
    entries = [entry.strip() for entry in spec.split(",")]
    if not all(entries):
        empty = entries.index("") + 1
        raise ParameterError("--vary", text, f"{_ALLOWED} (value {empty} of {len(entries)} is empty)")
    if len(entries) > MAX_NETLIST_VARIANTS:
        raise ParameterError("--vary", text, f"at most {MAX_NETLIST_VARIANTS} values")
    values = tuple(spice_number_exact(entry, "--vary", text) for entry in entries)
    each_once(values, entries, text)
    return Vary(name, text, values)


def each_once(values: Sequence[object], entries: Sequence[str], text: str) -> None:
    """Refuse a list that gives one value twice (``1k,1000``: one run, which a summary would count twice)."""
    for k, value in enumerate(values):
        for j in range(k):
            if type(values[j]) is type(value) and values[j] == value:
                raise ParameterError("--vary", text, f"each value once (value {k + 1}, {entries[k]}, is value "
                                     f"{j + 1}, {entries[j]}: the same run)")


def _stream(seed: int, name: str) -> np.random.SeedSequence:
    """The name's own seed sequence: its draws do not depend on the other names or their order."""
    digest = int.from_bytes(hashlib.sha256(name.lower().encode("utf-8")).digest()[:8], "big")
    return np.random.SeedSequence([seed, digest])


def variant_points(varies: Sequence[Vary], *, samples: int | None = None,
                   seed: int | None = None) -> list[dict[str, float]]:
    """Every run's varied values, by column (:attr:`Vary.column`), in the sweep's order: the product of the lists
    and grids (the first ``--vary`` slowest); with distributions, each point once per sample, ``sample`` (1 to
    ``samples``) before the drawn values.

    Raises
    ------
    ParameterError
        A name given twice, a distribution without ``samples`` (or ``samples`` without one), or more than
        :data:`lcchain.core.limits.MAX_NETLIST_VARIANTS` runs.
    """
    if not varies:
        raise ParameterError("--vary", None, f"at least one --vary with --netlist ({_ALLOWED})")
    seen: dict[str, str] = {}
    for vary in varies:
        if vary.name.lower() in seen:
            raise ParameterError("--vary", vary.spec, f"each name once (--vary {seen[vary.name.lower()]} names "
                                 f"{vary.name} already; SPICE names are the same in any case)")
        seen[vary.name.lower()] = vary.spec
    listed = [vary for vary in varies if vary.distribution is None]
    drawn = [vary for vary in varies if vary.distribution is not None]
    if drawn and samples is None:
        raise ParameterError("--vary", drawn[0].spec, "--samples N with a distribution (how many draws)")
    if samples is not None and not drawn:
        raise ParameterError("--samples", samples, "a --vary with a distribution (normal:, uniform:, tolerance:) "
                             "to draw from")
    count = math.prod(len(vary.values) for vary in listed)
    if drawn:
        samples = integer("--samples", samples, at_least=1, at_most=MAX_NETLIST_VARIANTS)
        count *= samples
    if count > MAX_NETLIST_VARIANTS:
        raise ParameterError("--vary", " x ".join(v.spec for v in varies), f"at most {MAX_NETLIST_VARIANTS} runs "
                             f"in one sweep (these make {count})")
    seed = integer("--seed", seed if seed is not None else DEFAULT_SEED, at_least=0)
    draws: dict[str, list[float]] = {}
    for vary in drawn:
        assert vary.distribution is not None and samples is not None
        distribution = vary.distribution
        draws[vary.column] = [distribution.draw(np.random.default_rng(child))
                              for child in _stream(seed, vary.name).spawn(samples)]
    points = []
    for values in itertools.product(*[vary.values for vary in listed]):
        point: dict[str, float] = {vary.column: value for vary, value in zip(listed, values, strict=True)}
        if not drawn:
            points.append(point)
            continue
        for k in range(samples or 0):
            points.append({**point, "sample": k + 1, **{column: drawn_values[k]
                                                        for column, drawn_values in draws.items()}})
    return points
