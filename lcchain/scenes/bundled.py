"""The example scenes that ship with lcchain, inside the package (``lcchain examples``).

They are the TOML files of ``lcchain/scenes/examples/`` (``examples/scenes/``
in the repository points there), so an installed wheel has them too: ``lcchain
examples`` lists them and ``lcchain examples NAME`` writes one where the user
works, to run or to edit.
"""

from __future__ import annotations

import tomllib
from importlib import resources

from ..core.errors import ParameterError

__all__ = ["example_names", "example_text", "example_title"]

_FOLDER = "examples"


def _files() -> dict[str, resources.abc.Traversable]:
    folder = resources.files(__package__ or "lcchain.scenes") / _FOLDER
    return {entry.name.removesuffix(".toml"): entry for entry in folder.iterdir() if entry.name.endswith(".toml")}


def example_names() -> list[str]:
    """The example scenes' names (a file's name without ``.toml``), sorted."""
    return sorted(_files())


def example_text(name: str) -> str:
    """The TOML text of an example scene.

    Raises
    ------
    ParameterError
        No example of that name (the message lists them).
    """
    files = _files()
    if name not in files:
        raise ParameterError("NAME", name, "the name of an example scene: " + ", ".join(sorted(files)))
    return files[name].read_text(encoding="utf-8")


def example_title(name: str) -> str:
    """The scene's ``title``, or its first comment line when it has none."""
    text = example_text(name)
    title = tomllib.loads(text).get("title")
    if isinstance(title, str) and title:
        return title
    return next((line.lstrip("# ").strip() for line in text.splitlines() if line.startswith("#")), "")
