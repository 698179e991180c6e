"""YAML text <-> :class:`~kinetostatics.model.Model`; never analyses.

:func:`read` and :func:`read_string` give the model as written (its ``clearance:``
section read into ``Model.clearances`` but not expanded: expanding solves the
linkage, which :mod:`kinetostatics.outputs.loading` does); :func:`build` builds a tree of
:func:`compose` again with other parameter values; :func:`dump` writes a model back.
The schema is documented in ``docs/yaml.md``.
"""

from ..base.document import compose, read_text
from .builder import TOP_KEYS, build, read, read_string
from .dump import dump

__all__ = ["read", "read_string", "compose", "read_text", "build", "dump", "TOP_KEYS"]
