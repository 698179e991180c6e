"""The model: plain frozen data in SI describing what the user wrote.

Nothing here computes.  A :class:`Model` is built by :func:`kinetostatics.load`
from YAML or directly from Python; the analysis stages read it and never
write to it.  Local points of a link are stored relative to the link's
centre of mass, in the link's frame (the frame the user drew the points in).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import ClassVar

import numpy as np

from ..base.arrays import same_fields
from ..errors import Location
from ..joints import Joint
from .sizing import SizingSpec

__all__ = [
    "Link",
    "Law",
    "MotionLaw",
    "EffortLaw",
    "Driver",
    "Condition",
    "Load",
    "Element",
    "ELEMENT_KINDS",
    "Analysis",
    "DriveSpec",
    "FlywheelSpec",
    "Clearance",
    "Model",
]


@dataclass(frozen=True)
class Link:
    """A rigid link.  ``points``: local points relative to the CoM (m)."""

    __eq__ = same_fields  # arrays compared by value (base/arrays.py)

    name: str
    points: Mapping[str, np.ndarray]
    mass: float = 0.0  # kg
    inertia: float = 0.0  # kg·m² about the CoM
    com: np.ndarray = field(default_factory=lambda: np.zeros(2))  # CoM in the user's frame, m
    ground: bool = False
    where: Location = field(default=Location(), compare=False, repr=False)
    number: int | None = None  # the textbook's number (``number:``), for the report and pictures


class Law:
    """The one interface of every motion law of a driver (:class:`MotionLaw` here, the laws
    of :mod:`kinetostatics.model.motion`); the schedule, the loader and the outputs read
    only this, never a law's class.

    * ``kind`` — the law's name in a file (``law:``): ``constant``, ``harmonic``,
      ``polynomial``, ``table``;
    * ``own_run`` — whether the law fixes its run: ψ(0) (``start``), the time it covers
      (``duration``) and whether it repeats (``cyclic``).  False for a constant-speed law,
      whose run the analysis sets (``analysis.start``, ``sweep``, ``positions``);
    * ``value(start, t) -> (ψ, ψ̇, ψ̈)`` — ``start`` is ψ(0) for a law that does not fix it,
      ignored by one that does;
    * ``start`` — ψ(0), or None where the law leaves it to the analysis or the sketch;
    * ``speed`` — the *reference speed* (rad/s or m/s), signed: the speed of a
      constant-speed law; of another, the largest |ψ̇| over the run with the sign of the
      first motion (it scales the zero-speed thresholds and the continuation step);
    * ``acceleration`` — the constant ψ̈ of a law that has one (0 at constant speed), else
      None;
    * ``duration`` (s) — the time a run covers (None where the analysis sets it);
      ``cyclic`` — whether ψ(duration) = ψ(0) with the same derivatives (a run then does
      not repeat its end point);
    * ``breaks`` — the times in one run where a derivative of ψ jumps (a table's knots);
    * ``to_spec()`` — the YAML ``motion:`` mapping in SI.
    """

    kind: ClassVar[str]
    own_run: ClassVar[bool] = True
    start: float | None  # annotations only: a subclass gives each as a field or a property
    speed: float
    duration: float | None = None
    acceleration: float | None = None
    cyclic: bool = False
    breaks: tuple[float, ...] = ()  # smooth: no jump in any derivative

    def value(self, start, t):  # pragma: no cover - every law defines it
        raise NotImplementedError

    def to_spec(self) -> dict:  # pragma: no cover - every law defines it
        raise NotImplementedError


@dataclass(frozen=True)
class MotionLaw(Law):
    """A prescribed driver coordinate: ``speed`` (rad/s or m/s, signed) at t = 0 and a
    constant ``acceleration`` (rad/s² or m/s², default 0: constant speed);
    ``start``, when given, is ψ(0) (otherwise the analysis start or the sketch).

    The laws that fix their own run (harmonic, polynomial, table) are in
    :mod:`kinetostatics.model.motion`; all answer through :class:`Law`."""

    speed: float
    acceleration: float = 0.0
    start: float | None = None
    kind: ClassVar[str] = "constant"
    own_run: ClassVar[bool] = False

    def value(self, start: float, t: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(ψ, ψ̇, ψ̈) at times ``t`` for ψ(0) = ``start``."""
        t = np.asarray(t, dtype=float)
        a = self.acceleration
        return (start + self.speed * t + 0.5 * a * t * t, self.speed + a * t, np.full_like(t, a))

    def to_spec(self) -> dict:
        """``{speed: v}`` (a file gives a constant speed only)."""
        return {"speed": self.speed}


@dataclass(frozen=True)
class EffortLaw:
    """A known applied effort (torque N·m or force N, by link i on j) of an ``effort:`` driver.

    ``kind``: ``constant`` (``value``); ``table`` (``at`` driver coordinates,
    ``values`` efforts; linear, periodic over 2π for a revolute); ``motor``, the
    linear motor curve τ(ω) = ``value``·[1 + (``speed`` − ω)/(``slip``·``speed``)]
    (``value`` the torque at the rated speed ``speed``, both signed in the
    driver's sense); ``curve`` (τ over the driver speed: ``at`` speeds, ``values``
    efforts; linear, held constant outside the table).
    """

    kind: str
    value: float = 0.0
    at: tuple[float, ...] = ()
    values: tuple[float, ...] = ()
    speed: float = 0.0
    slip: float = 0.0

    def __call__(self, psi, psi_d, period: float | None = 2.0 * np.pi):
        """The effort at driver coordinates ``psi`` and speeds ``psi_d`` (arrays)."""
        psi, psi_d = np.asarray(psi, dtype=float), np.asarray(psi_d, dtype=float)
        shape = np.broadcast(psi, psi_d).shape
        if self.kind == "constant":
            return np.full(shape, self.value)
        if self.kind == "table":
            return np.broadcast_to(np.interp(psi, self.at, self.values, period=period), shape)
        if self.kind == "motor":
            return np.broadcast_to(
                self.value * (1.0 + (self.speed - psi_d) / (self.slip * self.speed)), shape
            )
        return np.broadcast_to(np.interp(psi_d, self.at, self.values), shape)

    def kinks(self) -> tuple[str, np.ndarray]:
        """(variable, levels): where the law has a kink, as values of ``"coordinate"`` (a
        table: its driver coordinates, each repeating every turn for a revolute) or of
        ``"speed"`` (a curve: its speeds); no levels for a constant or the motor line.
        The cycle's quadrature is cut where the variable passes a level."""
        if self.kind in ("table", "curve"):
            return ("coordinate" if self.kind == "table" else "speed"), np.asarray(self.at)
        return "coordinate", np.zeros(0)


@dataclass(frozen=True)
class Driver:
    """A driver acting on ``joint``; its effort is applied by the joint's link i on j.

    ``offset``: the constant that turns the joint's relative coordinate into the
    driver coordinate (for a revolute, angle of (P_j − C) − angle of (P_i − C)
    minus θ_j − θ_i; zero for a prismatic).  ``balance_at``: the joint that
    carries the unknown effort instead of this one.
    """

    name: str
    joint: str
    motion: Law | None = None  # MotionLaw (constant speed) or a law of model.motion
    effort: float | EffortLaw | None = None  # applied torque (N·m) or force (N): constant or law
    offset: float = 0.0
    points: tuple[str | None, str | None] = (None, None)
    balance_at: str | None = None
    where: Location = field(default=Location(), compare=False, repr=False)


@dataclass(frozen=True)
class Condition:
    """One ``active:`` condition of a load.

    ``kind``: ``moving`` (point velocity · ``axis`` > 0), ``travel`` (the point's
    travel along ``axis`` from its extreme, p·axis − min over the cycle, within
    ``bounds`` m) or ``angle`` (driver coordinate within ``bounds``, rad, in the
    sense of motion, modulo 2π).
    """

    __eq__ = same_fields  # arrays compared by value (base/arrays.py)

    kind: str
    link: str = ""
    point: str | None = None
    axis: np.ndarray | None = None
    bounds: tuple[float, float] | None = None
    where: Location = field(default=Location(), compare=False, repr=False)


@dataclass(frozen=True)
class Load:
    """An external load on ``link``.

    ``kind``: ``force`` (global vector ``value`` at ``point``, N), ``torque``
    (``value`` N·m), ``resistance`` (magnitude ``value`` N along ``axis``
    opposing the point's velocity component along it) or ``resisting_torque``
    (magnitude ``value`` N·m opposing the link's angular velocity, or with ``joint``
    the rotation of ``link`` relative to the joint's other link, on which the
    reaction −M acts); ``table`` replaces the constant by values over the driver
    coordinate.  Active only while all ``active`` conditions hold.
    """

    __eq__ = same_fields  # arrays compared by value (base/arrays.py)

    name: str
    kind: str
    link: str
    value: np.ndarray
    point: str | None = None
    axis: np.ndarray | None = None
    active: tuple[Condition, ...] = ()
    where: Location = field(default=Location(), compare=False, repr=False)
    table: tuple[np.ndarray, np.ndarray] | None = None  # (driver coordinates, values)
    joint: str | None = None  # resisting_torque: opposes the relative rotation at this joint

    def value_at(self, psi: np.ndarray, period: float | None) -> np.ndarray:
        """The load's value at driver coordinates ``psi`` (...): constant, or the
        table interpolated linearly (periodic over ``period`` for a revolute driver)."""
        if self.table is None:  # value (V, 1, own) when variants are stacked
            own = (2,) if self.kind == "force" else ()
            v = np.asarray(self.value)
            lead = v.shape[: v.ndim - len(own)]
            return np.broadcast_to(v, np.broadcast_shapes(np.shape(psi), lead) + own)
        at, vals = self.table
        cols = vals.reshape(len(at), -1).T
        out = np.stack([np.interp(psi, at, c, period=period) for c in cols], axis=-1)
        return out.reshape(np.shape(psi) + vals.shape[1:])

    def kinks(self) -> np.ndarray:
        """The driver coordinates where the value has a kink: the table's entries (each
        repeating every turn for a revolute driver; none for a constant).  The cycle's
        quadrature is cut where the driver passes one."""
        return np.zeros(0) if self.table is None else np.asarray(self.table[0], dtype=float)


ELEMENT_KINDS = ("spring", "damper", "torsion_spring", "rotary_damper")
"""The kinds of force element: translational between two points, rotational at a revolute."""


@dataclass(frozen=True)
class Element:
    """A force element between two links (``elements:``; the maths in
    :mod:`kinetostatics.kinetics.elements`).

    ``kind``: ``spring`` or ``damper`` between point ``points[0]`` of ``links[0]`` and
    ``points[1]`` of ``links[1]`` (its coordinate s the distance, m); ``torsion_spring`` or
    ``rotary_damper`` at revolute ``joint`` (links i, j of the joint; s = θ_j − θ_i, the
    rotation of link j's local x axis relative to link i's, rad, unwrapped).  Its force f
    (N; N·m) acts to reduce s when positive (a spring in tension): a spring's is
    ``preload`` + ``stiffness``·(s − ``free``), or the ``table`` (s values, f values)
    interpolated linearly and held constant outside; a damper's is ``damping``·ṡ.
    """

    __eq__ = same_fields  # arrays compared by value (base/arrays.py)

    name: str
    kind: str
    links: tuple[str, str]
    points: tuple[str | None, str | None] = (None, None)
    joint: str | None = None
    stiffness: float = 0.0  # N/m or N·m/rad
    free: float = 0.0  # free length (m) or free angle (rad)
    preload: float = 0.0  # N or N·m at s = free
    damping: float = 0.0  # N·s/m or N·m·s/rad
    table: tuple[np.ndarray, np.ndarray] | None = None  # (s values, forces)
    where: Location = field(default=Location(), compare=False, repr=False)

    @property
    def rotational(self) -> bool:
        return self.kind in ("torsion_spring", "rotary_damper")

    @property
    def spring(self) -> bool:
        return self.kind in ("spring", "torsion_spring")


@dataclass(frozen=True)
class Analysis:
    """Positions: start + k·sweep·sign(speed)/positions for k = 0…positions−1, plus ``at``."""

    start: float = 0.0
    sweep: float = 2.0 * np.pi
    positions: int = 360
    at: tuple[float, ...] = ()
    events: bool = False


@dataclass(frozen=True)
class FlywheelSpec:
    """``flywheel:`` — size a flywheel for the coefficient of speed fluctuation ``delta``;
    ``ratio`` = motor speed / crank speed for the inertia referred to the motor shaft;
    ``friction``: from the balancing moment with friction (default frictionless)."""

    delta: float
    ratio: float | None = None
    friction: bool = False
    where: Location = field(default=Location(), compare=False, repr=False)


@dataclass(frozen=True)
class DriveSpec:
    """``drive:`` — the motor of a revolute motion driver, through a reduction, checked
    against the cycle (:mod:`kinetostatics.dynamics.drive`, docs/drive.md).  SI throughout.

    ``driver``: the motion driver (None: the first); ``friction``: size from the torque with
    friction (None: when the file has friction); ``ratio`` i = motor speed / driven shaft
    speed (None: ``flywheel.ratio``, else 1); ``efficiency`` η of the reduction (both power
    directions); ``gear_inertia`` the reduction's inertia referred to the motor shaft;
    ``motor_inertia`` the rotor's; ``rated_torque``, ``peak_torque`` (N·m) and
    ``rated_speed`` (rad/s) the motor's ratings, None when not given (not checked)."""

    driver: str | None = None
    friction: bool | None = None
    ratio: float | None = None
    efficiency: float = 1.0
    gear_inertia: float = 0.0
    motor_inertia: float = 0.0
    rated_torque: float | None = None
    peak_torque: float | None = None
    rated_speed: float | None = None
    where: Location = field(default=Location(), compare=False, repr=False)


@dataclass(frozen=True)
class Clearance:
    """Radial clearance ``size`` (m) at revolute ``joint``; see
    :mod:`kinetostatics.dynamics.clearance`.

    ``speed`` (rad/s), ``acceleration`` (rad/s²): the prescribed rotation of the
    clearance link relative to link i (model ``prescribed``).  ``angle``: the
    link's global angle at t = 0 (rad; None: along −F_ij of the ideal joint).
    ``contact``: the contact law (model ``contact``), a
    :class:`~kinetostatics.dynamics.contact.ContactLaw` without its clearance.
    """

    joint: str
    size: float
    model: str = "prescribed"
    speed: float = 0.0
    acceleration: float = 0.0
    angle: float | None = None
    contact: object | None = None
    where: Location = field(default=Location(), compare=False, repr=False)


@dataclass(frozen=True)
class Model:
    """A planar linkage in SI units: what a mechanism file says, as frozen data.

    :func:`load` and :func:`loads` build it from YAML; its fields are those of the file
    (docs/yaml.md), after units and parameters are applied.

    Parameters
    ----------
    name : str
        The mechanism's name.
    links : tuple of Link
        The links, the ground among them.
    joints : tuple of Joint
        The kinematic pairs.
    drivers : tuple of Driver, optional
        The prescribed motions.
    loads : tuple of Load, optional
        External forces and torques.
    gravity : numpy.ndarray, optional
        The gravity vector (m/s², default ``[0, -9.81]``).
    sketch : mapping of str to numpy.ndarray, optional
        Point references (``joint`` or ``link.point``) to rough global positions that
        select the assembly branch.
    analysis : Analysis, optional
        The positions to analyse and the solver settings (``analysis:``).
    loops : tuple of tuple of str, optional
        The loops as listed in the file (checked against the structure), or None.
    parameters : mapping of str to float, optional
        The file's named parameters, in its units.
    units : mapping of str to str, optional
        The file's units.
    source : str, optional
        Where the model was read from.
    flywheel : FlywheelSpec, optional
        The flywheel to size (``flywheel:``).
    clearances : tuple, optional
        The clearance specifications, as read (``ideal`` None) or expanded.
    ideal : Model, optional
        The model before its clearances were expanded.
    output : str, optional
        The machine's output member, a link or a joint (``output:``).
    sketch_where : mapping of str to Location, optional
        Where each sketch entry was written (for the sketch check's messages).
    elements : tuple of Element, optional
        Springs and dampers.
    drive : DriveSpec, optional
        The motor and its reduction (``drive:``).
    parameter_texts : mapping of str to str, optional
        The text of each parameter as the file writes it (the report shows the
        expressions as formulas); none for a parameter given as an override.
    sizing : SizingSpec, optional
        The bearings, pins, sections and materials to size (docs/sizing.md).
    notes : tuple of str, optional
        What the file gives that is allowed but implausible (a friction coefficient
        above 1), each naming its key and line; ``check`` and ``run`` warn of them.
    _compiled : tuple, optional
        Internal: the compiled system, kept with the model (never pass it).

    See Also
    --------
    load : Read a model from a file.

    Examples
    --------
    >>> import kinetostatics as ks
    >>> model = ks.load("mechanisms/slider_crank.yaml")  # doctest: +SKIP
    >>> [link.name for link in model.moving_links]  # doctest: +SKIP
    ['crank', 'rod', 'slider']
    """

    __eq__ = same_fields  # arrays compared by value (base/arrays.py)

    name: str
    links: tuple[Link, ...]
    joints: tuple[Joint, ...]
    drivers: tuple[Driver, ...] = ()
    loads: tuple[Load, ...] = ()
    gravity: np.ndarray = field(default_factory=lambda: np.array([0.0, -9.81]))
    sketch: Mapping[str, np.ndarray] = field(default_factory=dict)
    analysis: Analysis = field(default_factory=Analysis)
    loops: tuple[tuple[str, ...], ...] | None = None
    parameters: Mapping[str, float] = field(default_factory=dict)
    units: Mapping[str, str] = field(default_factory=dict)
    source: str = "<model>"
    flywheel: FlywheelSpec | None = None
    clearances: tuple = ()  # Clearance specs: as read (ideal None) or expanded with
    ideal: Model | None = field(default=None, compare=False, repr=False)  # before expansion
    output: str | None = None  # the machine's output member (a link or a joint): ``output:``
    sketch_where: Mapping[str, Location] = field(default_factory=dict, compare=False, repr=False)
    elements: tuple[Element, ...] = ()  # springs and dampers (kinetics/elements.py)
    drive: DriveSpec | None = None  # the motor and its reduction (``drive:``)
    # the text of each parameter as written (``theta: 180*(K - 1)/(K + 1)``), for the report's
    # dimension synthesis; a parameter replaced by an override has none
    parameter_texts: Mapping[str, str] = field(default_factory=dict, compare=False, repr=False)
    sizing: SizingSpec | None = None  # bearings, pins, sections, materials (docs/sizing.md)
    # what the file gives that is allowed but implausible, each naming its key and line
    # (io/plausible.py warns of them)
    notes: tuple[str, ...] = field(default=(), compare=False, repr=False)
    # the system compiled from this model, cached by structure.system_of with the model's
    # pickle as its key (so a copy made with ``replace`` or ``Model(**vars(m))`` that carries
    # it along reuses it only if it describes the same mechanism); not pickled
    _compiled: tuple | None = field(default=None, compare=False, repr=False)

    def __getstate__(self):
        return {**self.__dict__, "_compiled": None}

    @property
    def ground(self) -> Link:
        return next(link for link in self.links if link.ground)

    @property
    def moving_links(self) -> tuple[Link, ...]:
        return tuple(link for link in self.links if not link.ground)

    def link(self, name: str) -> Link:
        """The link called ``name``.

        Parameters
        ----------
        name : str
            The link's name in the file.

        Returns
        -------
        Link
            The link.

        Raises
        ------
        StopIteration
            No link has that name.

        Examples
        --------
        >>> import kinetostatics as ks
        >>> ks.load("mechanisms/slider_crank.yaml").link("rod").mass  # doctest: +SKIP
        3.0
        """
        return next(link for link in self.links if link.name == name)

    def joint(self, name: str) -> Joint:
        """The joint called ``name``.

        Parameters
        ----------
        name : str
            The joint's name in the file.

        Returns
        -------
        Joint
            The joint.

        Raises
        ------
        StopIteration
            No joint has that name.

        Examples
        --------
        >>> import kinetostatics as ks
        >>> ks.load("mechanisms/slider_crank.yaml").joint("A").links  # doctest: +SKIP
        ('crank', 'rod')
        """
        return next(j for j in self.joints if j.name == name)

    @property
    def has_friction(self) -> bool:
        return any(j.has_friction for j in self.joints)
