"""The accuracy bench's files: records.csv, records.json, pareto.png and summary.md."""

from __future__ import annotations

import csv
import io
from collections.abc import Mapping
from pathlib import Path

from ..core.json import LooseJSON, json_text
from ..studies.bench import RECORD_FIELDS, record_label
from .files import write_text

__all__ = ["write_accuracy_bench"]


def write_accuracy_bench(out: str | Path, bench: Mapping[str, LooseJSON]) -> list[str]:
    """Write a :func:`lcchain.studies.bench.bench_accuracy` result into the folder ``out`` (created): a JSON
    document read by key.

    Returns
    -------
    list of str
        The files written.
    """
    from .plots import pareto

    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    records, checks, summary = bench["records"], bench["targets"], bench["summary"]
    paths = [out / "records.csv", out / "records.json", out / "pareto.png", out / "summary.md"]
    table = io.StringIO(newline="")
    writer = csv.DictWriter(table, fieldnames=RECORD_FIELDS)
    writer.writeheader()
    for r in records:
        writer.writerow({k: ("" if r[k] is None else r[k]) for k in RECORD_FIELDS})
    write_text(paths[0], table.getvalue())
    write_text(paths[1], json_text({"records": records, "targets": checks, "fits": summary["fits"]}, indent=1))
    plotted = [{"method": record_label(r), "N": r["N"], "wall_s": r["wall_s"], "error": r["error"]} for r in records
               if r["wall_s"] > 0 and r["error"] > 0]
    pareto(plotted, path=paths[2])
    write_text(paths[3], bench["markdown"])
    return [str(p) for p in paths]
