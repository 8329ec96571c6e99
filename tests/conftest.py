"""Test configuration: the ngspice marker, and helpers on the import path via this folder.

Tests marked ``ngspice`` run the real simulator.  When ngspice is missing they
skip with the command that installs it, except under CI (``CI`` set), where a
missing simulator is a failure: CI must never pass by skipping the circuit.
"""

from __future__ import annotations

import os
import shutil
import tempfile
from collections.abc import Iterator
from pathlib import Path

import pytest

INSTALL = "bash .ci/setup (or: sudo apt-get install ngspice libngspice0)"


def pytest_runtest_setup(item: pytest.Item) -> None:
    if item.get_closest_marker("ngspice") is None or shutil.which("ngspice") is not None:
        return
    if os.environ.get("CI"):
        pytest.fail(f"ngspice is not installed, and CI must run the circuit tests: {INSTALL}", pytrace=False)
    pytest.skip(f"ngspice is not installed: {INSTALL}")


@pytest.fixture(scope="session", autouse=True)
def private_temporary_folder(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Path]:
    """A temporary folder of the session's own (children too), so tests can see what a run leaves there."""
    folder = tmp_path_factory.mktemp("tmpdir")
    with pytest.MonkeyPatch.context() as patch:
        patch.setenv("TMPDIR", str(folder))
        patch.setattr(tempfile, "tempdir", str(folder))
        yield folder
