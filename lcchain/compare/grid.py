"""The frequencies of an AC sweep, placed where the poles are dense (pure arrays).

An even sweep needs a few samples per *smallest* spacing of the poles everywhere; an optimised chain's spacing
shrinks like 1/N^2 at the top of its band while it stays near pi/N below, so an even sweep of N = 2000 would
need tens of millions of frequencies.  :func:`sweep_segments` cuts (0, omega_max] into a few even segments
(``.ac lin`` cards), each as fine as the smallest spacing of the poles it holds: a new segment starts where the
spacing changes by more than :data:`SEGMENT_RATIO`, and segments meet halfway between two poles, never on one.
The grid then holds about ``density`` samples per spacing wherever the poles are (O(N) frequencies for any
chain), and :func:`min_points` is the fewest that give :data:`POINTS_PER_SPACING` everywhere.
"""

from __future__ import annotations

import numpy as np

from ..circuit.netlist import AC_OFFSET

__all__ = ["Segment", "sweep_segments", "segment_frequencies", "min_points", "POINTS_PER_SPACING", "SEGMENT_RATIO"]

#: Samples per spacing of the poles that the fit needs (at least): each pole's window then holds a few samples
#: on each side.  :func:`min_points` uses it to refuse a grid too coarse before anything runs.
POINTS_PER_SPACING = 4
#: The largest ratio of two spacings of poles in one even segment.
SEGMENT_RATIO = 2.0

#: (points, lowest, highest): ``points`` even frequencies on (lowest, highest], the first at lowest + step.
Segment = tuple[int, float, float]


def _blocks(omega: np.ndarray, omega_max: float) -> list[tuple[float, float, float]]:
    """(lowest, highest, smallest spacing) of each stretch of poles whose spacings are within SEGMENT_RATIO."""
    poles = np.unique(np.asarray(omega, dtype=float))
    poles = poles[(poles > 0) & (poles < omega_max)]
    if poles.size < 2:
        return [(0.0, omega_max, omega_max / 4.0)]
    gaps = np.diff(poles)
    blocks = []
    start, smallest, largest = 0, gaps[0], gaps[0]
    for i in range(1, gaps.size):
        if max(largest, gaps[i]) > SEGMENT_RATIO * min(smallest, gaps[i]):
            blocks.append((start, i, smallest))
            start, smallest, largest = i, gaps[i], gaps[i]
        else:
            smallest, largest = min(smallest, gaps[i]), max(largest, gaps[i])
    blocks.append((start, gaps.size, smallest))
    # a stretch covers its gaps first..last-1; the segments meet halfway across the gap between two stretches, so
    # that gap is sampled by both: each takes it into its smallest spacing
    out = []
    for k, (first, last, smallest) in enumerate(blocks):
        if last < gaps.size:
            smallest = min(smallest, gaps[last])
        lowest = 0.0 if k == 0 else 0.5 * (poles[first] + poles[first + 1])
        # the last ends half a spacing past the top pole, or at omega_max when that comes first (small N)
        highest = min(omega_max, poles[-1] + 0.5 * gaps[-1]) if k == len(blocks) - 1 else \
            0.5 * (poles[last] + poles[last + 1])
        out.append((float(lowest), float(highest), float(smallest)))
    # beyond the top pole the response is smooth: segments twice as long and twice as coarse each
    step, lowest = float(gaps[-1]), out[-1][1]
    while lowest < omega_max:
        highest = min(omega_max, lowest + 2.0 * step) if lowest + 4.0 * step < omega_max else omega_max
        out.append((lowest, highest, step))
        lowest, step = highest, 2.0 * step
    return out


def min_points(omega: np.ndarray, omega_max: float) -> int:
    """The fewest frequencies on (0, omega_max] that separate every pole of ``omega`` (:func:`sweep_segments`
    with :data:`POINTS_PER_SPACING` samples per spacing)."""
    return sum(points for points, _, _ in sweep_segments(omega, omega_max, POINTS_PER_SPACING))


#: The fewest frequencies of a segment: ngspice 39's ``.ac lin 2 f1 f2`` gives one frequency, not two (``lin 3``
#: and more give as many as asked).
MIN_SEGMENT_POINTS = 3


def sweep_segments(omega: np.ndarray, omega_max: float, density: float, points: int | None = None
                   ) -> list[Segment]:
    """The sweep's even segments for the poles ``omega`` (units of 1/sqrt(L0 C0)).

    Parameters
    ----------
    omega : ndarray
        The predicted poles (the theory's normal frequencies); 0 and those beyond omega_max are ignored.
    omega_max : float
        The sweep's end (> every pole).
    density : float
        Samples per smallest spacing of each segment's poles.
    points : int, optional
        The total instead: the segments share it in proportion to what ``density`` gives them.

    Returns
    -------
    list of (points, lowest, highest)
        Disjoint, ascending; together (0, omega_max].
    """
    blocks = _blocks(omega, omega_max)
    wanted = np.array([max(float(MIN_SEGMENT_POINTS), (hi - lo) * density / step) for lo, hi, step in blocks])
    if points is None:
        counts = np.ceil(wanted).astype(int)
    else:  # share exactly ``points``: floors, then the largest remainders
        share = wanted * points / wanted.sum()
        counts = np.maximum(np.floor(share).astype(int), MIN_SEGMENT_POINTS)
        order = np.argsort(counts - share)
        for k in order[: max(points - int(counts.sum()), 0)]:
            counts[k] += 1
    return [(int(n), float(lo), float(hi)) for n, (lo, hi, _) in zip(counts, blocks, strict=True)]


def segment_frequencies(segments: list[Segment]) -> np.ndarray:
    """The angular frequencies the ``.ac lin`` cards of ``segments`` sample (as
    :func:`lcchain.circuit.netlist.ac_netlist_text` writes them): lowest + (k + AC_OFFSET) step in each."""
    return np.concatenate([lo + (np.arange(n) + AC_OFFSET) * (hi - lo) / n for n, lo, hi in segments])
