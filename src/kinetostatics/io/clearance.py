"""The ``clearance:`` section: the clearance of each revolute (docs/clearance.md) and its
contact law, read into ``Model.clearances``.  Expanding a model with them solves the
linkage, so it is not done here: :func:`kinetostatics.outputs.loading.load` does it."""

from __future__ import annotations

from ..base.keys import NUMBER, Keys, enum, list_of, one_of
from ..errors import did_you_mean
from ..model import Clearance

CLEARANCE_MODELS = ("prescribed", "contact")
CONTACT_KEYS = Keys(
    {
        "journal_radius": NUMBER,
        "young": one_of(NUMBER, list_of(NUMBER)),
        "poisson": one_of(NUMBER, list_of(NUMBER)),
        "restitution": NUMBER,
        "stiffness": NUMBER,
        "floor": NUMBER,
    }
)
CLEARANCE_KEYS = Keys(
    {
        "size": NUMBER,
        "model": enum(CLEARANCE_MODELS),
        "speed": NUMBER,
        "acceleration": NUMBER,
        "angle": NUMBER,
        "contact": CONTACT_KEYS,
    },
    required=("size",),
)


class ClearanceSection:
    """Reads ``clearance:``.

    A mixin of :class:`~kinetostatics.io.builder.Builder`: it uses the builder's ``top``, ``ctx``,
    ``problems`` and name bookkeeping (``_claim``, ``_broken``, ``_not_a``).
    """

    def _clearances(self, joints) -> list:
        """The ``clearance:`` section: {joint: {size, model, speed, acceleration,
        angle, contact}} (docs/clearance.md)."""
        section = self.top.get("clearance")
        if section is None or not section.mapping():
            return []
        by_name = {j.name: j for j in joints}
        out = []
        for name, e in section.items():
            if not e.mapping():
                continue
            if name not in by_name:
                if not self._broken("joint", name):
                    section.error(self._not_a("joint", name, by_name))
                continue
            if by_name[name].kind != "revolute":
                e.error(f"clearance applies to a revolute; '{name}' is {by_name[name].kind}")
                continue
            e.check(CLEARANCE_KEYS)
            size = e.require("size").number("length", minimum=0.0)
            kind = e["model"].text() if e.get("model") is not None else "prescribed"
            if kind is not None and kind not in CLEARANCE_MODELS:
                e["model"].error(
                    f"unknown clearance model '{kind}'"
                    f"{did_you_mean(kind, CLEARANCE_MODELS)}; "
                    "known: contact, prescribed"
                )
                continue
            rates = {}
            for key in ("speed", "acceleration"):  # the angle unit per s, per s²
                rates[key] = e[key].number("angle") if e.get(key) is not None else 0.0
            angle = e["angle"].number("angle") if e.get("angle") is not None else None
            contact = None
            if kind == "contact":
                contact = read_contact(e.require("contact"))
            elif e.get("contact") is not None:
                e["contact"].error("contact applies to model: contact")
            if (
                size is None
                or kind is None
                or None in rates.values()
                or (kind == "contact" and contact is None)
            ):
                continue
            out.append(
                Clearance(
                    name, size, kind, rates["speed"], rates["acceleration"], angle, contact, e.where
                )
            )
        return out


def read_contact(e):
    """A :class:`ContactLaw` from the YAML entry ``contact: {journal_radius, young,
    poisson, restitution, stiffness, floor}`` (young in Pa, one value or [E_i, E_j])."""
    from ..model.contact_law import ContactLaw  # when a file has a clearance

    if not e.check(CONTACT_KEYS):
        return None
    kw = {}
    if e.get("journal_radius") is not None:
        kw["journal_radius"] = e["journal_radius"].number("length", minimum=0.0, strict=True)
    for key in ("young", "poisson"):
        if (x := e.get(key)) is not None:
            vals = x.seq()
            vals = [v.number(None) for v in vals] if vals is not None else [x.number(None)]
            if None in vals or len(vals) not in (1, 2):
                x.error(f"{key}: one value or two [link i, link j]")
                return None
            kw[key] = tuple(vals * (3 - len(vals)))[:2]
    if (x := e.get("restitution")) is not None:
        kw["restitution"] = x.number(None, minimum=0.0)
        if kw["restitution"] is not None and kw["restitution"] > 1:
            x.error("the coefficient of restitution must be from 0 to 1")
            return None
    if (x := e.get("stiffness")) is not None:
        kw["stiffness"] = x.number(None, minimum=0.0, strict=True)
    if (x := e.get("floor")) is not None:
        kw["floor"] = x.number(None, minimum=0.0, strict=True)
    if None in kw.values():
        return None
    return ContactLaw(**kw)
