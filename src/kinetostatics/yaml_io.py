"""YAML text <-> :class:`~kinetostatics.model.Model` (the documented path; docs/yaml.md):
re-exports of :mod:`.loading` (load, loads, build), :mod:`.io` (dump), :mod:`.base.document` and
:mod:`.base.spec` (the reader) and :mod:`.base.limits` (the limits of a file)."""

from .base import document, limits, spec
from .base.document import *  # noqa: F403
from .base.limits import *  # noqa: F403
from .base.spec import *  # noqa: F403
from .io import TOP_KEYS, dump
from .outputs.loading import build, load, loads

__all__ = [
    "load",
    "loads",
    "build",
    "dump",
    "TOP_KEYS",
    *document.__all__,
    *spec.__all__,
    *limits.__all__,
]
