"""Sphinx configuration of lcchain's documentation site.

Build it (from the repository root, with ``pip install -e ".[docs]"``)::

    .venv/bin/python -m sphinx -W -n -b html docs build/site

``-W`` makes every warning an error and ``-n`` (nitpicky) every unresolved cross-reference a warning;
tests/test_docs.py builds the site that way from a copy of this folder. The API pages and the gallery's
pages are generated into this folder (``api/generated``, ``gallery-generated``; both ignored by git).
"""

from __future__ import annotations

import importlib
import os
import re
import sys
import types
from pathlib import Path

import lcchain

sys.path.insert(0, str(Path(__file__).resolve().parent / "_ext"))  # the gallery's figure scraper
PACKAGE = Path(lcchain.__file__).resolve().parent

project = "lcchain"
author = "the lcchain authors"
copyright = "the lcchain authors, MIT licence"
release = version = lcchain.__version__

extensions = [
    "myst_parser",
    "sphinx.ext.autodoc",
    "sphinx.ext.autosummary",
    "numpydoc",
    "sphinx_gallery.gen_gallery",
]

source_suffix = {".rst": "restructuredtext", ".md": "markdown"}
root_doc = "index"
exclude_patterns = ["_build", "package.md", "gallery/README.rst", "**/.ipynb_checkpoints"]
templates_path = ["_templates"]

# Markdown pages: headings get anchors for [text](page.md#anchor) links. No maths extension: formulas are
# written in Unicode, so that the site loads nothing from elsewhere (as the validation report does not).
myst_enable_extensions = ["colon_fence"]
myst_heading_anchors = 3

# The API reference: one page per public name, from the numpydoc docstrings.
autosummary_generate = True
autodoc_typehints = "none"  # the numpydoc "Parameters" sections say the types (and units)
autodoc_member_order = "bysource"
numpydoc_show_class_members = False
numpydoc_class_members_toctree = False
numpydoc_validation_checks: set[str] = set()



_FIELD = object()


def _python_object(name: str, modules: list[str]) -> bool:
    """Whether a cross-reference names an object, looked up as Python would: as written, then relative to each
    of ``modules`` (where the reference is written)."""
    for candidate in [name] + [f"{m}.{name}" for m in modules]:
        parts = candidate.split(".")
        for cut in range(len(parts), 0, -1):
            try:
                obj: object = importlib.import_module(".".join(parts[:cut]))
            except Exception:  # not a module: try a shorter prefix
                continue
            for attr in parts[cut:]:
                if hasattr(obj, attr):
                    obj = getattr(obj, attr)
                elif attr in getattr(obj, "__annotations__", {}):  # a dataclass field without a default
                    obj = _FIELD
                else:
                    break
            else:
                return True
            break
    return False


def _where_written(node) -> list[str]:
    """The modules (and classes) a reference is written in: the current ones of the page, and the module of
    the source file when the reference comes from a docstring."""
    modules = []
    module, cls = node.get("py:module"), node.get("py:class")
    if module:
        modules += [f"{module}.{cls}"] if cls else []
        modules.append(module)
    source = (node.source or "").split(":docstring of ")
    if len(source) == 2 and source[0].endswith(".py") and Path(source[0]).is_relative_to(PACKAGE.parent):
        path = Path(source[0]).relative_to(PACKAGE.parent).with_suffix("")
        module = ".".join(path.parts[:-1] if path.name == "__init__" else path.parts)
        owner = source[1].split(":")[0]  # the documented object: its class holds attributes a reference names
        modules += [owner.rsplit(".", 1)[0], module]
    return modules


def _text_for_real_names(app, env, node, contnode):
    """A reference the site has no page for (a private helper, a constant, a module outside the reference,
    the standard library: the site is built offline, without intersphinx) is shown as text when it names a
    real object; -n then reports only the names that do not exist (a stale docstring). A bare name in a
    summary line (an autosummary table) is looked up in every lcchain module loaded."""
    if node.get("refdomain") != "py":
        return None
    target = node["reftarget"].lstrip("~.")
    modules = _where_written(node)
    if not modules and "." not in target:
        modules = [m for m in sys.modules if m.startswith("lcchain.")]
    if _python_object(target, modules):
        return contnode
    return None


def _skip_type_aliases(app, what, name, obj, skip, options):
    """A type alias (``SeriesElement = tuple[str, float]``) is no class autodoc can sign: its module's
    source says what it is."""
    return True if isinstance(obj, types.GenericAlias) else None


def _literal_bars(app, what, name, obj, options, lines):
    """Docstrings write |x| for an absolute value; reStructuredText would read it as a substitution."""
    lines[:] = [re.sub(r"(?<!\\)\|", r"\\|", line) for line in lines]


def setup(app):
    app.connect("missing-reference", _text_for_real_names)
    app.connect("autodoc-skip-member", _skip_type_aliases)
    app.connect("autodoc-process-docstring", _literal_bars, priority=400)  # before numpydoc's (500)

# The gallery: small scripts run when the site is built, their figures kept (matplotlib's Agg backend).
os.environ.setdefault("MPLBACKEND", "Agg")
sphinx_gallery_conf = {
    "examples_dirs": ["gallery"],
    "gallery_dirs": ["gallery-generated"],
    "filename_pattern": r"/plot_",
    "download_all_examples": False,
    "remove_config_comments": True,
    "within_subsection_order": "FileNameSortKey",
    "abort_on_example_error": True,
    "show_memory": False,
    "plot_gallery": "True",
    # pyplot's figures, and the Figures lcchain's results draw without pyplot (docs/_ext/lcchain_figures.py)
    "image_scrapers": ("lcchain_figures.scrape", "matplotlib"),  # ours first: pyplot closes its own
}

html_theme = "alabaster"
html_title = f"lcchain {release}"
html_static_path: list[str] = []
html_show_sourcelink = False
