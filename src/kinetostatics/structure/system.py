"""The compiled system: structure, index layout and constraint assembly.

:func:`build_system` turns a :class:`~kinetostatics.model.Model` into a frozen
:class:`System` once (graph, Assur plan, index arrays); the stage functions
then evaluate Φ, Φ_q and γ over any leading batch axes.  q holds (x, y, θ) of
each moving link's centre of mass; ground enters as zeros.
"""

from __future__ import annotations

import weakref
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import cast

import numpy as np

from ..base import kernels
from ..base.arrays import entries_first, entries_last
from ..base.geometry import poses
from ..joints import Joint
from ..model import Model
from .drivers import DriverConstraint
from .evaluation import (
    BlockLayout,
    ConstraintSet,
    block_layout,
    constraint_sets,
    gamma_all,
    jacobian_blocks_all,
    phi_all,
)
from .fingerprint import fingerprint
from .graph import Group, Structure, structure

__all__ = [
    "System",
    "GroupPlan",
    "build_system",
    "system_of",
    "phi",
    "jacobian",
    "jacobian_blocks",
    "ground_jacobian",
    "gamma",
    "nu",
    "coordinate_gradient",
    "coordinate_gradients",
    "coordinate_rate",
    "link_pair",
    "link_poses",
]


@dataclass(frozen=True)
class GroupPlan:
    """Index sets of one Assur group: its q columns and its constraint rows."""

    group: Group
    cols: np.ndarray  # indices into q
    rows: np.ndarray  # indices into Φ
    constraints: tuple[int, ...]  # indices into System.constraints


@dataclass(frozen=True, eq=False)
class System:
    """Model + structure + layout, built once and reused for every position and variant."""

    model: Model
    structure: Structure
    links: tuple[str, ...]  # moving links in q order
    constraints: tuple[Joint | DriverConstraint, ...]  # joints, then motion drivers
    ends: np.ndarray  # (n_c, 2) link indices; ground = n_links
    row_start: np.ndarray  # (n_c + 1,) first row of each constraint
    plans: tuple[GroupPlan, ...]
    l_ref: float | np.ndarray  # longest link dimension, m ((V, 1) stacked)
    n_joint_rows: int = field(default=0)
    sets: tuple[ConstraintSet, ...] = ()  # the evaluation plan (structure/evaluation.py)
    layout: BlockLayout | None = None  # where Φ_q's entries go among the group blocks
    memo: dict = field(default_factory=dict, repr=False)  # what later stages compute once per
    # system (the start pose, the whole motion); held here, not in module-level tables, so it
    # goes with the system; not pickled
    joints: tuple[Joint, ...] = field(init=False, repr=False)  # the constraints that are joints
    motion_drivers: tuple[DriverConstraint, ...] = field(init=False, repr=False)  # the others

    def __post_init__(self):
        is_driver = [isinstance(c, DriverConstraint) for c in self.constraints]
        pairs = list(zip(self.constraints, is_driver, strict=True))
        object.__setattr__(self, "joints", tuple(c for c, d in pairs if not d))
        object.__setattr__(self, "motion_drivers", tuple(c for c, d in pairs if d))

    def __getstate__(self):
        return {**self.__dict__, "memo": {}}

    @property
    def n_q(self) -> int:
        return 3 * len(self.links)

    @property
    def n_rows(self) -> int:
        return int(self.row_start[-1])

    def link_index(self, name: str) -> int:
        return self.links.index(name)

    def rows_of(self, k: int) -> slice:
        return slice(int(self.row_start[k]), int(self.row_start[k + 1]))


def build_system(model: Model) -> System:
    """Compile the model: structure, q layout, constraint rows and group plans.

    Parameters
    ----------
    model : Model
        A loaded mechanism.

    Returns
    -------
    System
        The compiled mechanism, opaque: :func:`analyze` takes it (and compiles a
        model once, keeping the system with it).

    Raises
    ------
    StructureError
        The topology does not match the drivers or the listed loops (no Assur-group
        decomposition).

    Examples
    --------
    >>> import kinetostatics as ks
    >>> system = ks.build_system(ks.load("mechanisms/slider_crank.yaml"))  # doctest: +SKIP
    >>> result = ks.analyze(system)  # doctest: +SKIP
    """
    st = structure(model)
    links = tuple(link.name for link in model.moving_links)
    index = {name: k for k, name in enumerate(links)}
    index[model.ground.name] = len(links)
    joints = {j.name: j for j in model.joints}
    constraints: list = list(model.joints)
    constraints += [
        DriverConstraint(d, joints[d.joint]) for d in model.drivers if d.motion is not None
    ]
    ends = np.array([[index[c.links[0]], index[c.links[1]]] for c in constraints], dtype=int)
    row_start = np.cumsum([0, *(c.n_eq for c in constraints)]).astype(int)
    by_name = {c.name: k for k, c in enumerate(constraints)}
    plans = []
    for g in st.groups:
        cols = np.array([3 * index[n] + c for n in g.links for c in range(3)], dtype=int)
        cons = tuple(by_name[n] for n in g.joints + g.drivers)
        rows = np.concatenate([np.arange(row_start[k], row_start[k + 1]) for k in cons])
        plans.append(GroupPlan(g, cols, rows.astype(int), cons))
    l_ref = _reference_length(model)
    n_joint_rows = int(row_start[len(model.joints)])
    sets = constraint_sets(constraints, ends, row_start, len(model.joints))
    return System(
        model,
        st,
        links,
        tuple(constraints),
        ends,
        row_start,
        tuple(plans),
        l_ref,
        n_joint_rows,
        sets,
        block_layout(sets, plans, ends, len(links), len(model.joints)),
    )


def system_of(model: Model) -> System:
    """``build_system(model)``, built once per model and kept on it (not pickled with it).

    The model's fingerprint (:mod:`~kinetostatics.structure.fingerprint`: its arrays'
    bytes, its containers' items and its fields, taken apart once) says whether it changed:
    a model changed in place since (its arrays are writable) is built again, so a cached
    system never describes another model."""
    hit = model._compiled
    if hit is not None and hit[0].same(model):
        return hit[1]
    system = build_system(model)
    key = fingerprint(model)
    if key is not None:  # a model holding what a fingerprint cannot follow: no cache
        object.__setattr__(model, "_compiled", (key, system))
    return system


def _reference_length(model: Model) -> float | np.ndarray:
    """The largest extent of a link's points, m (``(V, 1)`` for stacked variants)."""
    l_ref: float | np.ndarray = 1e-300
    for link in model.links:
        if len(link.points) > 1:
            e = np.ptp(np.stack(np.broadcast_arrays(*link.points.values())), axis=0)
            l_ref = np.maximum(l_ref, np.hypot(e[..., 0], e[..., 1]))
    return float(l_ref) if np.ndim(l_ref) == 0 else l_ref


# -- assembly over batches -----------------------------------------------------
def _ext(q: np.ndarray) -> np.ndarray:
    """q with ground's zeros appended: shape (..., n_q + 3)."""
    return np.concatenate((q, np.zeros(q.shape[:-1] + (3,))), axis=-1)


def _pair(qe: np.ndarray, ends: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    i, j = ends
    return qe[..., 3 * i : 3 * i + 3], qe[..., 3 * j : 3 * j + 3]


def link_poses(system: System, q: np.ndarray) -> np.ndarray:
    """The links' poses with their frames (cos θ, sin θ computed once for this state, not
    once per joint and use), ``(..., n_links + 1, 5)``, ground last.

    The last state's are kept with the system: the stages of one analysis ask for the
    poses of the same q several times (Φ_q, γ, each effort's gradient).  The key is the
    state's content (an exact comparison, far cheaper than the cosines; none where the
    state is the very array kept and read-only, as an analysis's rows are), and the
    poses kept are read-only, so a hit is the same numbers as a new computation."""
    pe = _kept_poses(system, q)
    if pe is not None:
        return pe
    pe = poses(q, len(system.links))
    pe.flags.writeable = False
    system.memo["poses"] = (np.array(q, dtype=float), pe, q)
    return pe


FRAMED_KEPT = 64  # the live rows of one system whose pass's frames are kept


def keep_poses(system: System, q: np.ndarray, pe: np.ndarray) -> None:
    """Keep ``pe``, the poses of the frozen rows ``q`` with the frames computed with them
    (a closed-form pass's: equal to ``cos θ``, ``sin θ`` to round-off), for as long as
    ``q`` lives: :func:`link_poses` gives them for these very rows and runs of them, in
    every stage and whatever ran between (a column read later, another analysis), and
    its own frames for any other array, of the same numbers or not."""
    if q.flags.writeable or pe.shape[:-2] != q.shape[:-1]:
        raise ValueError("keep_poses: the rows must be frozen and the poses theirs")
    kept = system.memo.setdefault("framed", {})
    if len(kept) >= FRAMED_KEPT:  # the oldest rows' later stages evaluate their own frames
        del kept[next(iter(kept))]
    key = id(q)  # the entry goes with the rows (a weak reference: they are not kept alive)

    def forget(_ref: weakref.ref, key: int = key) -> None:
        kept.pop(key, None)

    kept[key] = (weakref.ref(q, forget), pe)


def _kept_poses(system: System, q: np.ndarray) -> np.ndarray | None:
    """The poses kept with the system where they are ``q``'s (:func:`link_poses`,
    :func:`keep_poses`)."""
    if not q.flags.writeable:  # rows a pass framed, or a run of them
        for ref, pe in list(system.memo.get("framed", {}).values()):  # (rows may die meanwhile)
            if (rows := ref()) is q:
                return pe
            if rows is not None and (k := _rows_within(rows, q)) is not None:
                return pe[k : k + len(q)]
    hit = system.memo.get("poses")
    if hit is None:
        return None
    if hit[2] is q and not q.flags.writeable:  # the same frozen rows: the same numbers
        return hit[1]
    if (k := _rows_within(hit[2], q)) is not None:  # a run of them (a stage's chunk)
        return hit[1][k : k + len(q)]
    if hit[0].shape == q.shape and np.array_equal(hit[0], q):
        return hit[1]
    return None


def _rows_within(kept: np.ndarray, q: np.ndarray) -> int | None:
    """The first row of ``q`` among the rows ``kept`` where ``q`` is a run of them (the
    same memory, row for row: a basic slice along the first axis) and both are frozen;
    else None."""
    if q.flags.writeable or kept.flags.writeable or q.ndim != kept.ndim or q.ndim < 2:
        return None
    if q.shape[1:] != kept.shape[1:] or q.strides != kept.strides or kept.strides[0] <= 0:
        return None
    offset = q.__array_interface__["data"][0] - kept.__array_interface__["data"][0]
    k, rest = divmod(offset, kept.strides[0])
    return k if rest == 0 and 0 <= k <= len(kept) - len(q) else None


def kept_pose(system: System, q: np.ndarray, k: int) -> np.ndarray | None:
    """Link ``k``'s pose with its frame ``(..., 5)`` at ``q`` where the system keeps the
    poses of that state (:func:`link_poses`), else None: a caller that needs one link's
    frame at a state of its own evaluates it rather than the poses of every link."""
    pe = _kept_poses(system, q)
    return None if pe is None else pe[..., k, :]


def _pose_pair(pe: np.ndarray, ends: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    return pe[..., ends[0], :], pe[..., ends[1], :]


def _selection(system: System, which: Sequence[int] | None) -> Sequence[int]:
    return range(len(system.constraints)) if which is None else which


def phi(
    system: System, q: np.ndarray, psi: np.ndarray, which: Sequence[int] | None = None
) -> np.ndarray:
    """Φ(q) for the constraints ``which`` (default all), ``(..., rows)``.

    ``psi (..., n_drivers)`` are the prescribed driver coordinates.
    """
    if which is None:
        return phi_all(system.sets, system.n_rows, link_poses(system, q), psi)
    pe, out = link_poses(system, q), []
    n_j = len(system.model.joints)
    for k in _selection(system, which):
        c = system.constraints[k]
        qi, qj = _pose_pair(pe, system.ends[k])
        if k >= n_j:  # a driver's constraint: its row reads the driver coordinate
            out.append(cast(DriverConstraint, c).residual(qi, qj, psi[..., k - n_j]))
        else:
            out.append(cast(Joint, c).residual(qi, qj))
    return np.concatenate(out, axis=-1)


def jacobian(
    system: System,
    q: np.ndarray,
    which: Sequence[int] | None = None,
    cols: np.ndarray | None = None,
    ground: bool = False,
    pe: np.ndarray | None = None,
) -> np.ndarray:
    """Φ_q for the constraints ``which``, restricted to ``cols``: ``(..., rows, cols)``.

    With ``ground=True`` the three columns of the ground link are kept at the end.
    Only the columns asked for are built (Φ_q is mostly structural zeros).  ``pe``:
    the poses of q (:func:`link_poses`) when the caller has them already.
    """
    pe = link_poses(system, q) if pe is None else pe
    which = list(_selection(system, which))
    width = q.shape[-1] + (3 if ground else 0)
    cols = np.arange(width) if cols is None else np.arange(width)[cols]
    pos = np.full(q.shape[-1] + 3, -1)
    pos[cols] = np.arange(len(cols))
    if not np.array_equal(pos[cols], np.arange(len(cols))):  # a column asked for twice
        return jacobian(system, q, which, ground=ground, pe=pe)[..., cols]
    n_rows = sum(system.constraints[k].n_eq for k in which)
    out = np.zeros(q.shape[:-1] + (n_rows, len(cols)))
    r = 0
    for k in which:
        c = system.constraints[k]
        ends = system.ends[k]
        for link, jl in zip(ends, c.jacobian(*_pose_pair(pe, ends))):
            at = pos[3 * link : 3 * link + 3]
            if at[0] >= 0 and at[1] == at[0] + 1 and at[2] == at[0] + 2:
                dest = out[..., r : r + c.n_eq, at[0] : at[0] + 3]
                if ends[0] != ends[1]:  # written once: as 0 + jl (−0 → +0), not read first
                    np.add(jl, 0.0, out=dest)
                else:
                    dest += jl
            elif (at >= 0).any():
                out[..., r : r + c.n_eq, at[at >= 0]] += jl[..., at >= 0]
        r += c.n_eq
    return out


def jacobian_blocks(
    system: System, q: np.ndarray
) -> list[tuple[np.ndarray, np.ndarray | None, np.ndarray]]:
    """Φ_q by Assur group, as :class:`~kinetostatics.base.blocks.BlockFactor` takes it:
    for each plan, (its diagonal block, rows × its own columns; its coupling block, rows
    × the earlier groups' columns its constraints touch, or None; those columns).  Each
    constraint is evaluated once, by the system's evaluation plan; the blocks are views
    of one buffer.  The ground's block is kept with the poses (:func:`ground_jacobian`)."""
    pe = link_poses(system, q)
    assert system.layout is not None  # set by build_system
    blocks, ground = jacobian_blocks_all(system.sets, system.layout, pe)
    system.memo["ground_jacobian"] = (pe, ground, None)
    return blocks


def ground_jacobian(system: System, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The rows of Φ (of the joints jointed to the ground, in order) and Φ_q there over
    the ground's three columns, ``(..., rows, 3)``: kept from :func:`jacobian_blocks` at
    the same state (its poses), else evaluated."""
    layout = system.layout
    assert layout is not None  # set by build_system
    if not layout.ground_joints:
        return layout.ground_rows, np.zeros(q.shape[:-1] + (0, 3))
    pe = link_poses(system, q)
    hit = system.memo.get("ground_jacobian")
    if hit is not None and hit[0] is pe:  # rows in order (a plan keeps a view of its buffer)
        _, ground, ready = hit
        if ready is not None:  # its structural zeros written first (kinematics/plan_buffers.py)
            ready()
        return layout.ground_rows, np.ascontiguousarray(ground)
    jac = jacobian(system, q, layout.ground_joints, np.arange(-3, 0), ground=True, pe=pe)
    return layout.ground_rows, jac


def link_pair(system: System, x: np.ndarray, k: int) -> tuple[np.ndarray, np.ndarray]:
    """The coordinates (or rates) of constraint ``k``'s two links from ``x (..., n_q)``,
    ``(..., 3)`` each, ground as zeros."""
    return _pair(_ext(x), system.ends[k])


def coordinate_gradient(system: System, q: np.ndarray, k: int, ground: bool = False) -> np.ndarray:
    """Gradient of constraint ``k``'s joint coordinate over all of q, ``(..., n_q)``."""
    return coordinate_gradients(system, q, (k,), ground)[..., 0, :]


def coordinate_gradients(
    system: System, q: np.ndarray, ks: Sequence[int], ground: bool = False
) -> np.ndarray:
    """The gradients of the constraints ``ks``' joint coordinates over all of q, in one
    array ``(..., len(ks), n_q)`` (``n_q + 3`` columns with the ground's)."""
    pe = link_poses(system, q)
    out = entries_last(np.zeros((len(ks), q.shape[-1] + 3) + q.shape[:-1]))  # component-major
    kept: dict = {}  # the poses laid out for the compiled kernels, once
    for n, k in enumerate(ks):
        i, j = system.ends[k]
        gi, gj = _directions(system, pe, k, kept)
        if i == j:  # pragma: no cover - a joint joins two links
            out[..., n, 3 * i : 3 * i + 3] += gi + gj
        else:  # written, not added: ~10× faster into the strided view, the same numbers
            out[..., n, 3 * i : 3 * i + 3] = gi
            out[..., n, 3 * j : 3 * j + 3] = gj
    return out if ground else out[..., :-3]


def coordinate_rate(system: System, q: np.ndarray, x: np.ndarray, k: int) -> np.ndarray:
    """The rate of constraint ``k``'s joint coordinate, c_k,q · x, at rates ``x (..., n_q)``
    (q̇, or a tangent ∂q/∂ψ), ``(...)``: its two links' directions (the entries of
    :func:`coordinate_gradient` that are not zero) times their rates, the ground's none —
    without the gradient's row over all of q (the joint's relative speed at ``x`` = q̇).
    A joint whose direction is the same at every pose (``Joint.fixed_direction``: a
    revolute's θ_j − θ_i) reads the rates of its components that are not zero alone, no
    pose: the same numbers (0·x adds nothing, ±1·x is ±x)."""
    n_links = len(system.links)
    fixed = getattr(system.constraints[k], "fixed_direction", None)
    rate = None
    if fixed is not None:
        for g, link in zip(fixed, system.ends[k].tolist()):
            if link < n_links:  # the ground has no rate
                for c, gc in enumerate(g):
                    if gc:  # a new array: −x, or x·g (x·1 is x)
                        xc = x[..., 3 * link + c]
                        term = -xc if gc == -1.0 else xc * gc
                        rate = term if rate is None else rate + term
        assert rate is not None  # a joint joins a moving link
        return rate
    pe = link_poses(system, q)
    for g, link in zip(_directions(system, pe, k), system.ends[k].tolist()):
        if link < n_links:  # the ground has no rate
            xl = x[..., 3 * link : 3 * link + 3]
            term = g[..., 0] * xl[..., 0] + g[..., 1] * xl[..., 1] + g[..., 2] * xl[..., 2]
            rate = term if rate is None else rate + term
    assert rate is not None  # a joint joins a moving link
    return rate


def _directions(
    system: System, pe: np.ndarray, k: int, kept: dict | None = None
) -> tuple[np.ndarray, np.ndarray]:
    """Constraint ``k``'s joint's ``motion_direction`` at the poses ``pe``: (g_i, g_j),
    ``(..., 3)`` each; by its compiled kernel on that backend (the same numbers; the
    poses laid out for it kept in ``kept`` for the next joint)."""
    kernel = _direction_kernel(system, k) if kernels.active() else None
    if kernel is None:
        c = cast(Joint, system.constraints[k])  # a joint's coordinate: k is a joint
        return c.motion_direction(*_pose_pair(pe, system.ends[k]))
    kept = {} if kept is None else kept
    if "flat" not in kept:
        kept["flat"] = np.ascontiguousarray(entries_first(pe).reshape(pe.shape[-2:] + (-1,)))
    flat = kept["flat"]
    gi, gj = np.empty((2, 1, 3, flat.shape[-1]))
    kernel[0](kernel[1], flat, system.ends[k][:, None], gi, gj)
    lead = pe.shape[:-2]
    return entries_last(gi[0], 1).reshape(lead + (3,)), entries_last(gj[0], 1).reshape(lead + (3,))


def _direction_kernel(system: System, k: int) -> tuple | None:
    """Constraint k's compiled ``motion_direction`` and its parameters, or None (kept)."""
    key = ("direction kernel", k)
    if key not in system.memo:
        c, hit = cast(Joint, system.constraints[k]), None  # a joint (as above)
        kernel = getattr(type(c), "direction_kernel", None)
        par = c.kernel_params(1) if kernel is not None else None
        if par is not None:
            hit = (kernels.compiled(kernel), par)
        system.memo[key] = hit
    return system.memo[key]


def nu(system: System, psi_d: np.ndarray) -> np.ndarray:
    """ν = −Φ_t: zeros for joints, ψ̇ for motion drivers.  ``(..., n_rows)``."""
    zeros = np.zeros(psi_d.shape[:-1] + (system.n_joint_rows,))
    return np.concatenate((zeros, psi_d), axis=-1)


def gamma(system: System, q: np.ndarray, qd: np.ndarray, psi_dd: np.ndarray) -> np.ndarray:
    """γ such that Φ_q q̈ = γ, ``(..., n_rows)``."""
    return gamma_all(system.sets, system.n_rows, link_poses(system, q), _rates(qd), psi_dd)


def _rates(qd: np.ndarray) -> np.ndarray:
    """The links' rates ``(..., n + 1, 3)``, the ground's zeros last, stored component-major
    as the poses are (:func:`~kinetostatics.base.geometry.poses`)."""
    n, lead = qd.shape[-1] // 3, qd.shape[:-1]
    out = np.zeros((n + 1, 3) + lead)
    out[:n] = entries_first(qd.reshape(lead + (n, 3)))
    return entries_last(out)
