"""Joint types.  Importing this package registers the built-in types."""

from .base import JOINT_TYPES, Anchor, Block, Circle, Curve, Glyph, Joint, Line, joint_type
from .cam import Cam
from .gear import Gear
from .prismatic import Prismatic
from .rack import Rack
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
