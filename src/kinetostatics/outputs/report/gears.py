"""The gear chapter: each toothed pair's involute geometry, every value with its formula,
and the notes (undercut, a contact ratio below 1, a shifted pair's working centre distance).
The numbers and formulas are the ``gears`` entry of methods.json (the record of
``methods/gears.py`` as a dict, which its caller passes: an output does not compute it)."""

from __future__ import annotations

import re

from ..lang import tr
from .blocks import _Heading, _List, _Para, _Table

# the quantity of each formula, by its key in the record's ``formulas`` ({n}: the gear)
QUANTITIES = {
    "m": "module",
    "alpha": "pressure angle",
    "h_a*": "addendum coefficient",
    "c*": "clearance coefficient",
    "z_": "number of teeth of gear {n} ({link})",
    "x_": "profile shift coefficient of gear {n}",
    "r_": "pitch radius of gear {n}",
    "r_b": "base radius of gear {n}",
    "r_a": "tip radius of gear {n}",
    "r_f": "root radius of gear {n}",
    "s_": "tooth thickness on the pitch circle of gear {n}",
    "alpha_a": "pressure angle at the tip circle of gear {n}",
    "x_min": "least profile shift without undercut of gear {n}",
    "p": "pitch",
    "p_b": "base pitch",
    "a": "standard centre distance",
    "a_file": "centre distance of the file's pitch circles",
    "alpha_w": "working pressure angle",
    "a_w": "working centre distance",
    "y": "centre distance modification coefficient",
    "dy": "tip reduction coefficient",
    "epsilon": "contact ratio",
    "z_min": "least number of teeth without undercut",
}
# a rack pair's centre distance is the pinion centre's height above the rack
RACK = {
    "a": "height of the pinion's centre above the rack's reference line",
    "a_file": "pitch radius of the pinion in the file",
}
MESHES = {"external": "external mesh", "internal": "internal mesh", "rack": "rack and pinion"}
_PER_GEAR = re.compile(r"^(z_|x_min|x_|r_b|r_a|r_f|r_|s_|alpha_a)(\d)$")


def _quantity(key: str, pair: dict, lang: str) -> str:
    """The name of the formula ``key`` of ``pair`` in ``lang``."""
    per_gear = _PER_GEAR.match(key)
    if per_gear is None:
        text = RACK.get(key) if pair["mesh"] == "rack" else None
        return tr(text or QUANTITIES.get(key, key), lang)
    stem, n = per_gear.group(1), int(per_gear.group(2))
    wheel = pair["wheels"][n - 1]
    link = wheel["link"] + (", " + tr("annulus", lang) if wheel["annulus"] else "")
    return tr(QUANTITIES[stem], lang, n=n, link=link)


def gear_blocks(gears: dict, lang: str = "en", number: int = 11) -> list:
    """Blocks of chapter ``number`` from methods.json's ``gears`` entry (``Gears.to_dict()``);
    none for a file without toothed pairs."""
    T = lambda s, **k: tr(s, lang, **k)  # noqa: E731
    pairs, incomplete = gears.get("pairs", {}), gears.get("incomplete", {})
    if not pairs and not incomplete:
        return []
    unit = next(iter(pairs.values()))["formula_length_unit"] if pairs else "mm"
    blocks: list = [
        _Heading(2, T("{n}. Gears", n=number)),
        _Para(
            T(
                "Standard involute teeth: each value with its formula, lengths in {unit}. "
                "h_a*: addendum coefficient, c*: clearance coefficient, x: profile shift "
                "coefficient (positive away from the gear's axis), α': working pressure angle.",
                unit=unit,
            )
        ),
    ]
    for k, (joint, pair) in enumerate(pairs.items(), start=1):
        mesh = T(MESHES[pair["mesh"]])
        rows = [[_quantity(key, pair, lang), text] for key, text in pair["formulas"].items()]
        blocks += [
            _Heading(3, T("{n}.{k} Gear pair {joint} ({mesh})", n=number, k=k, joint=joint,
                          mesh=mesh)),
            _Table([T("quantity"), T("formula and value")], rows,
                   T("Gear pair {joint}: geometry", joint=joint)),
        ]  # fmt: skip
        if pair["notes"]:
            blocks.append(_List([T(n["template"], **n["values"]) for n in pair["notes"]]))
    for joint, why in incomplete.items():
        blocks.append(_Para(T("{joint}: {why}", joint=joint, why=T(why))))
    return blocks
