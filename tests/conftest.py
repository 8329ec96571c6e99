"""Test configuration: the ngspice and gnucap markers, and helpers on the import path via this folder.

Tests marked ``ngspice`` (``gnucap``) run the real simulator.  When it is missing they
skip with the command that installs it, except under CI (``CI`` set), where a
missing simulator is a failure: CI must never pass by skipping the circuit.
"""

from __future__ import annotations

import os
import shutil
import stat
import tempfile
from collections.abc import Iterator
from pathlib import Path

import pytest

INSTALL = "bash .ci/setup (or: sudo apt-get install ngspice libngspice0)"
INSTALL_GNUCAP = "bash .ci/setup (or: sudo apt-get install gnucap)"
INSTALL_CHROMIUM = "bash .ci/setup test (or: sudo apt-get install chromium; pip install playwright)"


def _missing(what: str, install: str) -> None:
    if os.environ.get("CI"):
        pytest.fail(f"{what} is not installed, and CI must run these tests: {install}", pytrace=False)
    pytest.skip(f"{what} is not installed: {install}")


def _has_playwright() -> bool:
    try:
        import playwright.sync_api  # noqa: F401
    except ImportError:
        return False
    return True


def pytest_runtest_setup(item: pytest.Item) -> None:
    if item.get_closest_marker("ngspice") is not None and shutil.which("ngspice") is None:
        _missing("ngspice", INSTALL)
    if item.get_closest_marker("gnucap") is not None and shutil.which("gnucap") is None:
        _missing("gnucap", INSTALL_GNUCAP)
    if item.get_closest_marker("chromium") is not None:
        if shutil.which("chromium") is None:
            _missing("Chromium", INSTALL_CHROMIUM)
        if not _has_playwright():
            _missing("Playwright", INSTALL_CHROMIUM)


@pytest.fixture(scope="session", autouse=True)
def private_temporary_folder(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Path]:
    """A temporary folder of the session's own (children too), so tests can see what a run leaves there."""
    folder = tmp_path_factory.mktemp("tmpdir")
    with pytest.MonkeyPatch.context() as patch:
        patch.setenv("TMPDIR", str(folder))
        patch.setattr(tempfile, "tempdir", str(folder))
        yield folder


def _devnull_is_a_device() -> bool:
    return stat.S_ISCHR(os.stat(os.devnull).st_mode)


@pytest.fixture(autouse=True)
def devnull_left_alone() -> Iterator[None]:
    """The test that turns the machine's ``/dev/null`` into a file fails, by name: CI runs as root, where renaming
    over a device replaces it (it happened once on this machine, from an unknown command, and every gnucap
    version check that reads ``/dev/null`` then hung)."""
    before = _devnull_is_a_device()
    yield
    if before and not _devnull_is_a_device():
        pytest.fail(f"this test replaced {os.devnull} (now a {stat.filemode(os.stat(os.devnull).st_mode)} file): "
                    "tests must write only inside their tmp_path", pytrace=False)
