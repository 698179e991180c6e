"""The joint contract and the registry of joint types.

A joint is a kinematic pair between links ``i`` and ``j``.  It contributes
``n_eq`` rows to the constraint vector Φ(q, t) and the same number of
reaction unknowns λ.  All array arguments carry arbitrary leading batch axes
(variants × positions) and end in ``3`` = (x, y, θ) of the link's centre of
mass; ground enters as zeros.  A pose may carry its frame after them, ``(..., 5)``
= (x, y, θ, cos θ, sin θ), computed once per state by the system: a type reads
``q[..., :2]`` and ``q[..., 2]``, rotates local vectors with
:func:`~kinetostatics.base.geometry.turn` / ``turn_back``, and never relies on
``q.shape[-1]``.  Nothing here stores state.

Sign conventions (``docs/theory.md``): the equations of motion read
``M q̈ − Q = Φ_qᵀ λ``, so ``Φ_qᵀ λ`` is the generalized constraint force;
a joint's ``reaction`` turns its block of λ into the force of link i on
link j.  The *relative coordinate* of a joint (``coordinate``) is what a
driver prescribes and what friction opposes: θ_j − θ_i for a revolute, the
sliding distance for a prismatic pair.

The contract is a small core every pair implements (:class:`JointCore`: its rows of Φ,
their derivatives, its reaction, its relative coordinate, its YAML keys) and optional
parts, each with defaults (:class:`Presentation` for the outputs, the sketch and the dump;
:class:`Friction`; :class:`Compiled`, evaluation in sets and compiled kernels;
:class:`Shaped`, a geometry built once).  :class:`Joint` is the core with every part's
defaults, so that no module outside ``joints/`` needs to ask a joint for its class or probe
its attributes, and a type that only computes works, with no picture and no report text of
its own.  A type names the parts it gives among its bases (docs/extending.md).
"""

from __future__ import annotations

import importlib
from abc import ABC, abstractmethod
from collections.abc import Callable, Iterator, MutableMapping, Sequence
from dataclasses import dataclass, field, replace
from typing import TYPE_CHECKING, Any, ClassVar

import numpy as np

from ..base.kernels import Kernels, compiled
from ..base.keys import NAME, VECTOR, Keys, names
from ..errors import Location, did_you_mean

if TYPE_CHECKING:
    from ..base.spec import Entry
    from .gearing import GearData  # the toothed pairs' record (loaded with them)
    from .relative import RelativeMotion

__all__ = [
    "Joint",
    "JointCore",
    "Presentation",
    "Friction",
    "Compiled",
    "Shaped",
    "OPTIONAL_PARTS",
    "JOINT_TYPES",
    "joint_type",
    "Anchor",
    "Glyph",
    "Block",
    "Line",
    "Circle",
    "Curve",
    "Pole",
    "stack_vectors",
    "stack_scalars",
]

# The built-in types and their modules in this package: a module is imported when its type
# is first named (a file without gears does not pay for importing them).
BUILT_IN = {t: t for t in ("cam", "gear", "prismatic", "rack", "revolute")}


class _Registry(MutableMapping):
    """YAML ``type:`` -> joint class: the types registered (a subclass of :class:`Joint`
    with ``kind=`` registers itself when its module is imported) and the built-in ones,
    imported when first looked up; iterating imports them all."""

    def __init__(self) -> None:
        self._types: dict[str, type[Joint]] = {}

    def _load(self, kinds) -> None:
        for kind in kinds:
            if kind not in self._types and kind in BUILT_IN:
                importlib.import_module(f"{__package__}.{BUILT_IN[kind]}")

    def __getitem__(self, kind: str) -> type[Joint]:
        self._load((kind,))
        return self._types[kind]

    def __setitem__(self, kind: str, cls: type[Joint]) -> None:
        self._types[kind] = cls

    def __delitem__(self, kind: str) -> None:
        del self._types[kind]

    def __contains__(self, kind: object) -> bool:
        return kind in BUILT_IN or kind in self._types

    def __iter__(self) -> Iterator[str]:
        self._load(BUILT_IN)
        return iter([*(k for k in BUILT_IN if k in self._types), *self._extra()])

    def _extra(self) -> list[str]:
        return [k for k in self._types if k not in BUILT_IN]

    def __len__(self) -> int:
        self._load(BUILT_IN)
        return len(self._types)


JOINT_TYPES: MutableMapping[str, type[Joint]] = _Registry()


def joint_type(kind: str) -> type[Joint]:
    """The registered class for YAML ``type: kind``; ``KeyError`` lists the choices."""
    try:
        return JOINT_TYPES[kind]
    except KeyError:
        known = list(JOINT_TYPES)
        raise KeyError(
            f"unknown joint type '{kind}'{did_you_mean(kind, known)}; "
            f"known: {', '.join(sorted(known))}"
        ) from None


def stack_vectors(vectors: Sequence[np.ndarray]) -> np.ndarray:
    """Vectors ``(..., 2)`` of k joints as one array ``(..., k, 2)`` (see ``Joint.stack``)."""
    return np.stack(np.broadcast_arrays(*vectors), axis=-2)


def stack_scalars(values: Sequence) -> np.ndarray:
    """Scalars (or stacked-variant arrays ``(...)``) of k joints as ``(..., k)``."""
    return np.stack(np.broadcast_arrays(*(np.asarray(v, dtype=float) for v in values)), axis=-1)


@dataclass(frozen=True)
class Anchor:
    """A named point of a link that a pair ties: ``point`` of ``link`` at ``xy`` (the
    link's own frame, m, relative to its centre of mass, as ``Link.points``).

    ``at_joint``: the point lies at the joint itself (both pins of a revolute, the
    sliding point of a prismatic pair), so a ``sketch:`` entry named after the
    joint places it; an axis point or a gear centre is not at the joint.
    """

    link: str
    point: str
    xy: np.ndarray
    at_joint: bool = False


@dataclass(frozen=True)
class Line:
    """A straight line fixed in ``link``: through ``point`` along the unit ``direction``
    (global, m, each ``(..., 2)``)."""

    link: str
    point: np.ndarray
    direction: np.ndarray


@dataclass(frozen=True)
class Circle:
    """A circle fixed in ``link``: ``centre`` (global, m, ``(..., 2)``) and ``radius`` (m)."""

    link: str
    centre: np.ndarray
    radius: float


@dataclass(frozen=True)
class Curve:
    """A polyline fixed in ``link`` (a cam's profile or pitch curve): ``points``
    (global, m, ``(..., n, 2)``), closed when ``closed``."""

    link: str
    points: np.ndarray
    closed: bool = True


@dataclass(frozen=True)
class Block:
    """A slider block of ``link`` centred on ``centre`` and sliding along the unit
    ``direction`` (global, ``(..., 2)``); ``length`` its contact length (m), or
    ``None`` where none is given (a picture chooses one)."""

    link: str
    centre: np.ndarray
    direction: np.ndarray
    length: float | None = None


@dataclass(frozen=True)
class Glyph:
    """What a picture draws of a pair at given poses, in global m, batched like the
    poses.  The default (all empty) draws nothing.

    ``point (..., 2)``: where ``reaction()`` acts (a pin's centre, a slider's sliding
    point, a pitch point), where its force arrow starts and its label sits;
    ``None`` for a type that does not say.  ``block``: a slider block on link j;
    ``guide``: the axis on link i the block slides along (rails on the frame, the
    link's outline extended on a moving link); ``circles`` and ``lines``: pitch
    circles and pitch lines of toothed pairs, a roller; ``curves``: a cam's profile and
    pitch curve.  Whether the point is drawn as a pin
    is the class's ``pin``.
    """

    point: np.ndarray | None = None
    block: Block | None = None
    guide: Line | None = None
    circles: tuple[Circle, ...] = ()
    lines: tuple[Line, ...] = ()
    curves: tuple[Curve, ...] = ()


@dataclass(frozen=True)
class Pole:
    """An instant centre of a pair's two links, given by the pair itself: the point ``xy``
    (global, m, ``(..., 2)``), or, ``at_infinity``, the unit direction ``xy`` it lies at
    infinity along (the relative motion is then a translation perpendicular to it); with
    ``along``, only the line through ``xy`` along that unit direction on which the centre
    lies (a cam's common normal at the contact)."""

    xy: np.ndarray
    at_infinity: bool = False
    along: np.ndarray | None = None


# ``axis:`` of a slide (prismatic, rack): a point and a direction, or two points on link i
AXIS_KEYS = Keys(
    {"point": NAME, "direction": VECTOR, "points": names(2)},
    # without ``points``, a point and a direction
    extra={"if": {"not": {"required": ["points"]}}, "then": {"required": ["point", "direction"]}},
)


def _per_joint(joint, fields, k: int) -> np.ndarray | None:
    """The fields ``(name, size)`` as one row per joint of ``k``, or None (not one per joint)."""
    parts = []
    for f, size in fields:
        v = np.asarray(getattr(joint, f), dtype=float)
        if v.size != k * size:
            return None
        parts.append(v.reshape(k, size))
    return np.ascontiguousarray(np.concatenate(parts, axis=1)) if parts else None


@dataclass(frozen=True)
class JointCore(ABC):
    """What every pair is: its rows of Φ, their derivatives, its reaction and its relative
    coordinate.  The kinematics, the reactions, the drivers and friction's effort call
    these; a type implements the abstract ones (``coordinate_bias``, ``relative_speed`` and
    ``effort_force`` have defaults for a coordinate linear in q and a couple).

    Subclasses declare ``kind`` (their YAML ``type``), ``n_eq`` and
    ``reaction_labels``, parse their own keys in ``from_spec`` and implement
    the abstract methods.  Reactions are reported as the force of i on j.
    """

    kind: ClassVar[str]
    n_eq: ClassVar[int]
    reaction_labels: ClassVar[tuple[str, ...]]
    angular: ClassVar[bool]  # relative coordinate is an angle (rad) or a length (m)
    fixed_direction: ClassVar[tuple | None] = None  # (g_i, g_j) where the same at every pose
    # the keys of ``joints.<name>`` that from_spec checks, with their shapes (base/keys.py):
    # the JSON Schema of a mechanism file is made from them; None: any keys
    spec_keys: ClassVar[Keys | None] = None

    name: str
    links: tuple[str, str]
    where: Location = field(default=Location(), compare=False, repr=False)

    def __init_subclass__(cls, kind: str | None = None, **kwargs: Any) -> None:
        super().__init_subclass__(**kwargs)
        if kind is not None:
            cls.kind = kind
            JOINT_TYPES[kind] = cls

    # -- YAML ---------------------------------------------------------------
    @classmethod
    @abstractmethod
    def from_spec(
        cls,
        name: str,
        entry: Entry,
        links: tuple[str, str],
        points: dict[str, dict[str, np.ndarray]],
    ) -> Joint | None:
        """Parse this type's keys of ``joints.<name>``.

        ``points[link][point]`` are the links' local points relative to their
        centre of mass.  Problems go to ``entry``'s collector; return ``None``
        when the joint cannot be built.
        """

    @abstractmethod
    def to_spec(self) -> dict[str, Any]:
        """The type's keys (SI) for writing the model back to YAML."""

    # -- kinematics ---------------------------------------------------------
    @abstractmethod
    def residual(self, qi: np.ndarray, qj: np.ndarray) -> np.ndarray:
        """Φ, shape ``(..., n_eq)``; angular rows wrapped to [−π, π)."""

    @abstractmethod
    def jacobian(self, qi: np.ndarray, qj: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(∂Φ/∂q_i, ∂Φ/∂q_j), each ``(..., n_eq, 3)``."""

    @abstractmethod
    def acceleration_rhs(
        self, qi: np.ndarray, qj: np.ndarray, vi: np.ndarray, vj: np.ndarray
    ) -> np.ndarray:
        """γ = −(Φ_q q̇)_q q̇, shape ``(..., n_eq)``, so that Φ_q q̈ = γ."""

    @abstractmethod
    def reaction(self, lam: np.ndarray, qi: np.ndarray, qj: np.ndarray) -> dict[str, np.ndarray]:
        """λ block ``(..., n_eq)`` -> labelled components of the force of i on j."""

    # -- the relative coordinate (drivers, friction, efforts) ----------------
    @abstractmethod
    def coordinate(self, qi: np.ndarray, qj: np.ndarray) -> np.ndarray:
        """Relative coordinate ``(...)``: θ_j − θ_i (rad) or a sliding distance (m)."""

    @abstractmethod
    def motion_direction(self, qi: np.ndarray, qj: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Gradient of ``coordinate`` with respect to (q_i, q_j), each ``(..., 3)``.

        An effort ``e`` along the coordinate (applied by i on j) is the
        generalized force ``(g_i e, g_j e)``.
        """

    def coordinate_bias(
        self, qi: np.ndarray, qj: np.ndarray, vi: np.ndarray, vj: np.ndarray
    ) -> np.ndarray:
        """Velocity-product part of the coordinate's second derivative, ``(...)``.

        d²c/dt² = g·q̈ + coordinate_bias.  Zero for coordinates linear in q.
        """
        return np.zeros(np.broadcast_shapes(qi.shape, qj.shape)[:-1])

    def relative_speed(self, qi, qj, vi, vj) -> np.ndarray:
        """Rate of the relative coordinate: ω_j − ω_i, or the sliding speed."""
        gi, gj = self.motion_direction(qi, qj)
        return np.einsum("...k,...k->...", gi, vi) + np.einsum("...k,...k->...", gj, vj)

    def instant_centre(self, qi: np.ndarray, qj: np.ndarray) -> Pole | None:
        """The instant centre (velocity pole) of links i and j that the pair fixes by itself
        at poses ``qi``, ``qj`` ``(..., 3)``: a pin's centre, a slide's centre at infinity
        normal to it, a toothed pair's pitch point, or only a line it lies on (a cam's
        common normal at the contact).  None by default: the pair fixes nothing of it.
        Read by the instant centres' method (``methods/centres.py``)."""
        return None

    def relative_motion(self, qi, qj, vi, vj, ai, aj, labels) -> RelativeMotion | None:
        """j's motion relative to i at the pair's point at one pose (``joints/relative.py``),
        texts naming the links ``labels`` (i, j); None: not written for this pair type."""
        return None

    def effort_force(
        self, effort: np.ndarray, qi: np.ndarray, qj: np.ndarray
    ) -> dict[str, np.ndarray]:
        """What an effort along the coordinate (i on j) adds to the reaction labels.

        A couple adds no force (revolute: {}); a force along a sliding axis adds
        its components.  Used for the reactions of the friction solutions.
        """
        return {}


class Presentation:
    """Optional: what the outputs, the sketch and the dump ask of a pair, so that they never
    ask for its class.  The defaults draw nothing and write no text: a pair that only
    computes has no picture and no report text of its own (pair letter ``?``)."""

    letter: ClassVar[str] = "?"  # pair letter in Assur-group labels such as RRP (one character)
    reports_stroke: ClassVar[bool] = False  # undriven: its stroke and time ratio are an output
    reports_swing: ClassVar[bool] = False  # undriven, on the frame: swing angle and time ratio
    pin: ClassVar[bool] = False  # drawn as a pin at glyph().point; a bearing (polar diagrams)

    def anchors(self) -> tuple[Anchor, ...]:
        """The named points of the links this pair ties, in a fixed order (link i's first).

        Used by the sketch's initial guess (the ``at_joint`` ones), the default traced
        paths, a driver's default reference point, the pictures and the report.
        """
        return ()

    def coincident(self) -> tuple[tuple[Anchor, Anchor], ...]:
        """Pairs of points, one on each link, that this pair holds at the same place at
        every position (a revolute's two pins); () where none.  The loader refuses a
        spring or damper between two such points (its direction is undefined)."""
        return ()

    def glyph(self, qi: np.ndarray, qj: np.ndarray) -> Glyph:
        """Drawing primitives at poses ``qi``, ``qj`` ``(..., 3)`` (global, m, batched)."""
        return Glyph()

    def label(self) -> str:
        """The name a picture writes next to ``glyph().point``."""
        return self.name

    def describe(self, tr=None) -> dict[str, str]:
        """Text of the report's joint table: ``{"where": …, "friction": …}``.  ``tr(template,
        **values)``, when given, translates each English template before its values are
        filled in (the report's language); without it the text is English."""
        return {"where": "", "friction": ""}

    def columns(
        self, qi: np.ndarray, qj: np.ndarray, lam: np.ndarray | None = None
    ) -> dict[str, tuple[str, np.ndarray]]:
        """The type's own result columns ``<joint>.<label>``: ``{label: (unit, values)}``
        at poses ``qi``, ``qj`` ``(..., 3)``; with ``lam`` (its λ block, frictionless) also
        those that need the reaction.  None by default (a cam's pressure angle, its status)."""
        return {}

    def warnings(self, lam: np.ndarray, qi: np.ndarray, qj: np.ndarray) -> tuple[str, ...]:
        """Messages about a result at the poses (rows) ``qi``, ``qj`` with the frictionless
        λ block ``lam``, warned by the analysis (a cam follower that would separate)."""
        return ()

    def gear_data(self) -> GearData | None:
        """The tooth data of a toothed pair (teeth, pitch radii, pressure angle, addendum,
        clearance and shift coefficients) for the gear chapter; None for any other pair."""
        return None


class Friction:
    """Optional: a friction law μ(λ) ≥ 0 of the pair, the effort −sign(ċ)·μ along its relative
    coordinate (``kinetics/friction.py``), its kinks for the cycle's quadrature, its constants
    for the batch, its stack and compiled kernel for the friction solutions; default: none."""

    @property
    def has_friction(self) -> bool:
        return False

    friction_reads_poses: ClassVar[bool] = True  # False: a law in λ alone, handed no poses

    def friction_magnitude(self, lam: np.ndarray, qi: np.ndarray, qj: np.ndarray) -> np.ndarray:
        """|friction effort| from the reaction λ: ρ|F| or f|N|; zeros without friction.
        The poses ``qi``, ``qj`` are None where the type's ``friction_reads_poses`` is False."""
        return np.zeros(lam.shape[:-1])

    def friction_gradient(self, lam: np.ndarray, qi: np.ndarray, qj: np.ndarray) -> np.ndarray:
        """∂ friction_magnitude / ∂λ, ``(..., n_eq)`` (for Newton on the consistent solution)."""
        return np.zeros(lam.shape)

    def friction_kinks(self, lam: np.ndarray, qi: np.ndarray, qj: np.ndarray) -> np.ndarray:
        """The arguments of the absolute values in ``friction_magnitude``, ``(..., m)``: where
        one changes sign the law has a kink, where the cycle's quadrature is cut (a normal
        force through zero).  None by default (``m = 0``), nor for a smooth law (ρ|F|)."""
        return np.zeros(lam.shape[:-1] + (0,))

    def friction_constants(self) -> tuple[Any, ...]:
        """The constants ``friction_magnitude`` reads (ρ, f, 1 − η …), for a caller that
        must know whether they differ between stacked variants; () without friction."""
        return ()

    friction_scalars: ClassVar[tuple[str, ...]] = ()  # what friction_magnitude reads, stacked

    @classmethod
    def stack_friction(cls, joints: Sequence[Joint]) -> Joint | None:
        """One joint of this type standing for ``joints`` in ``friction_magnitude``, or
        None: each is evaluated on its own (a type that declares no ``friction_scalars``).

        Its ``friction_scalars`` are the joints' own on a new last axis (:func:`stack_scalars`,
        ``(..., k)``); they must be every field ``friction_magnitude`` reads, so that for
        reactions ``(..., k, n_eq)`` and poses ``(..., k, 5)`` it gives the k joints'
        magnitudes ``(..., k)``, each equal to the joint's own to the bit.  The friction
        solutions evaluate all a type's efforts in one call so (``kinetics/friction.py``)."""
        if not cls.friction_scalars:
            return None
        fields = {f: stack_scalars([getattr(j, f) for j in joints]) for f in cls.friction_scalars}
        return replace(joints[0], name="+".join(j.name for j in joints), **fields)

    friction_kernel: ClassVar[Callable | None] = None  # (par, x, rows, out): friction_magnitude

    def friction_kernel_params(self, k: int) -> np.ndarray | None:
        """What ``friction_kernel`` reads of this joint or of a stack of ``k`` (a
        ``stack_friction``): its ``friction_scalars`` per joint, ``(k, m)``, or None."""
        return _per_joint(self, [(f, 1) for f in self.friction_scalars], k)


class Compiled:
    """Optional: the pair evaluated in sets and by the compiled backend.  ``stack`` puts a
    type's joints into one (``structure/evaluation.py``); the kernels fill Φ_q, γ, the
    coordinate's gradient and bias one position at a time (``base/kernels.py``).  The
    defaults: each joint evaluated on its own, by NumPy."""

    # the fields ``stack`` stacks: vectors (..., 2) and scalars; none: evaluated one by one
    stacked_vectors: ClassVar[tuple[str, ...]] = ()
    stacked_scalars: ClassVar[tuple[str, ...]] = ()

    @classmethod
    def stack(cls, joints: Sequence[Joint]) -> Joint | None:
        """One joint of this type standing for ``joints`` (all of this type), or None: each
        is evaluated on its own (a type that declares no ``stacked_vectors`` or
        ``stacked_scalars``).

        Its ``stacked_vectors`` are the joints' own, stacked on a new axis before their
        last (:func:`stack_vectors`: ``(..., k, 2)``), its ``stacked_scalars`` on a new
        last axis (:func:`stack_scalars`: ``(..., k)``); they must be every field that
        ``residual``, ``jacobian`` and ``acceleration_rhs`` read, so that at poses
        ``(..., k, 5)`` these give the k joints' values on that axis (``(..., k, n_eq)``,
        ``(..., k, n_eq, 3)``), each equal to the joint's own to the bit.  The system
        evaluates all a type's joints in one call so (``structure/evaluation.py``);
        nothing else is called on the stack."""
        if not (cls.stacked_vectors or cls.stacked_scalars):
            return None
        fields = {f: stack_vectors([getattr(j, f) for j in joints]) for f in cls.stacked_vectors}
        fields |= {f: stack_scalars([getattr(j, f) for j in joints]) for f in cls.stacked_scalars}
        return replace(joints[0], name="+".join(j.name for j in joints), **fields)

    # the compiled backend's kernels (base/kernels.py): the same operations in the same order
    # as residual, jacobian, acceleration_rhs, motion_direction, coordinate_bias; None: by NumPy
    residual_kernel: ClassVar[Callable | None] = None  # (par, P, ends, out), traced only
    jacobian_kernel: ClassVar[Callable | None] = None  # (par, P, ends, ji, jj)
    gamma_kernel: ClassVar[Callable | None] = None  # (par, P, V, ends, out)
    direction_kernel: ClassVar[Callable | None] = None  # (par, P, ends, gi, gj)
    bias_kernel: ClassVar[Callable | None] = None  # (par, P, V, ends, out)
    whole_array_kernels: ClassVar[bool] = False  # True: they run over whole arrays too (plan)

    def kernel_params(self, k: int) -> np.ndarray | None:
        """What the kernels read of this joint, or of a stack of ``k``: its
        ``stacked_vectors`` then its ``stacked_scalars`` per joint, ``(k, m)``; None where
        they are not one value per joint (stacked variants: evaluated by NumPy)."""
        return _per_joint(
            self,
            [(f, 2) for f in self.stacked_vectors] + [(f, 1) for f in self.stacked_scalars],
            k,
        )

    def kernels(self, k: int) -> Kernels | None:
        """This joint's (or stack of ``k``'s) compiled Φ_q and γ with its parameters bound,
        or None: evaluated by NumPy (a type without kernels, stacked variants)."""
        cls = type(self)
        par = self.kernel_params(k)
        if cls.jacobian_kernel is None or cls.gamma_kernel is None or par is None:
            return None
        jac, gam = compiled(cls.jacobian_kernel), compiled(cls.gamma_kernel)
        return Kernels(
            lambda P, ends, ji, jj: jac(par, P, ends, ji, jj),
            lambda P, V, ends, extra, out: gam(par, P, V, ends, out),
        )


class Shaped:
    """Optional: a pair whose geometry is built once from constants (a cam's profile
    synthesised from its law): the constants a stacked model cannot carry on a variant
    axis, the places where a derivative of its constraint jumps along the motion, and
    what makes a start pose contradict it, and its design chart.  Defaults: none of these."""

    def motion_breaks(self, qi: np.ndarray, qj: np.ndarray) -> np.ndarray:
        """Values whose sign changes mark where a derivative of the pair's constraint jumps
        along the motion (a cam law's segment ends), ``(..., m)``: the cycle's quadrature
        is cut there.  None by default (``m = 0``)."""
        return np.zeros(np.broadcast_shapes(qi.shape[:-1], qj.shape[:-1]) + (0,))

    def shape_constants(self) -> tuple[Any, ...]:
        """The constants the pair builds its geometry from once (a cam's profile,
        synthesised from its law and dimensions), which a stacked model cannot carry on a
        variant axis: the vectorised analysis leaves variants where they differ to the
        per-variant one.  () by default (constants that broadcast)."""
        return ()

    def start_problem(self, qi: np.ndarray, qj: np.ndarray) -> str:
        """Why the assembled start pose ``qi``, ``qj`` ``(3,)`` (the ground, the frame, at
        zero) contradicts the joint's own definition, as one line ('' if it does not): a
        cam whose follower touches it out of phase with its law.  The start pose's check
        raises it as a model error at the joint."""
        return ""

    def profile_design(self) -> Any | None:
        """The design chart of a pair whose profile is synthesised (a cam's: its law's
        curves, its pressure angle as a closed form of the cam angle and the base radius,
        its pitch curve's curvature; ``joints/_camdesign.py``), which the cam-design method
        (``methods/cam_design.py``) reads.  None by default (no profile to design)."""
        return None


@dataclass(frozen=True)
class Joint(JointCore, Presentation, Friction, Compiled, Shaped):
    """Kinematic pair between links ``links = (i, j)``; one subclass per type.

    The core (:class:`JointCore`) and every optional part with its defaults
    (:class:`Presentation`, :class:`Friction`, :class:`Compiled`, :class:`Shaped`), so that
    the rest of the code may call any member of any joint.  A type declares the optional
    parts it gives by naming them among its bases after ``Joint`` (``class Cam(Joint,
    Presentation, Friction, Shaped, kind="cam")``); ``tests/joints/test_joint_contract.py`` checks
    that a type overrides the members of exactly the parts it declares.
    """


OPTIONAL_PARTS = (Presentation, Friction, Compiled, Shaped)
