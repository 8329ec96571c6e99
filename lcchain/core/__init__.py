"""The vocabulary every layer shares: errors, option sets, limits, checks, frozen values.

Imports nothing from the rest of lcchain.
"""

from importlib.metadata import PackageNotFoundError, version

try:
    __version__ = version("lcchain")
except PackageNotFoundError:  # pragma: no cover - running from a source tree that was never installed
    __version__ = "0+unknown"
