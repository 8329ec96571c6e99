"""The gallery's image scraper for lcchain's own figures.

lcchain draws on :class:`matplotlib.figure.Figure` directly, never through pyplot (a result's ``.plot()``
returns its Figure), so sphinx-gallery's matplotlib scraper, which asks pyplot for its figures, does not see
them. This one saves every Figure an example's code block left in its variables, that pyplot does not manage
and that no block saved before.
"""

from __future__ import annotations

import weakref
from typing import Any

_saved: weakref.WeakSet[Any] = weakref.WeakSet()


def scrape(block: Any, block_vars: dict[str, Any], gallery_conf: dict[str, Any], **kwargs: Any) -> str:
    from matplotlib.figure import Figure
    from sphinx_gallery.scrapers import figure_rst

    figures = [v for v in block_vars["example_globals"].values()
               if isinstance(v, Figure) and v not in _saved and v.canvas.manager is None]  # pyplot's: its scraper
    paths = []
    for figure, path in zip(figures, block_vars["image_path_iterator"], strict=False):
        figure.savefig(path, dpi=100)
        _saved.add(figure)
        paths.append(path)
    return figure_rst(paths, gallery_conf["src_dir"])
