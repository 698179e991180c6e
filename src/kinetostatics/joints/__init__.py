"""Joint types: ``JOINT_TYPES`` (YAML ``type:`` -> class) holds the built-in types,
each imported when first named (``joint_type``), and any subclass of ``Joint`` with
``kind=`` once its module is imported."""

from .base import JOINT_TYPES, Anchor, Block, Circle, Curve, Glyph, Joint, Line, joint_type
from .prismatic import Prismatic
from .revolute import Revolute

__all__ = [
    "Joint",
    "JOINT_TYPES",
    "joint_type",
    "Anchor",
    "Glyph",
    "Block",
    "Line",
    "Circle",
    "Curve",
    "Revolute",
    "Prismatic",
    "Gear",
    "Rack",
    "Cam",
]


def __getattr__(name: str):  # Cam, Gear, Rack: imported when first asked for
    kinds = {"Cam": "cam", "Gear": "gear", "Rack": "rack"}
    if name in kinds:
        return JOINT_TYPES[kinds[name]]
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
