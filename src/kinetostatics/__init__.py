"""kinetostatics: kinetostatic analysis of planar linkages described in YAML.

>>> import kinetostatics as ks
>>> model = ks.load("mechanisms/slider_crank.yaml")      # doctest: +SKIP
>>> result = ks.analyze(model)                           # doctest: +SKIP
>>> result["motor.torque"].max()                         # doctest: +SKIP
"""

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
from .model import Model
from .outputs.loading import load, loads

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


def __getattr__(name):  # keep `import kinetostatics` light: load stages on use
    if name == "analyze":
        from .analysis import analyze

        return analyze
    if name == "Result":
        from .analysis.results import Result

        return Result
    if name == "optimize":
        from .batch.optimize import optimize

        return optimize
    if name == "set_backend":
        from .base.kernels import set_backend

        return set_backend
    if name == "build_system":
        from .structure.system import build_system

        return build_system
    if name == "yaml_io" or name in _aliases.OLD_PATHS:  # ks.yaml_io.dump, ks.plotting, …
        import importlib

        return importlib.import_module(f"{__name__}.{name}")
    raise AttributeError(f"module 'kinetostatics' has no attribute '{name}'")
