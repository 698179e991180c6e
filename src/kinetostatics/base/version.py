"""The package's version, from the installed distribution's metadata."""

from __future__ import annotations

from importlib.metadata import PackageNotFoundError, version

__all__ = ["VERSION"]

try:
    VERSION = version("kinetostatics")
except PackageNotFoundError:  # a source tree that is not installed
    VERSION = "0+unknown"
