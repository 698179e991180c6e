"""The kernels' parameters a kinematic plan reads (kinematics/plan.py): one model's, or a
stacked model's variants' — the numbers alike in every variant written into the plan's
text, the others read from a table, one value per variant — and what else its text
depends on (the system's topology), so that one compiled text serves every population
of a search."""

from __future__ import annotations

import numpy as np

from ..structure.system import System

__all__ = [
    "whole_array",
    "driver_params",
    "jacobian_kernel",
    "gamma_kernel",
    "variant_params",
    "parameter_pattern",
    "topology",
    "unflat",
    "flat",
]


def whole_array(
    s, kernels=("jacobian_kernel", "gamma_kernel"), variants: int | None = None
) -> np.ndarray | None:
    """The kernels' parameters of set ``s`` where its joint type's ``kernels`` also hold
    over whole arrays (``Compiled.whole_array_kernels``: plain arithmetic, no branch on a
    value), ``(k, m)``, or of stacked ``variants`` ``(V, k, m)``; else None: the set is
    evaluated through the contract's NumPy methods."""
    cls = type(s.constraint)
    if s.driver is not None or not cls.whole_array_kernels:
        return None
    if any(getattr(cls, k) is None for k in kernels):
        return None
    if variants is None:
        return s.constraint.kernel_params(len(s.members))
    return variant_params(s.constraint, len(s.members), variants)


def driver_params(s) -> np.ndarray | None:
    """A motion driver's set (one driver): its joint's kernel parameters where the joint
    type's ``direction_kernel`` and ``bias_kernel`` hold over whole arrays, so that one
    model's plan traces the driver's row (:func:`jacobian_kernel`, :func:`gamma_kernel`);
    else None (the contract's methods)."""
    if s.driver is None or len(s.members) != 1:
        return None
    joint = s.constraint.joint
    cls = type(joint)
    if not cls.whole_array_kernels or cls.direction_kernel is None or cls.bias_kernel is None:
        return None
    return joint.kernel_params(1)


def jacobian_kernel(s):
    """Set ``s``'s Φ_q kernel ``(par, P, ends, ji, jj)`` as a plan traces it: its joint
    type's, or a motion driver's row, the gradient of its joint's coordinate (the joint
    type's ``direction_kernel``, as ``DriverConstraint.jacobian`` gives it)."""
    if s.driver is None:
        return type(s.constraint).jacobian_kernel
    direction = type(s.constraint.joint).direction_kernel

    def kernel(par, P, ends, ji, jj):
        direction(par, P, ends, ji[:, 0], jj[:, 0])

    return kernel


def gamma_kernel(s, psi_dd):
    """Set ``s``'s γ kernel ``(par, P, V, ends, out)`` as a plan traces it: its joint
    type's, or a motion driver's row, ψ̈ (``psi_dd``, its traced value) less its joint's
    coordinate bias (the joint type's ``bias_kernel``: ``DriverConstraint.acceleration_rhs``)."""
    if s.driver is None:
        return type(s.constraint).gamma_kernel
    bias = type(s.constraint.joint).bias_kernel

    def kernel(par, P, V, ends, out):
        b = np.empty(out.shape[:1] + out.shape[2:], dtype=object)
        bias(par, P, V, ends, b)
        for m, p in np.ndindex(b.shape):
            out[m, 0, p] = psi_dd - b[m, p]

    return kernel


def variant_params(joint, k: int, v: int) -> np.ndarray | None:
    """``kernel_params`` of a joint (or a stack of ``k``) of ``v`` stacked variants, ``(v,
    k, m)``: a field alike in every variant is the joint's ``(k, size)``, one that differs
    carries the variant axis first (model/stacking.py); None for any other shape."""
    fields = [(f, 2) for f in joint.stacked_vectors] + [(f, 1) for f in joint.stacked_scalars]
    parts = []
    for f, size in fields:
        a = np.asarray(getattr(joint, f), dtype=float)
        if a.size == k * size:
            parts.append(np.broadcast_to(a.reshape(1, k, size), (v, k, size)))
        elif a.ndim > 1 and a.shape[0] == v and a.size == v * k * size:
            parts.append(a.reshape(v, k, size))
        else:
            return None
    return np.concatenate(parts, axis=2) if parts else None


def parameter_pattern(system: System, variants: int) -> tuple[tuple, list[np.ndarray]]:
    """The kernels' parameters of a stacked system's sets as its plan reads them (the
    plan's source depends on them and on the system's topology alone): per set, None
    (the contract's methods) or, per entry, its number where every variant has the
    same, else the text ``PA[j]`` of row j of the table (one value per variant, each
    distinct row once); and the table's rows."""
    rows: dict[bytes, int] = {}
    columns: list[np.ndarray] = []
    out = []
    for s in system.sets:
        par = whole_array(s, variants=variants)
        if par is None:
            out.append(None)
            continue
        entries = []
        for at in np.ndindex(par.shape[1:]):
            col = np.ascontiguousarray(par[(slice(None),) + at])
            if np.all(col == col[0]):
                entries.append(float(col[0]))
                continue
            j = rows.setdefault(col.tobytes(), len(columns))
            if j == len(columns):
                columns.append(col)
            entries.append(f"PA[{j}]")
        out.append((par.shape[1:], tuple(entries)))
    return tuple(out), columns


def unflat(x: np.ndarray, shape: tuple) -> np.ndarray:
    """Rows ``(V·N, ...)`` of a stacked plan as ``(V, N, ...)``, as the contract's methods
    take a stacked model's poses (its parameters carry the variant axis)."""
    return x.reshape(shape + x.shape[1:])


def flat(x: np.ndarray, shape: tuple) -> np.ndarray:
    """A contract method's ``(V, N, ...)`` values as the plan's rows ``(V·N, ...)``."""
    tail = x.shape[len(shape) :]
    return np.broadcast_to(x, shape + tail).reshape((-1,) + tail)


def topology(system: System) -> tuple:
    """What a plan's source depends on besides its parameters: the sets' types, members,
    links and rows, the groups' rows and columns."""
    sets = tuple(
        (type(s.constraint), s.members, s.driver, s.ends.tobytes(), s.rows.tobytes())
        for s in system.sets
    )
    return sets + tuple((p.rows.tobytes(), p.cols.tobytes()) for p in system.plans)
