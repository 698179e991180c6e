"""A composed tree -> :class:`~kinetostatics.model.Model`: the builder's core.

The sections are read in dependency order by the mixins of this package, one module
per section; the core holds what they share: the names declared so far and what is
in error, so that a message can say what a name is and one mistake gives one line.
Nothing here analyses: the ``clearance:`` section is read into ``Model.clearances``,
and :mod:`kinetostatics.outputs.loading` expands the model with it.
"""

from __future__ import annotations

import gc
from collections.abc import Iterable, Mapping
from contextlib import contextmanager
from pathlib import Path

import numpy as np

from ..base.document import compose, read_text
from ..base.spec import READING, RESERVED, Entry, _Context, name_problem
from ..errors import Location, did_you_mean
from ..model import Model
from .bodies import BodySections
from .clearance import ClearanceSection
from .drive import DriveSection
from .drivers import DriverSections
from .elements import ElementSections
from .laws import LawSections
from .loads import LoadSections
from .parameters import ParameterSections
from .settings import SettingSections
from .sizing import SizingSections

__all__ = ["Builder", "TOP_KEYS", "build", "read", "read_string"]

TOP_KEYS = (
    "name",
    "units",
    "parameters",
    "gravity",
    "ground",
    "links",
    "joints",
    "loops",
    "drivers",
    "loads",
    "elements",
    "sketch",
    "analysis",
    "flywheel",
    "drive",
    "output",
    "sweep",
    "clearance",
)


# what ``output:`` takes (docs/yaml.md, Output), the tail of each refusal
OUTPUT_KINDS = (
    "output takes a moving link that no motion driver moves on the frame, an undriven "
    "revolute, or an undriven prismatic pair on the frame"
)


def read(path: str | Path, parameters: Mapping[str, float] | None = None) -> Model:
    """A mechanism read from a YAML file as written: its clearances are in
    ``Model.clearances``, not expanded (:func:`kinetostatics.load` expands them).

    Raises :class:`~kinetostatics.errors.ModelError` listing every problem
    as ``FILE:LINE:COL: key.path: message``.
    """
    return read_string(read_text(path), file=str(path), parameters=parameters)


def read_string(
    text: str, file: str = "<string>", parameters: Mapping[str, float] | None = None
) -> Model:
    """A mechanism read from YAML text (see :func:`read`)."""
    with _collector_paused():
        return build(compose(text, file), parameters)


@contextmanager
def _collector_paused():
    """Python's cyclic garbage collector held off while a text is read: composing and
    building make tens of thousands of objects that stay alive until the model is made,
    and each collection the allocations trigger walks all of them, so a long file's
    reading grew faster than its length (a 121-link chain read 1.4× slower per link
    than a 21-link one).  A cycle made meanwhile is collected by the next collection
    after it, as usual; the collector is left as it was (off stays off)."""
    if not gc.isenabled():
        yield
        return
    gc.disable()
    try:
        yield
    finally:
        gc.enable()


def build(top: Entry, parameters: Mapping[str, float] | None = None) -> Model:
    """The model of a composed tree, with ``parameters`` replacing the values of
    the file's parameters of those names (numbers in the file's units; the
    parameters computed from them follow); its clearances read, not expanded
    (:func:`kinetostatics.outputs.loading.build` expands them).  Raises :class:`ModelError`."""
    ctx = _Context(top.ctx.file)
    ctx.overrides = dict(parameters or {})
    with READING:
        return Builder(top.rebuilt(ctx), ctx).build()


class Builder(
    ParameterSections,
    BodySections,
    DriverSections,
    LawSections,
    LoadSections,
    ElementSections,
    SettingSections,
    ClearanceSection,
    DriveSection,
    SizingSections,
):
    """Reads the top-level sections in dependency order.

    A declared item that cannot be built (its problem reported) is remembered
    in ``broken``; later references to it stay silent, so one mistake gives
    one line rather than a cascade.
    """

    def __init__(self, top: Entry, ctx: _Context):
        self.top, self.ctx, self.problems = top, ctx, ctx.problems
        # name -> (what, the section whose key it is, the key) or (what, location, None)
        self.names: dict[str, tuple[str, Entry | Location, str | None]] = {}
        self.broken: dict[str, set[str]] = {
            "link": set(),
            "joint": set(),
            "driver": set(),
            "load": set(),
            "element": set(),
        }
        self.ground: str | None = None
        self.lost: set[str] = set()  # kinds whose whole section is missing or unreadable
        self.sketch_where: dict[str, Location] = {}  # sketch key -> where written
        self.pins: dict[str, list[str]] = {}  # pin -> the revolutes it expands to
        self.generated: dict[str, tuple[str, str, str]] = {}  # revolute -> (pin, hub, link)

    def build(self) -> Model:
        top = self.top
        top.check_keys(required=("links", "joints"), optional=TOP_KEYS)
        name = top["name"].text() if top.get("name") else "mechanism"
        unit_names = self._units()
        self._parameters()
        gravity = np.array([0.0, -9.81])
        if (g := top.get("gravity")) is not None:
            gravity = g.vector(None, bound="acceleration")
            if gravity is None:
                gravity = np.array([0.0, -9.81])
        self._sizing_start()
        links = self._links(gravity)
        points = {link.name: dict(link.points) for link in links}
        joints = self._joints(links, points)
        drivers = self._drivers(links, joints, points)
        loads_ = self._loads(links, joints, points, drivers)
        elements = self._elements(links, joints, points)
        sketch = self._sketch(links, joints)
        analysis = self._analysis(joints, drivers, links)
        loops = self._loops(joints)
        flywheel = self._flywheel()
        drive = self._drive(joints, drivers, flywheel)
        clearances = self._clearances(joints)
        output = self._output(links, joints, drivers)
        self.problems.raise_if_any()
        return Model(
            name=name or "mechanism",
            links=tuple(links),
            joints=tuple(joints),
            drivers=tuple(drivers),
            loads=tuple(loads_),
            gravity=gravity,
            sketch=sketch,
            analysis=analysis,
            loops=loops,
            parameters=dict(self.ctx.env),
            units=unit_names,
            source=self.ctx.file,
            flywheel=flywheel,
            sketch_where=self.sketch_where,
            clearances=tuple(clearances),
            output=output,
            elements=tuple(elements),
            drive=drive,
            parameter_texts=dict(self.parameter_texts),
            sizing=self._sizing_spec(),
            notes=tuple(dict.fromkeys(f"{where}: {message}" for where, message in self.ctx.notes)),
        )

    def _output(self, links, joints, drivers) -> str | None:
        """``output: <link or joint>``: the machine's output member (its stroke or swing,
        limit positions and time ratio head summary.json).  Not the frame, not the input
        (a motion driver's joint or the link it moves on the frame), not a slide between
        two moving links (a relative motion); every refusal ends with what it takes."""
        e = self.top.get("output")
        if e is None:
            return None
        name = e.text()
        if name is None:
            return None
        by_link = {link.name: link for link in links}
        by_joint = {j.name: j for j in joints}
        ground = next((link.name for link in links if link.ground), None)
        driven = {d.joint: d.name for d in drivers if d.motion is not None}
        if name in by_link:
            if by_link[name].ground:
                e.error(f"'{name}' is the frame, not an output; {OUTPUT_KINDS}")
                return None
            held = [j for j in joints if name in j.links and ground in j.links and j.name in driven]
            if held:
                e.error(
                    f"link '{name}' is moved on the frame by joint '{held[0].name}' of motion "
                    f"driver '{driven[held[0].name]}': it is the input; {OUTPUT_KINDS}"
                )
                return None
            return name
        if name not in by_joint:
            if not self._broken("link", name) and not self._broken("joint", name):
                e.error(
                    self._unknown("link or joint", name, [*by_link, *by_joint])
                    + f"; {OUTPUT_KINDS}"
                )
            return None
        j = by_joint[name]
        if name in driven:
            driver = driven[name]
            e.error(f"'{name}' is the joint of motion driver '{driver}', the input; {OUTPUT_KINDS}")
            return None
        if not (j.reports_stroke or j.reports_swing):
            e.error(f"joint '{name}' ({j.kind}) has no stroke or swing to report; {OUTPUT_KINDS}")
            return None
        if j.reports_stroke and ground not in j.links:
            e.error(
                f"'{name}' slides between two moving links ({', '.join(j.links)}): a relative "
                f"motion, not the machine's output; {OUTPUT_KINDS}"
            )
            return None
        return name

    # -- names ----------------------------------------------------------------
    def _claim(self, section: Entry, name: str, what: str) -> bool:
        """Register ``name`` (a key of ``section``) as a ``what``; report a bad name.  Where
        it is written is looked up only for a message (:meth:`_first_named`)."""
        problem = name_problem(what, name)
        if problem is None and name not in RESERVED and name not in self.names:
            self.names[name] = (what, section, name)
            return True
        where = section.key_where(name)
        if problem:
            self.problems.add(where, problem)
        elif name in RESERVED:
            self.problems.add(
                where,
                f"'{name}' is a reserved name (a results column); "
                f"reserved: {', '.join(sorted(RESERVED))}",
            )
        else:
            other, first = self.names[name][0], self._first_named(name)
            if name in self.generated:
                pin, hub, link = self.generated[name]
                self.problems.add(
                    where,
                    f"duplicate name '{name}': the pin '{pin}' at line "
                    f"{first.line} names its revolute {hub}-{link} so; "
                    "rename one",
                )
            else:
                self.problems.add(
                    where,
                    f"duplicate name '{name}': the {other} at line "
                    f"{first.line} has it already; names must be unique "
                    "across links, joints, drivers and loads",
                )
        self.broken[what].add(name)
        return False

    def _first_named(self, name: str) -> Location:
        """Where the name ``name`` was first given: a key of a section, or a location."""
        _, at, key = self.names[name]
        return at if key is None else at.key_where(key)

    def _broken(self, what: str, name: str) -> bool:
        """Whether ``name`` was declared as a ``what`` but is in error (already reported)."""
        return what in self.lost or name in self.broken[what]

    def _what(self, name: str) -> str | None:
        """What a name names (link, joint, driver, load), if anything."""
        return self.names[name][0] if name in self.names else None

    @staticmethod
    def _unknown(what: str, name: str, known: Iterable[str]) -> str:
        """``unknown link 'x' (did you mean 'y'?)``, or the list of choices when none is close."""
        known = list(known)
        hint = did_you_mean(name, known)
        if not hint:
            hint = f"; the {what}s are: {', '.join(known)}" if known else f"; there are no {what}s"
        return f"unknown {what} '{name}'{hint}"

    def _not_a(self, what: str, name: str, known: Iterable[str], links=()) -> str:
        """Why ``name`` is not a ``what``: it names something else, or nothing."""
        other = self._what(name)
        known = list(known)
        listing = f"; the {what}s are: {', '.join(known)}" if known else ""
        if what == "joint" and name in self.pins:
            return (
                f"'{name}' is a pin shared by {len(self.pins[name]) + 1} links, not one joint: "
                f"name one of its revolutes ({', '.join(self.pins[name])})"
            )
        if other is not None and other != what:
            return f"'{name}' is a {other}, not a {what}{listing}"
        owners = [link.name for link in links if name in link.points]
        if what == "link" and owners:
            return f"'{name}' is a point of link '{owners[0]}', not a link{listing}"
        return self._unknown(what, name, known)
