"""Members and quantities as the reader names them: the links' numbers (the file's
``number:``, else the model's order with the frame last), the textbook's symbols built on
them (ω₄, F_R34, M_I4) and a column of ``results.csv`` as a label in the report's
language (``导杆.omega`` → ``构件4 角速度 ω₄``; ``link 4 angular velocity ω₄``).

The pictures and the report take every link number and column label from here.
"""

from __future__ import annotations

from .lang import tr

__all__ = [
    "column_label",
    "link_numbers",
    "member",
    "numbered",
    "pair",
    "reaction_symbol",
    "subscript",
]

_SUBSCRIPT = str.maketrans("0123456789", "₀₁₂₃₄₅₆₇₈₉")


def link_numbers(system) -> dict[str, int]:
    """The number of every link: its ``number:`` in the file; the links without one take
    the smallest numbers not given, the moving links in ``System.links`` order and the
    frame last (no link numbered: moving links 1…n, the frame n + 1)."""
    model = system.model
    given = {lk.name: lk.number for lk in model.links if lk.number is not None}
    used = set(given.values())
    nums: dict[str, int] = {}
    k = 1
    for name in [*system.links, model.ground.name]:
        if name in given:
            nums[name] = given[name]
            continue
        while k in used:
            k += 1
        nums[name] = k
        used.add(k)
    return nums


def numbered(model) -> bool:
    """Whether the file numbers its links (``number:``): the report then names a link by
    its number (构件4, link 4), else by its name."""
    return any(lk.number is not None for lk in model.links)


def subscript(n: int) -> str:
    """``n`` in subscript digits: ω₄, α₁₂."""
    return str(n).translate(_SUBSCRIPT)


def pair(i: int, j: int) -> str:
    """The subscript of a pair of links: ``34``, or ``10,11`` when a number has two digits."""
    return f"{i}{j}" if i < 10 and j < 10 else f"{i},{j}"


def reaction_symbol(links, nums: dict[str, int]) -> str:
    """The reaction at a joint between ``links`` ``[i, j]``, the force of link i on link j:
    ``F_R61`` (frame 6 on crank 1)."""
    return "F_R" + pair(nums[links[0]], nums[links[1]])


def member(name: str, nums: dict[str, int], model, lang: str = "en") -> str:
    """The link ``name`` as the report names it: ``构件4`` / ``link 4`` when the file numbers
    its links, else its own name."""
    if numbered(model):
        return tr("link {n}", lang, n=nums[name])
    return name


# the quantity (English; Chinese in zh.py) and its symbol, {n} the link's number
_LINK = {
    "theta": ("angular position", "θ{n}"),
    "omega": ("angular velocity", "ω{n}"),
    "alpha": ("angular acceleration", "α{n}"),
}
# {p}: the point's name (with its link's number where several links have the point)
_POINT = {
    "x": ("coordinate", "x_{p}"),
    "y": ("coordinate", "y_{p}"),
    "vx": ("velocity", "v_{p}x"),
    "vy": ("velocity", "v_{p}y"),
    "|v|": ("velocity", "v_{p}"),
    "ax": ("acceleration", "a_{p}x"),
    "ay": ("acceleration", "a_{p}y"),
    "|a|": ("acceleration", "a_{p}"),
}
# {r}: the reaction's symbol F_Rij, {ij} its pair
_JOINT = {
    "Fx": ("reaction", "{r}x"),
    "Fy": ("reaction", "{r}y"),
    "|F|": ("reaction", "{r}"),
    "N": ("normal force", "N{ij}"),
    "M": ("couple", "M{ij}"),
    "friction": ("friction effort", "F_f{ij}"),
}
_DRIVER = {
    "torque": ("driving torque", "M_b"),
    "force": ("driving force", "F_b"),
    "efficiency": ("efficiency", "η"),
}
_SUFFIX = {
    "": "",
    "_friction": " (with friction)",
    "_friction_approx": " (with friction, approximate)",
}
_ALONE = {
    "angle": ("driver angle", "φ"),
    "travel": ("driver travel", ""),
    "time": ("time", "t"),
    "stroke": ("driver stroke", "s"),
    "friction.status": ("friction status", ""),
    "friction.iterations": ("friction iterations", ""),
    "power.input": ("input power", "P"),
    "power.friction": ("friction loss", "P_f"),
}


def _one_place(model, point: str) -> bool:
    """Whether every link's point called ``point`` is one place at every position: one link
    has it, or the links that have it are pinned together there (the pairs'
    ``coincident()``): then ``v_B`` says which; else ``v_B4`` (B on link 4)."""
    having = [lk.name for lk in model.links if point in lk.points]
    group = {name: name for name in having}

    def root(n: str) -> str:
        while group[n] != n:
            n = group[n]
        return n

    for j in model.joints:
        for a, b in j.coincident():
            if a.point == b.point == point and a.link in group and b.link in group:
                group[root(a.link)] = root(b.link)
    return len({root(n) for n in having}) <= 1


def _suffixed(quantity: str) -> tuple[str, str]:
    """``Fx_friction`` → (``Fx``, ``_friction``)."""
    for suffix in ("_friction_approx", "_friction"):
        if quantity.endswith(suffix) and quantity != suffix[1:]:
            return quantity[: -len(suffix)], suffix
    return quantity, ""


def _text(who: str, quantity: str, symbol: str, suffix: str, lang: str) -> str:
    words = tr(quantity, lang) + (tr(_SUFFIX[suffix], lang) if suffix else "")
    return " ".join(part for part in (who, words, symbol) if part)


def column_label(system, name: str, lang: str = "en") -> str:
    """The column ``name`` of the results (``lever.omega``, ``crank.A.|v|``,
    ``O2.Fx_friction``, ``motor.torque``) as the reader names it: who, the quantity in
    ``lang`` and the textbook's symbol with the link numbers of :func:`link_numbers`
    (``构件4 角速度 ω₄``, ``O2 反力（计摩擦） F_R61x``); a column it does not know
    (an element's, a group's) keeps its name."""
    model = system.model
    nums = link_numbers(system)
    if name in _ALONE:
        quantity, symbol = _ALONE[name]
        return _text("", quantity, symbol, "", lang)
    parts = name.split(".")
    links = {lk.name for lk in model.links}
    if parts[0] in links and len(parts) == 2 and parts[1] in _LINK:
        quantity, symbol = _LINK[parts[1]]
        who = member(parts[0], nums, model, lang)
        return _text(who, quantity, symbol.format(n=subscript(nums[parts[0]])), "", lang)
    if parts[0] in links and len(parts) == 3 and parts[2] in _POINT:
        quantity, symbol = _POINT[parts[2]]
        point = parts[1]
        if not _one_place(model, point):
            point += str(nums[parts[0]])
        who = tr("point {p}", lang, p=point)
        return _text(who, quantity, symbol.format(p=point), "", lang)
    joints = {j.name: j for j in model.joints}
    if parts[0] in joints and len(parts) == 2:
        quantity, suffix = _suffixed(parts[1])
        if quantity in _JOINT:
            j = joints[parts[0]]
            word, symbol = _JOINT[quantity]
            ij = pair(nums[j.links[0]], nums[j.links[1]])
            symbol = symbol.format(r=reaction_symbol(j.links, nums), ij=ij)
            return _text(parts[0], word, symbol, suffix, lang)
    drivers = {d.name for d in model.drivers}
    if parts[0] in drivers and len(parts) == 2:
        quantity, suffix = _suffixed(parts[1])
        if quantity in _DRIVER:
            word, symbol = _DRIVER[quantity]
            return _text(parts[0], word, symbol, suffix, lang)
    return name
