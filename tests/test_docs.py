"""The documentation site (issue 33): Sphinx builds docs/ with every warning an error and every cross-reference
checked (``-W -n``), runs the gallery's examples (in real ngspice), and every link between its pages lands on a
page and an anchor that exist.

The site is built from a copy of docs/ in tmp_path: Sphinx writes the API pages and the gallery's pages into
its source folder, and a build in the repository would leave them there (a page left from a name since
removed would then fail the next build). ``linkcheck`` is Sphinx's check of external links; this site has
none to check, so its own links are checked here, in the built HTML.
"""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
from html.parser import HTMLParser
from pathlib import Path
from urllib.parse import unquote, urlsplit

import pytest

ROOT = Path(__file__).resolve().parent.parent
DOCS = ROOT / "docs"


class _Links(HTMLParser):
    """The href and src values of a page, and the ids it defines."""

    def __init__(self) -> None:
        super().__init__()
        self.targets: list[str] = []
        self.ids: set[str] = set()

    def handle_starttag(self, tag: str, attrs: list[tuple[str, str | None]]) -> None:
        for name, value in attrs:
            if value is None:
                continue
            if name in ("href", "src"):
                self.targets.append(value)
            elif name in ("id", "name"):
                self.ids.add(value)


def _parsed(page: Path) -> _Links:
    links = _Links()
    links.feed(page.read_text(encoding="utf-8"))
    return links


def broken_links(site: Path) -> list[str]:
    """Every relative href/src of every page that names no file of the site, or an anchor the page lacks."""
    site = site.resolve()
    pages = {page: _parsed(page) for page in site.rglob("*.html")}
    broken = []
    for page, links in pages.items():
        for target in links.targets:
            parts = urlsplit(target)
            if parts.scheme or parts.netloc or target.startswith(("mailto:", "javascript:")):
                continue  # not this site's (there are none in its pages; the search index may name some)
            path = page if not parts.path else (page.parent / unquote(parts.path)).resolve()
            if not path.is_relative_to(site) or not path.exists():
                broken.append(f"{page.relative_to(site)}: {target} (no such file)")
            elif parts.fragment and path.suffix == ".html":
                ids = pages[path].ids if path in pages else _parsed(path).ids
                if unquote(parts.fragment) not in ids:
                    broken.append(f"{page.relative_to(site)}: {target} (no such anchor)")
    return sorted(broken)


def test_the_link_check_finds_a_missing_page_and_a_missing_anchor(tmp_path: Path) -> None:
    (tmp_path / "a.html").write_text('<a id="here" href="b.html#there">b</a> <a href="#here">a</a> '
                                     '<img src="missing.png"> <a href="https://example.org/x">out</a>')
    (tmp_path / "b.html").write_text('<p id="elsewhere"></p><a href="a.html#nowhere">a</a>')
    assert broken_links(tmp_path) == ["a.html: b.html#there (no such anchor)", "a.html: missing.png (no such file)",
                                      "b.html: a.html#nowhere (no such anchor)"]


def test_the_readme_links_only_to_files_of_the_repository() -> None:
    """The README is the front page: its links lead to the site's pages (their sources in docs/)."""
    text = (ROOT / "README.md").read_text(encoding="utf-8")
    targets = re.findall(r"\]\(([^)\s]+)\)", text)
    relative = [t.split("#", 1)[0] for t in targets if not urlsplit(t).scheme and not t.startswith("#")]
    assert relative and [t for t in relative if not (ROOT / t).exists()] == []
    assert "docs/getting-started.md" in relative and "docs/extending.md" in relative


@pytest.fixture(scope="module")
def site(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The site built from a copy of docs/ (benchmarks/ beside it, for the figures the pages show)."""
    top = tmp_path_factory.mktemp("docs-src")
    shutil.copytree(DOCS, top / "docs", ignore=shutil.ignore_patterns("generated", "gallery-generated", "_build",
                                                                      "sg_execution_times.rst", "__pycache__"))
    (top / "benchmarks").symlink_to(ROOT / "benchmarks")
    out = tmp_path_factory.mktemp("docs-html")
    env = dict(os.environ, MPLBACKEND="Agg", PYTHONDONTWRITEBYTECODE="1")
    done = subprocess.run([sys.executable, "-m", "sphinx", "-W", "--keep-going", "-n", "-q", "-b", "html",
                           "-d", str(out / ".doctrees"), str(top / "docs"), str(out)],
                          capture_output=True, text=True, env=env, cwd=top, timeout=600)
    assert done.returncode == 0, (done.stdout[-4000:] + done.stderr[-6000:]
                                  + "\n(pip install -e '.[docs]' installs what builds the site)")
    return out


@pytest.mark.ngspice
def test_the_site_builds_without_a_warning_and_its_links_resolve(site: Path) -> None:
    assert broken_links(site) == []
    pages = {p.relative_to(site).as_posix() for p in site.rglob("*.html")}
    assert {"index.html", "getting-started.html", "physics.html", "extending.html", "api/index.html",
            "guide/simulate.html", "guide/spectrum.html", "guide/scenes.html", "guide/studies.html",
            "guide/batch.html", "guide/report.html", "guide/requirements.html"} <= pages
    # the API reference: the top-level names and the modules named in issue 33
    assert {"api/generated/lcchain.Request.html", "api/generated/lcchain.simulate.html",
            "api/generated/lcchain.runs.request.html", "api/generated/lcchain.circuit.effects.html",
            "api/generated/lcchain.circuit.exact.html", "api/generated/lcchain.studies.store.html"} <= pages
    assert "Parameters" in (site / "api/generated/lcchain.Chain.html").read_text(encoding="utf-8")


@pytest.mark.ngspice
def test_the_gallery_ran_and_kept_its_figures(site: Path) -> None:
    scripts = sorted(p.stem for p in (DOCS / "gallery").glob("plot_*.py"))
    assert 3 <= len(scripts) <= 5
    for stem in scripts:
        page = (site / "gallery-generated" / f"{stem}.html").read_text(encoding="utf-8")
        figures = re.findall(r'src="(\.\./_images/sphx_glr_' + stem + r'_\d+\.png)"', page)
        assert figures, stem
        assert all((site / "gallery-generated" / f).resolve().stat().st_size > 10_000 for f in figures)


def test_the_extending_guide_is_a_page_of_the_site_as_it_is() -> None:
    """tests/test_extending.py runs its marked blocks; the site shows the same file, not a copy of it."""
    index = (DOCS / "index.md").read_text(encoding="utf-8")
    assert re.search(r"(?m)^extending$", index)
    assert not (DOCS / "guide" / "extending.md").exists()
