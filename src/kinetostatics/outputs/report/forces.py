"""The chapter of the force polygons of the Assur groups: at the positions where the report
draws the velocity polygons, the last group first and the driving link last, per group its
free body and force polygon (``plotting/forces.py``) and a table of its forces with μ_F and
the closure error; the driving link's M_b.  It formats methods.json's ``force_polygons``
entry (and ``force_polygons_friction`` after it when the file has friction): an output
does not compute it."""

from __future__ import annotations

import math

from ..labels import link_numbers
from ..lang import tr
from ..plotting.forces import force_label, group_figure, group_title
from .blocks import _Heading, _Para, _Table

ROUND_OFF = 1e-9  # a force below this × the group's largest: 0 (round-off)


def _g(v, digits: int = 5) -> str:
    """A number to ``digits`` significant digits; "–" for none (null in methods.json)."""
    return "–" if v is None or not math.isfinite(v) else f"{v + 0.0:.{digits}g}"  # no −0


def _small(v, scale: float):
    return 0.0 if v is not None and abs(v) <= ROUND_OFF * scale else v


def _name(f: dict, numbers: dict) -> str:
    """The picture's label in plain text (F_R23, G_5, M_b), the file's name beside it."""
    label = force_label(f, numbers).strip("$").replace("{", "").replace("}", "")
    return label if label == f["name"] else f"{label} ({f['name']})"


def _row(f: dict, scale: float, numbers: dict, lang: str) -> list[str]:
    """A force: name, link, point (mm), vector (N) or couple (N·m), known/solved."""
    vx, vy = (_small(v, scale) for v in f["vector"])
    vector = f"{_g(vx)}, {_g(vy)}"
    if f.get("couple"):
        vector = (vector + "; " if (vx or vy) else "") + f"M = {_g(f['couple'])} N·m"
    point = ", ".join(_g(None if v is None else 1e3 * _small(v, 1.0)) for v in f["point"])
    return [_name(f, numbers), f["link"], point, vector, tr(f["status"], lang)]


def _balancing(group: dict) -> str:
    """The driving link's balancing effort: M_b (N·m) or F_b (N)."""
    for f in group["forces"]:
        if f["kind"] == "balancing":
            if f["name"].startswith("M_b"):
                return f"M_b = {_g(f['couple'])} N·m."
            return f"F_b = {_g(math.hypot(*f['vector']))} N."
    return ""


def _version(fp: dict, result, image, lang: str, where: tuple, drawn) -> list:  # noqa: PLR0913  the chapter's context
    """Subsections of one version (frictionless or with friction) at the drawn positions;
    ``where`` = (chapter number, first subsection number, file-name tag)."""
    T = lambda s, **k: tr(s, lang, **k)  # noqa: E731
    number, k, suffix = where
    numbers = link_numbers(result.system)
    header = [T("force"), T("link"), "P, mm", T("vector, N"), T("known/solved")]
    friction = T(" (with friction)") if suffix else ""
    blocks: list = []
    for p in fp["positions"]:
        label = p["label"]
        if drawn is not None and label not in drawn:
            continue
        tag = label.replace("′", "p").replace("/", "_t") + suffix
        blocks.append(_Heading(3, T("{n}.{k} Position {pos}", n=number, k=k, pos=label)
                               + friction))  # fmt: skip
        k += 1
        for i, g in enumerate(p["groups"], start=1):
            name = T("driving link {links}", links=", ".join(g["links"])) if g["driving"] else (
                group_title(g, lang))  # fmt: skip
            title = T("Position {pos}: {name}", pos=label, name=name) + friction
            scale = g["largest"] or 0.0
            blocks += [
                image(group_figure(g, numbers=numbers, title=title, lang=lang),
                      f"polygon_{tag}_{i}", title + ("。" if lang == "zh" else "."), True),
                _Table(header, [_row(f, scale, numbers, lang) for f in g["forces"]],
                       T("{title}: its forces", title=title)),
                _Para(T("μ_F = {mu} N/mm; closure error |ΣF| = {c} N ({e} of the largest "
                        "force, {big} N); moment error {m}.", mu=_g(g["mu_F"], 4),
                        c=_g(_small(g["closure"], scale), 3), e=_g(g["closure_error"], 2),
                        big=_g(g["largest"]), m=_g(g["moment_error"], 2))
                      + (" " + _balancing(g) if g["driving"] else "")),
            ]  # fmt: skip
    return blocks


def polygon_blocks(graded: dict, result, image, lang: str = "en", number: int = 10,
                   drawn=None) -> list:  # fmt: skip
    """Blocks of chapter ``number`` from methods.json's ``force_polygons`` entry (and
    ``force_polygons_friction`` after it); at the positions ``drawn`` (labels; None: all);
    ``image(fig, name, caption, true_scale)`` saves a figure as a block.  None without
    the entry."""
    T = lambda s, **k: tr(s, lang, **k)  # noqa: E731
    fp = graded.get("force_polygons")
    if not fp:
        return []
    blocks: list = [
        _Heading(2, T("{n}. Force polygons of the Assur groups", n=number)),
        _Para(
            T(
                "The graphical force analysis (图解法), group by group in the order of the "
                "solution: the last Assur group first, the driving link last. Per group its "
                "free body (the loads, weights, inertia forces and couples of its links, the "
                "reactions of the groups already solved: known; the reactions at its outer "
                "pairs: solved) and its force polygon, the vectors chained tip to tail at the "
                "round scale μ_F, which closes because the group is in equilibrium. F_Rij is "
                "the force of link i on link j. Points P in mm in the frame's axes; vectors "
                "(F_x, F_y) in N."
            )
        ),
    ]
    if fp.get("friction"):
        blocks.append(_Para(T("The forces are the frictionless solution's first.")))
    blocks += _version(fp, result, image, lang, (number, 1, ""), drawn)
    fric = graded.get("force_polygons_friction")
    if fric:
        k = 1 + sum(1 for b in blocks if isinstance(b, _Heading) and b.level == 3)
        blocks += _version(fric, result, image, lang, (number, k, "_f"), drawn)
    return blocks
