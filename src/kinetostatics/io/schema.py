"""The JSON Schema of a mechanism file, made from the loader's own key tables.

Every mapping the loader checks with :meth:`~kinetostatics.base.spec.Entry.check` has a
:class:`~kinetostatics.base.keys.Keys` table (``LINK_KEYS``, ``DRIVER_KEYS``, a joint
type's ``spec_keys``, …); :func:`schema` assembles them, so a key added to the loader is
in the schema too.  ``mechanism.schema.json`` beside this module is the schema written
out (``tests/io/test_schema.py`` checks it equals :func:`schema`); ``kinetostatics schema``
prints it; docs/yaml.md tells how to point an editor at it.

What a schema cannot see (the loader reports it): a number written as a word
(``mass: heavy`` is text like the expression ``2*m``), names that refer to nothing,
values out of range (but for a count such as ``analysis.positions``), geometry that does
not assemble.  It does see a unit name that is not a unit (each kind's spellings as a
pattern), a count that is not whole, and a key that another key requires (a
``journal_radius`` with its ``coefficient``, an axis's ``direction`` with its ``point``).
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from ..base import units
from ..base.files import json_text
from ..base.keys import ANY, NAME, NUMBER, TEXT, VECTOR, list_of, names, shape_schema
from ..base.names import SCHEMA_PATTERN
from ..base.spec import RESERVED
from ..joints import JOINT_TYPES
from . import bodies, clearance, drive, drivers, elements, loads, settings
from .builder import TOP_KEYS

__all__ = ["schema", "schema_text", "SCHEMA_FILE"]

SCHEMA_FILE = Path(__file__).with_name("mechanism.schema.json")
# a name of the file's own (link, joint, driver, load, parameter): the loader's rule, as far
# as a JSON Schema pattern can tell it (base/names.py)
NAME_PATTERN = SCHEMA_PATTERN


def _named(item, reserved: bool = True) -> dict[str, Any]:
    """A mapping from names to ``item``s."""
    key: dict[str, Any] = {"pattern": NAME_PATTERN}
    if reserved:
        key["not"] = {"enum": sorted(RESERVED)}
    return {"type": "object", "propertyNames": key, "additionalProperties": item}


def _joint() -> dict[str, Any]:
    """A joint: ``type`` one of the registered types, then that type's keys."""
    kinds = sorted(JOINT_TYPES)
    return {
        "type": "object",
        "required": ["type", "links"],
        "properties": {"type": {"enum": kinds}},
        "allOf": [
            {
                "if": {"properties": {"type": {"const": kind}}, "required": ["type"]},
                "then": shape_schema(JOINT_TYPES[kind].spec_keys),
            }
            for kind in kinds
            if JOINT_TYPES[kind].spec_keys is not None
        ],
    }


def _element() -> dict[str, Any]:
    """An element: ``type`` one of the element types, then that type's keys."""
    kinds = list(elements.ELEMENT_KEYS)
    return {
        "type": "object",
        "required": ["type"],
        "properties": {"type": {"enum": kinds}},
        "allOf": [
            {
                "if": {"properties": {"type": {"const": kind}}, "required": ["type"]},
                "then": shape_schema(elements.ELEMENT_KEYS[kind]),
            }
            for kind in kinds
        ],
    }


def _sections() -> dict[str, Any]:
    """The shape of each top-level key (``TOP_KEYS``)."""
    return {
        "name": TEXT,
        "units": {
            "type": "object",
            "properties": {
                kind: {"type": "string", "pattern": units.unit_pattern(kind)}
                for kind in units.QUANTITY_KINDS
            },
            "propertyNames": {"enum": list(units.QUANTITY_KINDS)},
        },
        "parameters": _named(NUMBER, reserved=False),
        "gravity": VECTOR,
        "ground": NAME,
        "links": {**_named(shape_schema(bodies.LINK_KEYS)), "minProperties": 1},
        "joints": _named(_joint()),
        "loops": list_of(names(minimum=2)),
        "drivers": _named(shape_schema(drivers.DRIVER_KEYS)),
        "loads": _named(shape_schema(loads.LOAD_KEYS)),
        "elements": _named(_element()),
        "output": NAME,
        "sketch": {"type": "object", "additionalProperties": VECTOR},
        "analysis": shape_schema(settings.ANALYSIS_KEYS),
        "flywheel": shape_schema(settings.FLYWHEEL_KEYS),
        "drive": shape_schema(drive.DRIVE_KEYS),
        "sweep": ANY,  # the variants of a batch: read by the batch (docs/batch.md)
        "clearance": {
            "type": "object",
            "additionalProperties": shape_schema(clearance.CLEARANCE_KEYS),
        },
    }


def schema() -> dict[str, Any]:
    """The JSON Schema (draft 2020-12) of a mechanism YAML file."""
    sections = _sections()
    if set(sections) != set(TOP_KEYS):  # a top-level key of the loader without a shape
        raise RuntimeError(
            f"schema and loader differ on the top-level keys: {set(sections) ^ set(TOP_KEYS)}"
        )
    return {
        "$schema": "https://json-schema.org/draft/2020-12/schema",
        "title": "kinetostatics mechanism file",
        "description": (
            "A planar linkage for kinetostatics (docs/yaml.md). Generated from the "
            "loader's key tables by `kinetostatics schema`."
        ),
        "type": "object",
        "required": ["links", "joints"],
        "properties": {key: sections[key] for key in TOP_KEYS},
        "additionalProperties": False,
    }


def schema_text() -> str:
    """:func:`schema` as the text of ``mechanism.schema.json``."""
    return json_text(schema(), ensure_ascii=False) + "\n"
