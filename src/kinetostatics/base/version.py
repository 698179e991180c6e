"""The package's version: the one place it is written (pyproject.toml reads it from here,
so the installed metadata agrees and importing the package reads no metadata)."""

from __future__ import annotations

__all__ = ["VERSION"]

VERSION = "0.1.0"
