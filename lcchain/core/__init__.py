"""The vocabulary every layer shares: errors, option sets, limits, checks, frozen values.

Imports nothing from the rest of lcchain.
"""

#: lcchain's version, stated here once (pyproject.toml reads it: ``[tool.setuptools.dynamic]``), so that a command's
#: start does not import ``importlib.metadata`` (30 ms, with the email package) to learn it.  It is in every run's
#: key, so a change here is a new version of every stored result.
__version__ = "0.2.0"
