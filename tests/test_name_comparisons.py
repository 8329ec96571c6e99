"""Nothing outside the registries tests a part's name (issue 34, item 1): a part describes itself.

The scanner (:mod:`helpers.name_comparisons`) reads every module's syntax tree and lists each ``==``, ``!=``,
``in``/``not in`` comparison or ``match`` of a name-like attribute or variable with a registered part name (an
engine's, a transport's, an analysis's, an executor's, a case's, a mode method's, an effect's), and each
``isinstance`` on an effect class.  Measured with it: 83 on main before issue 34's item 1.
"""

from __future__ import annotations

from collections import Counter
from pathlib import Path

from helpers.name_comparisons import name_comparisons

#: What is left, by module and kind of part: only the command layer, which issue 34's item 3 moves into app/ at
#: the same time (its options become typed requests there; each has its attribute ready: ``analysis_kind(...)
#: .swept``, ``DESIGN_TABLES``, ``CHAIN_CASES[...].walls``, ``EXECUTOR_TRAITS[...].parallel``, the engines'
#: ``transports``).  A place that is not here, or one more of a kind here, fails the test; one fewer asks to
#: lower the count.
LEFT: dict[tuple[str, str], int] = {
    ("cli/check.py", "analysis"): 1,
    ("cli/commands.py", "analysis"): 1,
    ("cli/commands.py", "case"): 2,
    ("cli/commands.py", "isinstance"): 1,
    ("cli/commands.py", "transport"): 1,
    ("cli/common.py", "case"): 2,
    ("cli/studies.py", "analysis"): 4,
    ("cli/studies.py", "executor"): 2,
    ("cli/studies.py", "transport"): 2,
}


def test_nothing_outside_the_command_layer_compares_a_part_name() -> None:
    outside = [str(place) for place in name_comparisons() if not place.path.startswith("cli/")]
    assert outside == []


def test_no_part_name_is_compared_outside_the_registries() -> None:
    found = Counter((place.path, place.part.split(" ")[0]) for place in name_comparisons())
    places = "\n".join(str(place) for place in name_comparisons())
    assert found == Counter(LEFT), places


def test_the_scanner_finds_each_form_of_a_name_comparison(tmp_path: Path) -> None:
    package = tmp_path / "package"
    package.mkdir()
    (package / "tests_names.py").write_text(
        "def f(spec, args, effect, other):\n"
        "    if spec.engine == 'ngspice':\n"  # an attribute against an engine's name
        "        pass\n"
        "    if args.backend in ('batch', 'shared'):\n"  # a variable in a tuple of transports
        "        pass\n"
        "    if meta['analysis'] != 'ac':\n"  # a subscript's key against an analysis
        "        pass\n"
        "    match args.executor:\n"  # a match on an executor
        "        case 'serial':\n"
        "            pass\n"
        "    if isinstance(effect, Tolerance):\n"  # an isinstance on an effect class
        "        pass\n"
        "    if spec.engine == other.name or args.backend == 'ngspice' or spec.text == 'batch':\n"  # none of these
        "        pass\n", encoding="utf-8")
    found = name_comparisons(package)
    assert [place.line for place in found] == [2, 4, 6, 8, 11], "\n".join(map(str, found))
    assert [place.part.split(" ")[0] for place in found] == ["engine", "transport", "analysis", "match", "isinstance"]
