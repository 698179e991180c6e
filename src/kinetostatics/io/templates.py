"""The course-design templates: the classic topics as commented mechanism files.

Each template is a YAML file shipped in ``kinetostatics/templates/``: a mechanism file
whose ``parameters:`` block starts with the design data of the guide's table (its first
row) and derives every dimension from them, followed by a ``template:`` mapping that
``kinetostatics init`` reads and does not write::

    template:
      zh: 插床                       # the Chinese name (accepted by init too)
      title: slotting machine        # the English title (the written file's name:)
      description: one line for init --list
      rows:                          # the guide's data table, one row per 方案
        I: {n1: 60, K: 2, ...}       # each key a data line of parameters:
        II: {...}

:func:`render` writes the chosen row's numbers into those ``parameters:`` lines (their
comments kept), names the row in ``name:`` and puts the whole table, as comments, where
the ``template:`` mapping was.  docs/templates.md lists the templates.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from importlib import resources

import yaml

from ..errors import KinetostaticsError, did_you_mean

__all__ = ["NAMES", "Template", "TemplateError", "load_template", "render", "templates"]

# the order of `init --list`; tests/io/test_templates.py checks it against the files
NAMES: tuple[str, ...] = ("slotting", "shaper", "press", "jaw_crusher", "saw")

_ROMAN = ("I", "II", "III", "IV", "V", "VI", "VII", "VIII", "IX", "X", "XI", "XII")
_MARK = "template:"


class TemplateError(KinetostaticsError, ValueError):
    """An unknown template or data row named on ``kinetostatics init``: one line naming
    what was written and listing the valid choices."""


@dataclass(frozen=True)
class Template:
    """One template: its names, its one-line description, its rows and its text."""

    name: str
    zh: str
    title: str
    description: str
    rows: dict[str, dict[str, float]]
    text: str

    def row(self, label: str | None) -> str:
        """The row key for ``label``: ``II``, ``ii``, ``2`` or ``Ⅱ`` all name row II;
        ``None``: the first row."""
        if label is None:
            return next(iter(self.rows))
        word = str(label).strip()
        if len(word) == 1 and 0x2160 <= ord(word) <= 0x216B:  # Ⅰ … Ⅻ
            word = _ROMAN[ord(word) - 0x2160]
        if word.isdigit() and 1 <= int(word) <= len(_ROMAN):
            word = _ROMAN[int(word) - 1]
        for key in self.rows:
            if key.upper() == word.upper():
                return key
        raise TemplateError(
            f"--data {label}: template {self.name} ({self.zh}) has no such row; "
            f"its rows are {', '.join(self.rows)}"
        )


def _folder():
    return resources.files("kinetostatics").joinpath("templates")


def load_template(name: str) -> Template:
    """The template ``name``: an English name of :data:`NAMES` or its Chinese name."""
    all_ = templates()
    for t in all_:
        if name in (t.name, t.zh):
            return t

    choices = ", ".join(f"{t.name} ({t.zh})" for t in all_)
    raise TemplateError(
        f"no template '{name}'{did_you_mean(name, [t.name for t in all_])}; "
        f"the templates are {choices} (kinetostatics init --list)"
    )


def templates() -> list[Template]:
    """Every shipped template, in the order of :data:`NAMES`."""
    out = []
    for name in NAMES:
        text = _folder().joinpath(f"{name}.yaml").read_text(encoding="utf-8")
        meta = yaml.safe_load(text[_start(text) :])["template"]
        rows = {str(k): dict(v) for k, v in meta["rows"].items()}
        out.append(
            Template(
                name, meta["zh"], meta["title"], " ".join(meta["description"].split()), rows, text
            )
        )
    return out


def _start(text: str) -> int:
    """Where the ``template:`` mapping starts (a line of its own at column 0)."""
    m = re.search(rf"^{_MARK}\s*$", text, re.M)
    if m is None:  # a shipped template always has one (tests/io/test_templates.py)
        raise ValueError("a template without its template: mapping")
    return m.start()


def _number(value) -> str:
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise ValueError(f"a template row holds {value!r}, not a number")
    return str(value) if isinstance(value, int) else f"{value:.12g}"


def render(template: Template, label: str | None = None) -> str:
    """The mechanism file of ``template`` with the data of row ``label`` (default the
    first): its data lines in ``parameters:`` hold the row's numbers, ``name:`` names
    the row, and the guide's table follows as comments."""
    key = template.row(label)
    values = template.rows[key]
    head = template.text[: _start(template.text)]
    lines = head.splitlines(keepends=True)
    inside, seen = False, set()
    for k, line in enumerate(lines):
        if re.match(r"^\S", line) and not line.startswith("#"):
            inside = line.startswith("parameters:")
            if line.startswith("name:"):
                lines[k] = f"name: {template.title} (row {key})\n"
            continue
        m = re.match(r"^(  ([^\s:#]+):\s*)(\S+)(\s*)(#.*)?$", line.rstrip("\n"))
        if inside and m and m.group(2) in values:
            text = m.group(1) + _number(values[m.group(2)])
            if m.group(5):  # the comment stays in its column
                column = len(m.group(1)) + len(m.group(3)) + len(m.group(4))
                text = text.ljust(column - 1) + " " + m.group(5)
            lines[k] = text + "\n"
            seen.add(m.group(2))
    missing = [name for name in values if name not in seen]
    if missing:  # a template's rows and its parameters disagree (tests/io/test_templates.py)
        raise ValueError(f"template {template.name}: no parameters line for {missing}")
    intro = (
        f"# Written by `kinetostatics init {template.name} --data {key}` from the template "
        f"{template.zh} ({template.title}), row {key} of the table at the end of this file.\n"
    )
    return intro + "".join(lines).rstrip("\n") + "\n\n" + _table(template, key)


def _table(template: Template, chosen: str) -> str:
    """The rows as a comment table, the chosen one marked."""
    keys = list(next(iter(template.rows.values())))
    cells = [["row", *keys]] + [
        [name, *(_number(row[k]) for k in keys)] for name, row in template.rows.items()
    ]
    widths = [max(len(c[i]) for c in cells) for i in range(len(keys) + 1)]
    out = [
        f"# The data table of this template ({template.zh} {template.title}); this file is row "
        f"{chosen}.",
        f"# Another row: kinetostatics init {template.name} --data ROW --out FILE",
    ]
    for c in cells:
        mark = "  <-" if c[0] == chosen else ""
        out.append("#   " + "  ".join(v.rjust(w) for v, w in zip(c, widths)) + mark)
    return "\n".join(out) + "\n"
