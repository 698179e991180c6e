"""The chapter "Vector equations" (矢量方程图解法): methods.json's ``vector_equations`` entry
written out as the textbook does, at each position of the detailed chapters, group by group
in the order of the solution: each velocity and acceleration equation's line, a table with
one column per term and the rows direction (方向), magnitude (大小: its formula where known
before the group is solved, "?" where not) and the solved value; under each group its solved
unknowns (ω, α, sliding speeds) and the largest closure residual.  It formats the dict the
report's caller passes (an output does not compute it)."""

from __future__ import annotations

import math
import re

from ..lang import tr
from .blocks import _Heading, _Para, _Table

_DYAD = re.compile(r"^([A-Z]{3}) dyad (\{.*\})$")
_DRIVEN = re.compile(r"^driven links? (\{.*\})$")
_GROUP = re.compile(r"^(\d+)-link group (\{.*\})$")
_NOTE = re.compile(r"^(.+) \((.+)\): (.+ for this pair type)$")
_AXIS = re.compile(r"the axis of (\S+)")
# the words of the higher pairs' directions (joints/_meshrelative.py, joints/_camrelative.py)
_WORDS = (
    "the tangent of the pitch curve",
    "the tangent of the profile",
    "the tangent of the face",
    "its centre of curvature",
    "the line of action",
    "the face",
)
_PHRASE = re.compile("|".join(re.escape(w) for w in _WORDS))
_UNITS = {"velocity": "m/s", "acceleration": "m/s²"}


def _g(v, digits: int = 4) -> str:
    """A number to ``digits`` significant digits; "–" for none (null in methods.json)."""
    return "–" if v is None or not math.isfinite(v) else f"{v + 0.0:.{digits}g}"  # no −0


def _group_title(label: str, lang: str) -> str:
    """The group's label of methods.json (``RPR dyad {block, bar}``) in ``lang``."""
    if m := _DYAD.match(label):
        return tr("{letters} dyad {links}", lang, letters=m[1], links=m[2])
    if m := _DRIVEN.match(label):
        return tr("driving link {links}", lang, links=m[1])
    if m := _GROUP.match(label):
        return tr("{n}-link group {links}", lang, n=m[1], links=m[2])
    return label


def _note(note: str, lang: str) -> str:
    """A group's note (``slot (slide): accelerations not written for this pair type``)."""
    if m := _NOTE.match(note):
        return f"{m[1]} ({tr(m[2], lang)}): {tr(m[3], lang)}"
    return note


def _text(s: str, lang: str) -> str:
    """A direction or magnitude text of the record (formulas stay; its words translated)."""
    if s in ("known", "?", ""):
        return tr(s, lang) if s == "known" else s
    s = _AXIS.sub(lambda m: tr("the axis of {joint}", lang, joint=m[1]), s)
    return _PHRASE.sub(lambda m: tr(m[0], lang), s)


def _table(eq: dict, lang: str) -> _Table:
    """One column per term (left side, then right); rows 方向, 大小, the solved value."""
    T = lambda s, **k: tr(s, lang, **k)  # noqa: E731
    terms = [*eq["lhs"], *eq["rhs"]]
    unit = _UNITS.get(eq["kind"], "")
    rows = [
        [T("direction"), *(_text(t["direction"], lang) for t in terms)],
        [T("magnitude"), *(_text(t["magnitude"], lang) for t in terms)],
        [T("value, {unit}", unit=unit), *(_g(t["value"]) for t in terms)],
    ]
    return _Table(["", *(t["symbol"] for t in terms)], rows, "")


def _group_blocks(g: dict, lang: str) -> list:
    T = lambda s, **k: tr(s, lang, **k)  # noqa: E731
    blocks: list = [_Para(T("{group}:", group=_group_title(g["group"], lang)))]
    for eq in g["equations"]:
        what = T("Velocity") if eq["kind"] == "velocity" else T("Acceleration")
        line = T("{kind} at the pair {joint}: {equation}", kind=what, joint=eq["joint"],
                 equation=eq["text"])  # fmt: skip
        blocks += [_Para(line), _table(eq, lang)]
    solved = ", ".join(f"{s['symbol']} = {_g(s['value'])} {s['unit']}" for s in g["solved"])
    residual = max((e["residual"] or 0.0 for e in g["equations"]), default=0.0)
    blocks.append(
        _Para(T("Solved: {solved}; closure residual {res} (relative).", solved=solved,
                res=_g(residual, 2)))
    )  # fmt: skip
    blocks += [_Para(T("Not written: {note}", note=_note(n, lang))) for n in g["notes"]]
    return blocks


def vector_blocks(entry: dict, lang: str = "en", number: int = 11) -> list:
    """Blocks of chapter ``number`` from methods.json's ``vector_equations`` entry
    (``{label: VectorPosition.to_dict()}``); none for an empty entry."""
    T = lambda s, **k: tr(s, lang, **k)  # noqa: E731
    if not entry:
        return []
    blocks: list = [
        _Heading(2, T("{n}. Vector equations", n=number)),
        _Para(
            T(
                "The velocity and acceleration equations of the vector-polygon method, group "
                "by group in the order of the solution: each pair of a group equates its two "
                "links' views of its point. Per term: its direction, its magnitude (the "
                'formula where it is known before the group is solved, "?" for the group\'s '
                "two unknowns) and its value from the solution. a^n normal, a^t tangential, "
                "a^r relative, a^k Coriolis (2ω × v_r) acceleration; ω, α counter-clockwise "
                "positive. The closure residual is |Σ left − Σ right| over the largest term."
            )
        ),
    ]
    for k, (label, p) in enumerate(entry.items(), start=1):
        blocks.append(_Heading(3, T("{n}.{k} Position {pos}", n=number, k=k, pos=label)))
        for g in p["groups"]:
            blocks += _group_blocks(g, lang)
    return blocks
