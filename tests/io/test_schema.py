"""The JSON Schema of a mechanism file (io/schema.py): made from the loader's key tables,
shipped as io/mechanism.schema.json, printed by ``kinetostatics schema``.

Every shipped mechanism is valid; the broken files whose mistake is in the shape of the
text (an unknown key, a value of the wrong type, a name that is not a name, a missing
section) are rejected; the other broken files are valid as far as a schema can see,
because their mistake is in what a value means: a number that is a word (a string, like
any parameter expression), a name that refers to nothing, a value out of range, geometry
that does not assemble, two keys that exclude each other, or text that is not YAML."""

import json

import jsonschema
import pytest
import yaml

import kinetostatics as ks
from kinetostatics.cli import main
from kinetostatics.io.schema import SCHEMA_FILE, schema, schema_text
from kinetostatics.joints import JOINT_TYPES
from tests.helpers import MECHANISMS, ROOT

BROKEN = ROOT / "tests" / "broken"

# the mistake is in the shape of the text: the schema must reject these
SHAPE = {
    "unknown_top_level_key.yaml": "'drivrs' was unexpected",
    "unknown_link_key.yaml": "'mas' was unexpected",
    "unknown_unit_kind.yaml": "'lenght' is not one of",
    "unknown_joint_type.yaml": "'revolut' is not one of",
    "unknown_load_type.yaml": "'resistence' is not one of",
    "vector_three_numbers.yaml": "is too long",
    "prismatic_point_list.yaml": "is not of type 'string'",
    "invalid_name.yaml": "does not match",
    "reserved_name.yaml": "should not be valid",
    "missing_joints.yaml": "'joints' is a required property",
    "links_empty.yaml": "should be non-empty",
    "top_level_list.yaml": "is not of type 'object'",
    "empty_file.yaml": "None is not of type 'object'",
    # a key another key requires, a count that is not whole or below 1, a unit that is none
    # a coefficient alone takes the diameter of the joint's bearing, which it has not
    "journal_without_radius.yaml": "'bearing' is a required property",
    "prismatic_axis_no_point.yaml": "'point' is a required property",
    "positions_fraction.yaml": "1.5 is not of type 'integer', 'string'",
    "positions_zero.yaml": "0 is less than the minimum of 1",
    "unknown_unit.yaml": "'mmm' does not match",
    "two_problems.yaml": "'mmm' does not match",
}
# rejected, though their point lies elsewhere (the loader's limits on the text itself):
# the alias bomb's carrier key 'notes' and the nested lists given as the name
INCIDENTAL = {"alias_bomb.yaml", "deep_nesting.yaml"}
# not YAML that a YAML reader accepts (or not text): no schema applies
NOT_YAML = {
    "not_utf8.yaml",
    "python_tag.yaml",
    "tab_indent.yaml",
    "two_documents.yaml",
    "yaml_syntax_error.yaml",
}


@pytest.fixture(scope="module")
def validator():
    s = json.loads(SCHEMA_FILE.read_text(encoding="utf-8"))
    jsonschema.Draft202012Validator.check_schema(s)
    return jsonschema.Draft202012Validator(s)


def test_shipped_file_is_the_generated_schema():
    assert SCHEMA_FILE.read_text(encoding="utf-8") == schema_text(), (
        "io/mechanism.schema.json is out of date: write it with "
        "`kinetostatics schema --out src/kinetostatics/io/mechanism.schema.json`"
    )


def test_every_mechanism_is_valid(validator):
    assert MECHANISMS
    for path in MECHANISMS:
        errors = [e.message for e in validator.iter_errors(yaml.safe_load(path.read_text()))]
        assert not errors, (path.name, errors)


def _errors(validator, path):
    return [e.message for e in validator.iter_errors(yaml.safe_load(path.read_text()))]


@pytest.mark.parametrize("name", sorted(SHAPE))
def test_shape_mistakes_are_rejected(validator, name):
    errors = _errors(validator, BROKEN / name)
    assert any(SHAPE[name] in m for m in errors), errors
    with pytest.raises(ks.KinetostaticsError):  # and the loader agrees
        ks.load(BROKEN / name)


def test_other_broken_files_pass_the_schema(validator):
    """The classification above is exact: every other broken file is valid text."""
    others = sorted(
        p for p in BROKEN.glob("*.yaml") if p.name not in set(SHAPE) | INCIDENTAL | NOT_YAML
    )
    assert len(others) > 40
    for path in others:
        assert not _errors(validator, path), path.name
    for name in INCIDENTAL:
        assert _errors(validator, BROKEN / name), name


def test_schema_follows_the_loader_tables():
    """A key added to a loader table is in the schema; a joint type brings its keys."""
    from kinetostatics.io import bodies, builder

    s = schema()
    assert list(s["properties"]) == list(builder.TOP_KEYS)
    link = s["properties"]["links"]["additionalProperties"]
    assert list(link["properties"]) == list(bodies.LINK_KEYS.names)
    joint = s["properties"]["joints"]["additionalProperties"]
    assert joint["properties"]["type"]["enum"] == sorted(JOINT_TYPES)
    per_type = {b["if"]["properties"]["type"]["const"]: b["then"] for b in joint["allOf"]}
    assert set(per_type) == set(JOINT_TYPES)  # every registered type declares its keys
    for kind, cls in JOINT_TYPES.items():
        assert list(per_type[kind]["properties"]) == list(cls.spec_keys.names)
        assert per_type[kind]["required"] == list(cls.spec_keys.required)


def test_a_new_key_reaches_loader_and_schema(monkeypatch, validator):
    """The loader's message and the schema both come from LINK_KEYS."""
    from kinetostatics.base.keys import NUMBER, Keys
    from kinetostatics.io import bodies

    text = (ROOT / "mechanisms" / "slider_crank.yaml").read_text()
    text = text.replace("    mass: 3\n", "    mass: 3\n    colour: 7\n", 1)
    with pytest.raises(ks.ModelError, match="unknown key 'colour'"):
        ks.loads(text)
    messages = [e.message for e in validator.iter_errors(yaml.safe_load(text))]
    assert any("'colour' was unexpected" in m for m in messages), messages
    monkeypatch.setattr(bodies, "LINK_KEYS", Keys({**bodies.LINK_KEYS.shapes, "colour": NUMBER}))
    ks.loads(text)  # the loader takes it now
    fresh = jsonschema.Draft202012Validator(schema())
    assert not list(fresh.iter_errors(yaml.safe_load(text)))  # and so does the schema


def test_cli_schema(tmp_path, capsys):
    assert main(["schema"]) == 0
    assert json.loads(capsys.readouterr().out) == schema()
    out = tmp_path / "mechanism.schema.json"
    assert main(["schema", "--out", str(out)]) == 0
    assert out.read_text(encoding="utf-8") == schema_text()
    assert main(["schema", "--out", str(tmp_path / "no" / "such.json")]) == 2
    assert "--out" in capsys.readouterr().err


def test_unit_pattern_is_the_loader_s_units():
    """Each kind's pattern accepts exactly what units.factor accepts, over every spelling of
    every kind written with the freedom the loader allows (spaces, ·, ², µ) and broken ones."""
    import re

    from kinetostatics.base import units

    written = set()
    for spellings in units.UNITS.values():
        for u in spellings:
            written |= {
                u,
                f" {u} ",
                u.replace("*", " "),
                u.replace("*", " · "),
                u.replace("^2", "²"),
                u.replace("^2", " ** 2"),
                u.replace("u", "µ"),
                u.replace("/", " / "),
                u + "x",
                u.upper(),
                "k" + u,
            }
    for kind in units.QUANTITY_KINDS:
        pattern = re.compile(units.unit_pattern(kind))
        for u in written:
            try:
                units.factor(kind, u)
                known = True
            except units.UnitError:
                known = False
            assert bool(pattern.search(u)) == known, (kind, u)


def test_issue_36_shapes_rejected(validator):
    """A missing key that another requires, ``positions: 1.5``, an unknown unit: each is
    refused by the schema (and by the loader), while the shipped files stay valid."""
    text = (ROOT / "mechanisms" / "slider_crank.yaml").read_text()
    base = yaml.safe_load(text)
    assert not list(validator.iter_errors(base))
    joints = {**base["joints"], "O": {**base["joints"]["O"], "friction": {"coefficient": 0.1}}}
    cases = [
        ({**base, "units": {**base["units"], "length": "furlong"}}, "does not match"),
        ({**base, "analysis": {**base.get("analysis", {}), "positions": 1.5}}, "'integer'"),
        ({**base, "joints": joints}, "'bearing' is a required property"),
    ]
    for doc, message in cases:
        errors = [e.message for e in validator.iter_errors(doc)]
        assert any(message in m for m in errors), (message, errors)
        with pytest.raises(ks.ModelError):
            ks.loads(yaml.safe_dump(doc))
