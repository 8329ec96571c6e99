"""``lcchain bench accuracy`` as a function: what each digit costs per method and N, priced, run and written."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field

from ..core.budget import Budget
from ..core.json import LooseJSONObject
from ..report.files import check_output_folder

__all__ = ["AccuracyBenchRequest", "AccuracyBench", "bench_accuracy", "write_bench"]


@dataclass(frozen=True)
class AccuracyBenchRequest:
    """The sizes (None: the default ones), ``quick`` (fewer steps and tolerances), the output folder."""

    Ns: tuple[int, ...] | None = None
    quick: bool = False
    out: str = "benchmarks/accuracy"
    budget: Budget = field(default_factory=Budget)
    progress: Callable[..., None] | None = None


@dataclass(frozen=True)
class AccuracyBench:
    """The benchmark's table as Markdown, and everything it measured (written by :func:`write_bench`)."""

    markdown: str
    data: LooseJSONObject


def bench_accuracy(request: AccuracyBenchRequest) -> AccuracyBench:
    from ..studies.bench import bench_accuracy as run
    from ..studies.bench import bench_estimate

    Ns = None if request.Ns is None else list(request.Ns)
    check_output_folder("--out", request.out, parents=True)  # the folder itself is made when the results are written
    bench_estimate(Ns, quick=request.quick).check(request.budget, "bench accuracy",
                                                  "--quick" if request.quick else "the full sweep", "--quick or --N")
    result = run(Ns, quick=request.quick, progress=request.progress)
    return AccuracyBench(result["markdown"], dict(result))


def write_bench(out: str, bench: AccuracyBench) -> list[str]:
    """Write the benchmark's files into folder ``out`` (made now); returns their paths."""
    from ..report.bench import write_accuracy_bench

    return write_accuracy_bench(out, bench.data)
