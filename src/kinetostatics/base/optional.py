"""Optional third-party packages, imported when a feature first needs them."""

from __future__ import annotations

import importlib
from types import ModuleType

from ..errors import MissingPackageError

__all__ = ["require"]


def require(module: str, extra: str, feature: str) -> ModuleType:
    """The module ``module``, or :class:`~kinetostatics.errors.MissingPackageError`
    saying that ``feature`` needs it and how to install it (the extra ``extra``)."""
    try:
        return importlib.import_module(module)
    except ImportError:
        top = module.split(".")[0]
        raise MissingPackageError(
            f"{feature} needs the package '{top}', which is not installed: "
            f"pip install 'kinetostatics[{extra}]' (or pip install {top})"
        ) from None
