"""The joint contract and the registry of joint types.

A joint is a kinematic pair between links ``i`` and ``j``.  It contributes
``n_eq`` rows to the constraint vector Φ(q, t) and the same number of
reaction unknowns λ.  All array arguments carry arbitrary leading batch axes
(variants × positions) and end in ``3`` = (x, y, θ) of the link's centre of
mass; ground enters as zeros.  Nothing here stores state.

Sign conventions (``docs/theory.md``): the equations of motion read
``M q̈ − Q = Φ_qᵀ λ``, so ``Φ_qᵀ λ`` is the generalized constraint force;
a joint's ``reaction`` turns its block of λ into the force of link i on
link j.  The *relative coordinate* of a joint (``coordinate``) is what a
driver prescribes and what friction opposes: θ_j − θ_i for a revolute, the
sliding distance for a prismatic pair.
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, ClassVar

import numpy as np

from ..errors import Location, did_you_mean

if TYPE_CHECKING:
    from ..yaml_io import Entry

__all__ = ["Joint", "JOINT_TYPES", "joint_type"]

JOINT_TYPES: dict[str, type[Joint]] = {}


def joint_type(kind: str) -> type[Joint]:
    """The registered class for YAML ``type: kind``; ``KeyError`` lists the choices."""
    try:
        return JOINT_TYPES[kind]
    except KeyError:
        raise KeyError(
            f"unknown joint type '{kind}'{did_you_mean(kind, JOINT_TYPES)}; "
            f"known: {', '.join(sorted(JOINT_TYPES))}"
        ) from None


@dataclass(frozen=True)
class Joint(ABC):
    """Kinematic pair between links ``links = (i, j)``; one subclass per type.

    Subclasses declare ``kind`` (their YAML ``type``), ``n_eq`` and
    ``reaction_labels``, parse their own keys in ``from_spec`` and implement
    the abstract methods.  Reactions are reported as the force of i on j.
    """

    kind: ClassVar[str]
    n_eq: ClassVar[int]
    reaction_labels: ClassVar[tuple[str, ...]]
    angular: ClassVar[bool]  # relative coordinate is an angle (rad) or a length (m)
    reports_stroke: ClassVar[bool] = False

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

    def effort_force(
        self, effort: np.ndarray, qi: np.ndarray, qj: np.ndarray
    ) -> dict[str, np.ndarray]:
        """What an effort along the coordinate (i on j) adds to the reaction labels.

        A couple adds no force (revolute: {}); a force along a sliding axis adds
        its components.  Used for the reactions of the friction solutions.
        """
        return {}

    # -- friction -----------------------------------------------------------
    @property
    def has_friction(self) -> bool:
        return False

    def friction_magnitude(self, lam: np.ndarray, qi: np.ndarray, qj: np.ndarray) -> np.ndarray:
        """|friction effort| from the reaction λ: ρ|F| or f|N|; zeros without friction."""
        return np.zeros(lam.shape[:-1])

    def friction_gradient(self, lam: np.ndarray, qi: np.ndarray, qj: np.ndarray) -> np.ndarray:
        """∂ friction_magnitude / ∂λ, ``(..., n_eq)`` (for Newton on the consistent solution)."""
        return np.zeros(lam.shape)
