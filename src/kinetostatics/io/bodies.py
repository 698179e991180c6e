"""The ``links:`` and ``joints:`` sections (a joint's own keys are read by its type,
found in the registry of :mod:`kinetostatics.joints`; a pin shared by three or more
links becomes one revolute per pair)."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import yaml

from ..base.keys import NUMBER, VECTOR, Keys, whole
from ..base.limits import MAGNITUDE, MAX_LINKS
from ..base.spec import Entry, name_problem
from ..errors import KinetostaticsError, Location, did_you_mean
from ..joints import Joint, Revolute, joint_type
from ..model import Link
from .sizing import MATERIAL_KEYS, SECTION_KEYS

COUNTERWEIGHT_KEYS = Keys({"at": VECTOR, "mass": NUMBER, "inertia": NUMBER}, ("at", "mass"))
LINK_KEYS = Keys(
    {
        "points": {"type": "object", "additionalProperties": VECTOR},
        "mass": NUMBER,
        "weight": NUMBER,
        "com": VECTOR,
        "inertia": NUMBER,
        "counterweights": {"type": "object", "additionalProperties": COUNTERWEIGHT_KEYS},
        "number": whole(1, 99),
        "section": SECTION_KEYS,  # the sizing keys (io/sizing.py, docs/sizing.md)
        "material": MATERIAL_KEYS,
    }
)
MAX_NUMBER = 99  # a link's textbook number: F_R12 … F_R10,11 stay readable


def _number(e: Entry, name: str, numbered: dict[int, str]) -> int | None | bool:
    """The link's ``number:`` (its number in the textbook's figure: 1 the frame, 2 the
    crank, …): a whole number from 1 to :data:`MAX_NUMBER`, no two links alike; None when
    not given, False after a problem (reported)."""
    if (ne := e.get("number")) is None:
        return None
    v = ne.number(None, bounded=False)
    if v is None:
        return False
    if v != int(v) or not 1 <= v <= MAX_NUMBER:
        ne.error(f"a link's number must be a whole number from 1 to {MAX_NUMBER}, got {v:g}")
        return False
    if int(v) in numbered:
        ne.error(f"number {int(v)} is already the number of link '{numbered[int(v)]}'")
        return False
    numbered[int(v)] = name
    return int(v)


def with_counterweights(
    mass: float, com: np.ndarray, inertia: float, added: list[tuple[float, np.ndarray, float]]
) -> tuple[float, np.ndarray, float]:
    """(mass, CoM, inertia about the CoM) of a link with point masses or discs ``added``
    ((mass, place in the link's frame, own inertia about its centre)): the masses add, the
    CoM is the mass-weighted mean of the places, and each body's inertia is carried to the
    new CoM by the parallel-axis theorem, I + m·|c − c'|²."""
    if not added:
        return mass, com, inertia
    total = mass + sum(m for m, _, _ in added)
    if not total > 0.0:
        return mass, com, inertia + sum(i for _, _, i in added)
    first = mass * com + sum((m * p for m, p, _ in added), np.zeros(2))
    c = first / total
    j = inertia + mass * float(np.sum((com - c) ** 2))
    for m, p, i in added:
        j += i + m * float(np.sum((p - c) ** 2))
    return total, c, j


class BodySections:
    """Reads ``ground:``, ``links:`` and ``joints:``.

    A mixin of :class:`~kinetostatics.io.builder.Builder`: it uses the builder's ``top``, ``ctx``,
    ``problems`` and name bookkeeping (``_claim``, ``_broken``, ``_not_a``).
    """

    def _links(self, gravity: np.ndarray) -> list[Link]:
        section = self.top.get("links")
        if section is None or not section.mapping():
            self.lost.add("link")
            return []
        keys = section.keys()
        where = self.top.key_where("links")
        if not keys:
            self.problems.add(where, "no links: give the ground and the moving links")
            self.lost.add("link")
            return []
        if len(keys) > MAX_LINKS:  # refused whole: nothing that names a link is checked
            self.problems.add(where, f"{len(keys)} links; the limit is {MAX_LINKS}")
            self.lost.add("link")
            return []
        if (g := self.top.get("ground")) is not None:
            name = g.text()
            if name is not None and name not in keys:
                g.error(
                    f"the ground link '{name}' is not among the links"
                    f"{did_you_mean(name, keys)}; the links are: {', '.join(keys)}"
                )
            elif name is not None:
                self.ground = name
        elif "ground" in keys:
            self.ground = "ground"
        else:
            self.problems.add(
                where,
                "no ground link: name a link 'ground', or give the "
                "top-level key 'ground: <link>' naming the frame",
            )
        links = []
        numbered: dict[int, str] = {}  # number -> the link that has it
        for name, e in section.items():
            link, n = None, None
            if self._claim(section, name, "link") and e.check(LINK_KEYS):
                link = self._link(name, e, gravity, section.key_where(name))
                n = _number(e, name, numbered)
                if not self._link_sizing(name, e):
                    link = None
            if link is None or n is False:
                self.broken["link"].add(name)
            else:
                links.append(link if n is None else replace(link, number=n))
        return links

    def _link(self, name: str, e: Entry, gravity: np.ndarray, where: Location) -> Link | None:
        is_ground = name == self.ground
        com = e["com"].vector("length") if e.get("com") is not None else np.zeros(2)
        raw: dict[str, np.ndarray] = {}
        ok = True
        if (pts := e.get("points")) is not None and pts.mapping():
            for pname, pe in pts.items():
                if problem := name_problem("point", pname):
                    self.problems.add(pts.key_where(pname), problem)
                    ok = False
                    continue
                v = pe.vector("length")
                if v is None:
                    ok = False
                else:
                    raw[pname] = v
        elif pts is not None:
            ok = False
        mass = inertia = 0.0
        if e.get("mass") is not None and e.get("weight") is not None:
            e["weight"].error("give either mass or weight, not both")
            mass = None
        elif e.get("mass") is not None:
            mass = e["mass"].number("mass", minimum=0.0)
        elif e.get("weight") is not None:
            w = e["weight"].number("force", minimum=0.0)
            g = float(np.hypot(*gravity))
            if w is not None and w > 0 and g == 0.0:
                e["weight"].error(
                    "a weight needs a non-zero gravity to give a mass "
                    "(gravity is [0, 0]); give the mass instead"
                )
                w = None
            mass = None if w is None else (w / g if w else 0.0)
            if mass and not MAGNITUDE["mass"][0] <= mass <= MAGNITUDE["mass"][1]:
                e["weight"].error(
                    f"a weight of {w:g} N with |gravity| = {g:g} m/s^2 gives a mass "
                    f"of {mass:g} kg; the mass must be from "
                    f"{MAGNITUDE['mass'][0]:g} to {MAGNITUDE['mass'][1]:g} kg"
                )
                mass = None
        if e.get("inertia") is not None:
            inertia = e["inertia"].number("inertia", minimum=0.0)
        if is_ground and (mass or inertia):
            e.error("the ground link takes no mass or inertia")
        added = self._counterweights(e, is_ground)
        if com is None or mass is None or inertia is None or not ok or added is None:
            return None
        mass, com, inertia = with_counterweights(float(mass), com, float(inertia), added)
        return Link(
            name,
            {k: v - com for k, v in raw.items()},
            float(mass),
            float(inertia),
            com,
            is_ground,
            where,
        )

    def _counterweights(
        self, e: Entry, is_ground: bool
    ) -> list[tuple[float, np.ndarray, float]] | None:
        """The link's ``counterweights:`` as (mass, place, own inertia), places in the
        link's frame (that of ``points:`` and ``com:``); None after a problem."""
        section = e.get("counterweights")
        if section is None:
            return []
        if not section.mapping():
            return None
        if is_ground and section.keys():
            section.error("the ground link takes no counterweights")
            return None
        out: list[tuple[float, np.ndarray, float]] | None = []
        for name, c in section.items():
            if problem := name_problem("counterweight", name):
                self.problems.add(section.key_where(name), problem)
                out = None
                continue
            if not c.check(COUNTERWEIGHT_KEYS):
                out = None
                continue
            at = c["at"].vector("length")
            m = c["mass"].number("mass", minimum=0.0)
            i = c["inertia"].number("inertia", minimum=0.0) if c.get("inertia") else 0.0
            if at is None or m is None or i is None:
                out = None
            elif out is not None:
                out.append((float(m), at, float(i)))
        return out

    def _joints(self, links: list[Link], points) -> list[Joint]:
        section = self.top.get("joints")
        if section is None or not section.mapping():
            self.lost.add("joint")
            return []
        link_names = [link.name for link in links]
        joints = []
        for name, e in section.items():
            joint = None
            if self._claim(section, name, "joint") and e.mapping():
                if _is_pin(e):
                    pin = self._pin(name, e, links, link_names, points)
                    joints += pin or []
                    if pin is None:
                        self.broken["joint"].add(name)
                    continue
                joint = self._joint(name, e, links, link_names, points)
                if joint is not None and joint.pin and not self._joint_sizing([name], e):
                    joint = None
            if joint is None:
                self.broken["joint"].add(name)
            else:
                joints.append(joint)
        return joints

    def _joint(self, name: str, e: Entry, links, link_names, points) -> Joint | None:
        t = e.require("type")
        kind = t.text()
        if kind is None:
            return None
        try:
            cls = joint_type(kind)
        except KeyError as exc:  # unknown: the message lists the registered types
            t.error(exc.args[0])
            return None
        le = e.require("links")
        pair = le.names(2)
        if None in pair:
            return None
        bad = False
        for k, ln in enumerate(pair):
            if ln not in link_names:
                if not self._broken("link", ln):
                    le._child(k, le.node.value[k]).error(self._not_a("link", ln, link_names, links))
                bad = True
        if bad:
            return None
        if pair[0] == pair[1]:
            le.error(f"both links are '{pair[0]}'; a joint connects two different links")
            return None
        try:
            return cls.from_spec(name, e, tuple(pair), points)
        except KinetostaticsError:
            raise
        except Exception as exc:  # a joint type's reader must not crash the loader
            e.error(
                f"cannot read this {kind} joint ({type(exc).__name__}: {exc}); "
                "this is a bug in the joint type, please report it"
            )
            return None

    def _pin(self, name: str, e: Entry, links, link_names, points) -> list[Joint] | None:
        """A pin shared by the links of ``links: [hub, a, b, ...]``: the revolutes
        ``<name>_a`` = [hub, a], ``<name>_b`` = [hub, b], ... at the points of
        ``points`` (default: the point ``<name>`` on each link), each with the
        pin's ``friction`` (docs/yaml.md, "Pins shared by three or more links")."""
        e.check(Revolute.spec_keys)
        le = e["links"]
        items = le.seq() or []
        if len(items) < 2:
            le.error(
                f"a revolute connects two links, or three or more that share one pin; "
                f"got {len(items)}"
            )
            return None
        names = [x.text() for x in items]
        if None in names:
            return None
        bad = False
        for k, ln in enumerate(names):
            if ln not in link_names:
                if not self._broken("link", ln):
                    items[k].error(self._not_a("link", ln, link_names, links))
                bad = True
            elif ln in names[:k]:
                items[k].error(f"link '{ln}' is listed twice; each link of a pin once")
                bad = True
        pts = e["points"].names(len(names)) if e.get("points") is not None else [name] * len(names)
        rho = Revolute.friction_radius(e)
        if bad or None in pts or rho is None:
            return None
        hub = names[0]
        p_hub = e.point(hub, pts[0], points, key="points", index=0)
        out, gens = [], []
        for k in range(1, len(names)):
            gen = f"{name}_{names[k]}"
            p_k = e.point(names[k], pts[k], points, key="points", index=k)
            if gen in self.names:
                other, first = self.names[gen][0], self._first_named(gen)
                self.problems.add(
                    self.top["joints"].key_where(name),
                    f"the pin's revolute {hub}-{names[k]} is named '{gen}', but the "
                    f"{other} at line {first.line} has that name; rename one",
                )
                bad = True
                continue
            self.names[gen] = ("joint", e.where, None)
            self.generated[gen] = (name, hub, names[k])
            gens.append(gen)
            if p_hub is not None and p_k is not None:
                out.append(
                    Revolute(
                        gen, (hub, names[k]), e.where, p_hub, p_k, (pts[0], pts[k]), float(rho)
                    )
                )
        self.pins[name] = gens
        if not self._joint_sizing(gens, e):
            bad = True
        if bad or len(out) != len(names) - 1:
            self.broken["joint"].update(gens)
            return None
        return out


def _is_pin(e: Entry) -> bool:
    """Whether a joint entry is a revolute whose ``links`` is not a pair (a pin shared
    by three or more links, or a list too short, reported by ``_pin``)."""
    t, links_ = e.get("type"), e.get("links")
    return (
        t is not None
        and isinstance(t.node, yaml.ScalarNode)
        and t.node.value == "revolute"
        and links_ is not None
        and isinstance(links_.node, yaml.SequenceNode)
        and len(links_.node.value) != 2
    )
