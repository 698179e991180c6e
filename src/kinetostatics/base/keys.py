"""The keys of a YAML mapping and the shape of each value: one table, two readers.

The loader checks a mapping's keys against its :class:`Keys`
(:meth:`~kinetostatics.base.spec.Entry.check`); the JSON Schema of a mechanism file
(:mod:`kinetostatics.io.schema`) is made from the same tables, so that the schema and
the loader name the same keys.  A shape is a JSON Schema fragment; the fragments below
are what a key of the loader accepts *before* its value is read: a number may also be a
parameter expression (a string), so a schema cannot tell ``mass: heavy`` from
``mass: 2*m`` — the loader reports the first.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

__all__ = [
    "Keys",
    "NUMBER",
    "whole",
    "TEXT",
    "NAME",
    "BOOLEAN",
    "VECTOR",
    "ANY",
    "names",
    "list_of",
    "one_of",
    "enum",
    "shape_schema",
]

NUMBER: dict[str, Any] = {"type": ["number", "string"]}  # a number or an expression


TEXT: dict[str, Any] = {"type": ["string", "number"]}  # any scalar read as text
NAME: dict[str, Any] = {"type": "string"}  # a link, joint, point or unit name
BOOLEAN: dict[str, Any] = {"type": "boolean"}
VECTOR: dict[str, Any] = {"type": "array", "items": NUMBER, "minItems": 2, "maxItems": 2}
ANY: dict[str, Any] = {}


def whole(minimum: int, maximum: int) -> dict[str, Any]:
    """A whole number from ``minimum`` to ``maximum``, or an expression (the bounds apply
    to a number only)."""
    return {"type": ["integer", "string"], "minimum": minimum, "maximum": maximum}


def names(n: int | None = None, minimum: int = 1) -> dict[str, Any]:
    """A list of ``n`` names (``None``: at least ``minimum``)."""
    if n is None:
        return {"type": "array", "items": NAME, "minItems": minimum}
    return {"type": "array", "items": NAME, "minItems": n, "maxItems": n}


def list_of(shape) -> dict[str, Any]:
    return {"type": "array", "items": shape}


def one_of(*shapes) -> dict[str, Any]:
    return {"anyOf": list(shapes)}


def enum(values) -> dict[str, Any]:
    return {"enum": list(values)}


class Keys:
    """The keys of one mapping, in the order the loader lists them in its messages,
    each with the shape of its value; ``required`` the keys that must be there;
    ``extra``: JSON Schema keywords for what the loader requires of the keys together
    (``dependentRequired``, an ``if``/``then``), added to the mapping's schema."""

    def __init__(
        self,
        shapes: Mapping[str, Any],
        required: tuple[str, ...] = (),
        extra: Mapping[str, Any] | None = None,
    ):
        self.shapes = dict(shapes)
        self.required = tuple(required)
        self.extra = dict(extra or {})
        missing = set(self.required) - set(self.shapes)
        if missing:
            raise ValueError(f"required keys without a shape: {sorted(missing)}")

    @property
    def names(self) -> tuple[str, ...]:
        return tuple(self.shapes)

    def schema(self) -> dict[str, Any]:
        """The JSON Schema of such a mapping: these keys only, each of its shape."""
        out: dict[str, Any] = {
            "type": "object",
            "properties": {k: shape_schema(v) for k, v in self.shapes.items()},
            "additionalProperties": False,
        }
        if self.required:
            out["required"] = list(self.required)
        out.update(_convert(self.extra))
        return out


def shape_schema(shape) -> dict[str, Any]:
    """A shape as JSON Schema: a :class:`Keys` is a mapping's schema, a dict is as is
    (its nested :class:`Keys` converted)."""
    if isinstance(shape, Keys):
        return shape.schema()
    if isinstance(shape, dict):
        return {k: _convert(v) for k, v in shape.items()}
    raise TypeError(f"not a shape: {shape!r}")


def _convert(value):
    if isinstance(value, (Keys, dict)):
        return shape_schema(value)
    if isinstance(value, list):
        return [_convert(v) for v in value]
    return value
