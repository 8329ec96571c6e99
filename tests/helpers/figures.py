"""Checks of drawn figures on their artists, never on pixels: where legends sit against the data."""

from __future__ import annotations

from typing import Any


def drawn(fig: Any) -> Any:
    """The figure laid out (no pixels rendered); its renderer."""
    fig.draw_without_rendering()
    return fig._get_renderer() if hasattr(fig, "_get_renderer") else fig.canvas.get_renderer()


def legend_boxes(fig: Any) -> list[Any]:
    """Every legend's box (the figure's and the axes'), in display coordinates; there is at least one."""
    legends = [*fig.legends, *(ax.get_legend() for ax in fig.axes if ax.get_legend() is not None)]
    assert legends
    renderer = drawn(fig)
    return [legend.get_window_extent(renderer) for legend in legends]


def assert_legends_off_lines(fig: Any) -> None:
    """No legend's box (display coordinates) holds a point of, or is crossed by, a line of any panel."""
    boxes = legend_boxes(fig)
    for ax in fig.axes:
        for line in ax.get_lines():
            path = line.get_transform().transform_path(line.get_path())
            for box in boxes:
                inside = box.contains_points(path.vertices) if hasattr(box, "contains_points") else \
                    [box.contains(x, y) for x, y in path.vertices]
                assert not any(inside), (line.get_label(), box)
                assert not path.intersects_bbox(box, filled=False), (line.get_label(), box)


def _drawn_tick_labels(axis: Any) -> list[Any]:
    """The tick labels an axis draws: within its view, visible, with text (matplotlib keeps labels of ticks
    outside the view, never drawn)."""
    ticks = axis._update_ticks()  # the ticks draw() draws (private, but what Axis.draw itself calls)
    return [label for tick in ticks for label in (tick.label1, tick.label2)
            if label.get_visible() and label.get_text()]


def _all_axes(fig: Any) -> list[Any]:
    axes = []
    for ax in fig.axes:
        axes += [ax, *getattr(ax, "child_axes", [])]  # secondary axes (a physical unit on top) are children
    return axes


def assert_readable(fig: Any) -> None:
    """After ``fig.canvas.draw()``: no two tick labels of an axis overlap, and every text drawn (titles, labels,
    tick labels, legends, notes) lies inside the figure, in display coordinates (1 pixel of slack)."""
    from matplotlib.text import Text

    if not hasattr(fig.canvas, "get_renderer"):  # lcchain's figures have no pyplot: Agg draws them here
        from matplotlib.backends.backend_agg import FigureCanvasAgg

        FigureCanvasAgg(fig)
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    frame = fig.bbox.padded(1.0)
    drawn_labels: set[int] = set()
    all_labels: set[int] = set()
    for ax in _all_axes(fig):
        if not ax.get_visible():
            continue
        for axis in (ax.xaxis, ax.yaxis):
            for tick in [*axis.get_major_ticks(), *axis.get_minor_ticks()]:
                all_labels |= {id(tick.label1), id(tick.label2)}
            labels = _drawn_tick_labels(axis)
            drawn_labels |= {id(label) for label in labels}
            boxes = [(label.get_text(), label.get_window_extent(renderer)) for label in labels]
            for i, (text_a, a) in enumerate(boxes):
                for text_b, b in boxes[i + 1:]:
                    overlap = min(a.x1, b.x1) - max(a.x0, b.x0), min(a.y1, b.y1) - max(a.y0, b.y0)
                    assert not (overlap[0] > 0.5 and overlap[1] > 0.5), \
                        f"tick labels {text_a!r} and {text_b!r} overlap on {axis.axis_name} of {ax.get_title()!r}"
    for text in fig.findobj(Text):
        if not text.get_visible() or not text.get_text() or (id(text) in all_labels and id(text) not in drawn_labels):
            continue
        if text.axes is not None and not text.axes.get_visible():
            continue
        box = text.get_window_extent(renderer)
        assert frame.x0 <= box.x0 and box.x1 <= frame.x1 and frame.y0 <= box.y0 and box.y1 <= frame.y1, \
            f"{text.get_text()!r} at {box.bounds} is clipped by the figure {fig.bbox.bounds}"
