"""Optional third-party packages, imported when a feature first needs them."""

from __future__ import annotations

import importlib
from types import ModuleType

from ..errors import MissingPackageError

__all__ = ["require"]


def require(module: str, extra: str, feature: str) -> ModuleType:
    """The module ``module``, or :class:`~kinetostatics.errors.MissingPackageError`
    saying that ``feature`` needs it and how to install it (the extra ``extra``)."""
    top = module.split(".")[0]
    try:
        return importlib.import_module(module)
    except ModuleNotFoundError as exc:
        if exc.name is not None and exc.name.split(".")[0] != top:  # the package is there,
            why = f"which cannot be imported ({exc})"  # but lacks one of its own needs
        else:
            why = "which is not installed"
    except ImportError as exc:  # installed, but broken or built for another NumPy
        why = f"which cannot be imported ({exc})"
    raise MissingPackageError(
        f"{feature} needs the package '{top}', {why}: "
        f"pip install 'kinetostatics[{extra}]' (or pip install {top})"
    ) from None
