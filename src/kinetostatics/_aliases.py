"""Import paths from before the layer packages, kept working for users' scripts.

``import kinetostatics.positions`` gives the module ``kinetostatics.kinematics.positions``
itself (the same object, so attributes set on one are seen through the other).  Code in
the package and its tests use the new paths; docs/architecture.md lists both.
"""

from __future__ import annotations

import importlib
import importlib.util
import sys

OLD_PATHS = {
    "_checks": "base.arguments",
    "_files": "base.files",
    "_geometry": "base.geometry",
    "_linalg": "base.linalg",
    "best": "batch.best",
    "checks": "analysis.checks",
    "clearance": "dynamics.clearance",
    "cli_batch": "cli.batch",
    "cli_dynamics": "cli.dynamics",
    "cli_pictures": "cli.pictures",
    "contact": "dynamics.contact",
    "differences": "kinematics.differences",
    "drivers": "structure.drivers",
    "dyads": "kinematics.dyads",
    "expressions": "base.expressions",
    "flywheel": "dynamics.flywheel",
    "forces": "kinetics.forces",
    "friction": "kinetics.friction",
    "graph": "structure.graph",
    "motion": "model.motion",
    "plotting": "outputs.plotting",
    "positions": "kinematics.positions",
    "reactions": "kinetics.reactions",
    "report": "outputs.report",
    "results": "analysis.results",
    "stacking": "model.stacking",
    "summary": "outputs.summary",
    "sweeps": "batch.sweeps",
    "system": "structure.system",
    "units": "base.units",
    "variants": "batch.variants",
    "vectorised": "analysis.vectorised",
}


class _Alias:
    # a meta path finder and its loader by protocol (find_spec; create_module and
    # exec_module), not by importlib.abc's base classes: importing importlib.abc loads
    # importlib.resources, tempfile, urllib and ipaddress, ~8 % of every command's start
    def find_spec(self, fullname, path=None, target=None):
        head, _, tail = fullname.partition(".")
        if head != __package__ or tail not in OLD_PATHS:
            return None
        return importlib.util.spec_from_loader(fullname, self)

    def create_module(self, spec):
        module = importlib.import_module(f"{__package__}.{OLD_PATHS[spec.name.partition('.')[2]]}")
        spec.loader_state = module.__spec__  # the import system sets __spec__ to the alias's
        return module

    def exec_module(self, module):
        module.__spec__ = module.__spec__.loader_state  # the module keeps its own spec


def install() -> None:
    if not any(isinstance(f, _Alias) for f in sys.meta_path):
        sys.meta_path.insert(0, _Alias())
