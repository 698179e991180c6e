"""kinetostatics: kinetostatic analysis of planar linkages described in YAML.

The public API is ``__all__`` (``dir(kinetostatics)`` lists it) and the public methods of
its classes; a joint author's extension points are in ``kinetostatics.joints``
(docs/api.md says what is public, docs/extending.md how to add a joint type).

>>> import kinetostatics as ks
>>> model = ks.load("mechanisms/slider_crank.yaml")      # doctest: +SKIP
>>> result = ks.analyze(model)                           # doctest: +SKIP
>>> result["motor.torque"].max()                         # doctest: +SKIP
"""

from __future__ import annotations

import importlib
from typing import TYPE_CHECKING, Any

from . import _aliases
from .base.version import VERSION
from .errors import (
    AssemblyError,
    KinetostaticsError,
    LostInertiaError,
    ModelError,
    NearSingularWarning,
    NonFiniteResultError,
    OutputError,
    SelfLockingError,
    SingularConfigurationError,
    StructureError,
)

if TYPE_CHECKING:  # what the lazy names are, for type checkers (nothing imported at run time)
    from .analysis.pipeline import analyze
    from .analysis.results import Result
    from .base.kernels import set_backend
    from .batch.optimize import optimize
    from .model import Model
    from .outputs.loading import load, loads
    from .structure.system import build_system

__version__ = VERSION  # the installed distribution's (pyproject.toml)

_aliases.install()  # the import paths from before the layer packages (docs/architecture.md)

__all__ = [
    "__version__",
    "load",
    "loads",
    "analyze",
    "Model",
    "Result",
    "KinetostaticsError",
    "ModelError",
    "StructureError",
    "AssemblyError",
    "SingularConfigurationError",
    "SelfLockingError",
    "NonFiniteResultError",
    "LostInertiaError",
    "OutputError",
    "NearSingularWarning",
    "build_system",
    "optimize",
    "set_backend",
]

# The names of __all__ whose modules are imported on first use, so that `import
# kinetostatics` stays light: no NumPy until a name needs it (the command line sets
# NumPy's BLAS threads before it loads, cli.main), no scipy, no matplotlib.
_LAZY = {
    "load": "outputs.loading",
    "loads": "outputs.loading",
    "Model": "model",
    "analyze": "analysis.pipeline",
    "Result": "analysis.results",
    "optimize": "batch.optimize",
    "set_backend": "base.kernels",
    "build_system": "structure.system",
}

# What every module shows besides its API (``dir()`` of a module lists them).
_MODULE_DUNDERS = ("__doc__", "__file__", "__loader__", "__name__", "__package__", "__path__")


def __getattr__(name: str) -> Any:
    if name in _LAZY:
        return getattr(importlib.import_module(f"{__name__}.{_LAZY[name]}"), name)
    if name == "yaml_io" or name in _aliases.OLD_PATHS:  # ks.yaml_io.dump, ks.plotting, …
        return importlib.import_module(f"{__name__}.{name}")
    raise AttributeError(f"module 'kinetostatics' has no attribute '{name}'")


def __dir__() -> list[str]:
    """The public names (``__all__``, lazy ones included) and a module's own dunders."""
    return sorted({*__all__, *_MODULE_DUNDERS, "__all__", "__spec__"})
