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
