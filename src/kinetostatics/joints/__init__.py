"""Joint types.  Importing this package registers the built-in types."""

from .base import JOINT_TYPES, Anchor, Block, Circle, Glyph, Joint, Line, joint_type
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
    "Revolute",
    "Prismatic",
    "Gear",
    "Rack",
]
