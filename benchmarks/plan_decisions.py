"""Every decision a batch's plan makes of every netlist the tests hold, one line each, for diffing two trees.

For each netlist of :func:`helpers.corpus.netlist_cases` and each of its :func:`helpers.corpus.variants` (written
into ``FOLDER``, which must not exist, with the files it includes) it prints: the allow-list's text or refusal, the
``.meas`` names, and for the checked text and the text run as it is (``--allow-control``) its logical lines, its
options, its analysis, its saves, its contents, its price and its run's limits, then ``batch_plan``'s tasks
(price, memory, spec) or refusals with and without ``--allow-control``; each as a hash of its ``repr`` and its
first 150 characters.  Usage (the two outputs must be equal; the same FOLDER, since messages name the files)::

    PYTHONPATH=/tmp/before .venv/bin/python benchmarks/plan_decisions.py /tmp/decisions > before.txt
    rm -r /tmp/decisions; .venv/bin/python benchmarks/plan_decisions.py /tmp/decisions > after.txt
    diff before.txt after.txt

(``/tmp/before``: ``git archive REV lcchain | tar -x -C /tmp/before``.)
"""

from __future__ import annotations

import hashlib
import sys
from collections.abc import Callable
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "tests"))

from helpers.corpus import netlist_cases, variants  # noqa: E402

from lcchain.core.budget import Budget  # noqa: E402
from lcchain.core.errors import ParameterError  # noqa: E402
from lcchain.spice.foreign import allowed_netlist, analysis_of, foreign_price  # noqa: E402
from lcchain.spice.measure import measure_names  # noqa: E402
from lcchain.spice.pricing import read_contents  # noqa: E402
from lcchain.spice.result import read_include  # noqa: E402
from lcchain.spice.text import canonical_text, logical_lines, parse_options, saved_vectors  # noqa: E402
from lcchain.studies.plan import batch_plan  # noqa: E402


def outcome(work: Callable[..., object], *args: object) -> str:
    try:
        return repr(work(*args))
    except ParameterError as error:
        return f"refused {error}"


def priced(text: str, source: str) -> tuple[object, ...]:
    analysis = analysis_of(text, source, lambda: "39")
    saved = saved_vectors(text)
    price = foreign_price(text, analysis, len(saved), source)
    return price, price.limits(Budget(), 100.0)


def planned(path: Path, trusted: bool) -> tuple[object, ...]:
    made = batch_plan([str(path)], allow_control=trusted, engine_version=lambda: "39")
    return tuple((t.seconds, t.memory, t.spec) for t in made.tasks), tuple(r.reason for r in made.refusals)


def decisions(path: Path) -> dict[str, str]:
    try:
        raw = read_include(path, "NETLIST")
    except ParameterError as error:
        return {"read": f"refused {error}"}
    source = str(path)
    found = {"allowed": outcome(lambda: str(allowed_netlist(raw, source, path.parent, read_include))),
             "measure names": outcome(measure_names, raw)}
    for kind, make in (("checked", lambda: allowed_netlist(raw, source, path.parent, read_include)),
                       ("as it is", lambda: canonical_text(raw, source))):
        try:
            text = str(make())
        except ParameterError:
            continue
        for name, work in (("logical lines", logical_lines), ("options", parse_options), ("saved", saved_vectors)):
            found[f"{kind} {name}"] = outcome(work, text)
        found[f"{kind} analysis"] = outcome(analysis_of, text, source, lambda: "39")
        found[f"{kind} contents"] = outcome(read_contents, text, source)
        found[f"{kind} price"] = outcome(priced, text, source)
    for trusted in (False, True):
        found[f"plan trusted={trusted}"] = outcome(planned, path, trusted)
    return found


def main() -> int:
    root = Path(sys.argv[1])
    root.mkdir()
    k = 0
    for name, files in netlist_cases().items():
        for top in [f for f in files if f.endswith(".cir")] or list(files)[:1]:
            content = files[top]
            written = variants(content) if isinstance(content, str) else {"bytes": content}
            for variant, text in written.items():
                k += 1
                folder = root / f"c{k}"
                for file, each in files.items():
                    path = folder / file
                    path.parent.mkdir(parents=True, exist_ok=True)
                    data = each if isinstance(each, bytes) else each.replace("{here}", str(folder)).encode()
                    path.write_bytes(data)
                path = folder / top
                path.write_bytes(text if isinstance(text, bytes) else
                                 text.replace("{here}", str(folder)).encode("utf-8", "surrogatepass"))
                for key, value in decisions(path).items():
                    digest = hashlib.sha256(value.encode("utf-8", "surrogatepass")).hexdigest()[:16]
                    print(f"{name} | {top} | {variant} | {key} {digest} {value[:150]!r}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
