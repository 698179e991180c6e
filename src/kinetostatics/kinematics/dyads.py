"""Closed-form dyads: a fast path beside the groups' Newton solve.

For RRR, RRP (slide axis on a known link) and RPR (slide axis on the dyad's
pivoted link) dyads, and for a link driven about a revolute on a known link,
the positions of every requested time follow in closed form from the known
links, vectorised over all positions at once.  The assembly branch is the
sign ``σ`` read off the Newton solution at the sketched pose; an optional
per-position factor (±1) multiplies it, so a path can change to the other
closed-form sign where it passes a change point (see
:func:`kinetostatics.kinematics.closed_path.closed_form_path`).  Each group also
gives the dyad's *discriminant* ``D``, normalised to its scale: ``D > 0`` where
the dyad assembles, ``D = 0`` at its singular positions (the two assemblies
meet), ``D < 0`` where the links cannot reach.  ``D`` is a smooth function of
the known links' poses (no square root is taken), so it can be interpolated and
minimised along a path: ``√D`` is the distance of the assembly from the singular
pose (the margin).

The groups of a system are solved in one pass, written once per system (and start
pose) as Python source: :func:`closed_forms` gives a :class:`ClosedForms` whose
``run(q, psi, signs) -> (q, D)`` fills every column of ``q`` and the groups'
discriminants ``D (..., n_groups)`` (and, asked, the frames it placed the links with).
The source is one straight line of component formulas (x and y as separate arrays:
no ``(..., 2)`` temporaries), the joints' points and the dyads' lengths as constants,
each link's angle, cos θ and sin θ computed once and read by the later groups
(``ClosedForms.source`` is the text).  The constants are those of the model, scalars,
or arrays along a leading variant axis for a stacked batch: the same text serves both.

The closed forms are formulas of revolute and prismatic pairs by nature (like
pyslvs' PLLP), so this module names the joint classes and reads their
attributes (``p_i``, ``p_j``, ``a``, ``u``, ``p``); with the velocity polygons and
the clearance macro it is the only place outside ``joints/`` that does.
"""

from __future__ import annotations

import functools
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from ..base.geometry import cross, dot, perp, rotate, wrap_angle
from ..joints import Prismatic, Revolute
from ..structure.system import GroupPlan, System

__all__ = ["closed_form", "closed_forms", "ClosedForms", "MARGIN"]

MARGIN = 1e-3  # below this margin √D a solve near a guess hands over to Newton

FRAMES_FROM = 512
"""Points of a pass from which a dyad's links take their cos θ and sin θ from their own
vectors (:meth:`_Pass.heading`: ~12 whole-array operations) rather than by ``np.cos``
and ``np.sin`` (two calls of ~10 ns a number): below, the calls cost less."""


@dataclass(frozen=True, eq=False)
class ClosedForms:
    """The closed forms of every group of a system, in solve order, as one generated pass:
    ``run(q, psi, signs, F=None) -> (q, D)`` writes every link's (x, y, θ) into ``q (...,
    n_q)`` at the driver coordinates ``psi (..., n_d)`` and returns it with the
    discriminants ``D (..., n_groups)``; group g takes its start sign times ``signs[...,
    g]`` (±1), or its start sign where ``signs`` is None.  With ``F (n_links, 2, ...)``
    the pass also writes each link's cos θ and sin θ there, the frame it placed the link
    with.  ``source`` is the generated text."""

    source: str
    run: Callable[..., tuple[np.ndarray, np.ndarray]]
    n_groups: int
    wrapping: tuple[int, ...] = ()  # the links whose angle may jump by 2π (a heading's)

    def __len__(self) -> int:
        return self.n_groups


class _Pass:
    """The source of one pass being written: its lines, its constants (``env``), and the
    links placed so far (their angle ``t<k>``, position ``x<k>``, ``y<k>`` and, once
    asked, their frame ``c<k>``, ``s<k>``)."""

    def __init__(self, system: System):
        self.system = system
        self.env: dict = {"np": np}
        self.lines: list[str] = []
        self.framed: set[int] = set()
        self.placed: set[int] = set()
        self.frames: dict[int, tuple] = {}  # cos θ, sin θ without cos and sin (a recipe)
        self.wrapping: set[int] = set()  # links whose angle may jump by 2π along a path
        self.n = 0

    def index(self, link: str) -> int | None:
        """The link's index among the moving links, None for the ground."""
        links = self.system.links
        return links.index(link) if link in links else None

    def const(self, value) -> str:
        name = f"K{len(self.env)}"
        self.env[name] = value
        return name

    def vec(self, p: np.ndarray) -> tuple[str, str]:
        return self.const(p[..., 0]), self.const(p[..., 1])

    def let(self, expr: str) -> str:
        """A new local set to ``expr``."""
        name = self.local()
        self.lines.append(f"    {name} = {expr}")
        return name

    def local(self) -> str:
        """A new local's name."""
        self.n += 1
        return f"v{self.n}"

    def angle(self, link: str) -> str:
        k = self.index(link)
        return "0.0" if k is None else f"t{k}"

    def set_angle(
        self, link: str, theta: str, frame: tuple[str, str] | None = None, like: str | None = None
    ) -> None:
        """The link's angle ``theta``; ``frame``: its cos θ and sin θ as arithmetic on
        the pass's locals (:meth:`heading`, :meth:`turned_by`) over :data:`FRAMES_FROM`
        points and more, else evaluated by ``np.cos`` and ``np.sin`` at the frame's first
        use (so over fewer points, where a call costs more than ~10 ns a number);
        ``like``: the link whose angle
        plus a continuous term it is (it jumps by 2π where that one does; the ground's
        never), else a heading (``arctan2``: it may jump by 2π along a path)."""
        k = self.index(link)
        self.lines.append(f"    t{k} = {theta}")
        if frame is not None:
            self.frames[k] = frame
        if like is None or self.index(like) in self.wrapping:
            self.wrapping.add(k)

    def heading(self, vx: str, vy: str, alpha) -> tuple:
        """The recipe of cos and sin of ``atan2(vy, vx) − alpha`` (``alpha`` a constant)
        from the vector itself: its direction (v / |v|) turned back by ``alpha`` — the
        same angle to round-off, without a cosine or a sine (each ~10 ns a number, most of
        a pass over thousands of points): (lines, cos, sin, the links it reads)."""
        r, ex, ey = self.local(), self.local(), self.local()
        lines = [f"{r} = np.sqrt({vx} * {vx} + {vy} * {vy})", f"{ex} = {vx} / {r}"]
        lines.append(f"{ey} = {vy} / {r}")
        ca, sa = self.const(np.cos(alpha)), self.const(np.sin(alpha))
        return lines, f"{ex} * {ca} + {ey} * {sa}", f"{ey} * {ca} - {ex} * {sa}", ()

    def turned_by(self, link: str, angle) -> tuple:
        """The recipe of cos and sin of ``link``'s angle + ``angle`` (a constant) by the
        sum's formulas from the link's frame (the ground's: the constant's cos and sin)."""
        ca, sa = self.const(np.cos(angle)), self.const(np.sin(angle))
        k = self.index(link)
        if k is None:
            return [], ca, sa, ()
        return [], f"c{k} * {ca} - s{k} * {sa}", f"s{k} * {ca} + c{k} * {sa}", (k,)

    def frame(self, k: int) -> tuple[str, str]:
        """The names of link k's cos θ and sin θ, written at their first use: by its
        recipe over :data:`FRAMES_FROM` points or more, else by ``np.cos``, ``np.sin``."""
        if k not in self.framed:
            self.framed.add(k)
            by_call = [f"c{k} = np.cos(t{k})", f"s{k} = np.sin(t{k})"]
            if k not in self.frames:
                self.lines += ["    " + line for line in by_call]
                return f"c{k}", f"s{k}"
            lines, c, s_, reads = self.frames[k]
            for other in reads:
                self.frame(other)
            self.env["FRAMES_FROM"] = FRAMES_FROM
            self.lines += [
                "    if psi[..., 0].size >= FRAMES_FROM:",
                *("        " + line for line in [*lines, f"c{k} = {c}", f"s{k} = {s_}"]),
                "    else:",
                *("        " + line for line in by_call),
            ]
        return f"c{k}", f"s{k}"

    def turned(self, link: str, p: np.ndarray) -> tuple[str, str]:
        """Local vector ``p`` of ``link`` in world axes (the ground's: ``p`` itself); the
        link's cos θ and sin θ evaluated at its first use."""
        px, py = self.vec(p)
        k = self.index(link)
        if k is None:
            return px, py
        c, s_ = self.frame(k)
        return self.let(f"{c} * {px} - {s_} * {py}"), self.let(f"{s_} * {px} + {c} * {py}")

    def world(self, link: str, p: np.ndarray) -> tuple[str, str]:
        """Point ``p`` of ``link`` (local) in world coordinates."""
        k = self.index(link)
        if k is None:
            return self.vec(p)
        rx, ry = self.turned(link, p)
        return self.let(f"x{k} + {rx}"), self.let(f"y{k} + {ry}")

    def place(self, link: str, wx: str, wy: str, local: np.ndarray) -> None:
        """Set the position of ``link`` (its angle set) so that its local point ``local``
        lies at (``wx``, ``wy``), and write its pose into ``q``."""
        k = self.index(link)
        self.placed.add(k)
        rx, ry = self.turned(link, local)
        self.lines += [
            f"    x{k} = {wx} - {rx}",
            f"    y{k} = {wy} - {ry}",
            f"    q[..., {3 * k}] = x{k}",
            f"    q[..., {3 * k + 1}] = y{k}",
            f"    q[..., {3 * k + 2}] = t{k}",
            "    if F is not None:",
            f"        F[{k}, 0], F[{k}, 1] = {self.frame(k)[0]}, {self.frame(k)[1]}",
        ]

    def sign(self, g: int, sigma) -> str:
        """Group g's branch sign: its start sign ``sigma`` times ``signs[..., g]``."""
        s = self.const(sigma)
        return self.let(f"{s} if signs is None else {s} * signs[..., {g}]")


def _world(system: System, q: np.ndarray, link: str, p: np.ndarray) -> np.ndarray:
    """Point ``p`` of ``link`` in world coordinates at the pose ``q`` (the start pose)."""
    if link not in system.links:  # the ground (the moving links are the others)
        return np.broadcast_to(p, q.shape[:-1] + (2,))
    k = system.links.index(link)
    return q[..., 3 * k : 3 * k + 2] + rotate(q[..., 3 * k + 2], p)


def _angle(system: System, q: np.ndarray, link: str):
    if link not in system.links:  # the ground
        return np.zeros(q.shape[:-1])
    return q[..., 3 * system.links.index(link) + 2]


def _heading(v: np.ndarray) -> np.ndarray:
    return np.arctan2(v[..., 1], v[..., 0])


def _norm(v: np.ndarray) -> np.ndarray:
    return np.hypot(v[..., 0], v[..., 1])


def _pin(j: Revolute, link: str) -> np.ndarray:
    return j.p_i if link == j.links[0] else j.p_j


def _other(j, link: str) -> str:
    return j.links[1] if j.links[0] == link else j.links[0]


def _split(plan, joints):
    """(a, b, inner joint, a's external joint, b's external joint), or None."""
    a, b = plan.group.links
    gj = [joints[n] for n in plan.group.joints]
    inner = [j for j in gj if set(j.links) == {a, b}]
    ext_a = [j for j in gj if a in j.links and j not in inner]
    ext_b = [j for j in gj if b in j.links and j not in inner]
    if not (len(inner) == len(ext_a) == len(ext_b) == 1):
        return None
    return a, b, inner[0], ext_a[0], ext_b[0]


Group = Callable[[_Pass, int], None]  # writes group g's part of the pass


def _rrr(system, plan, joints, q0) -> Group | None:
    parts = _split(plan, joints)
    if parts is None or not all(isinstance(j, Revolute) for j in parts[2:]):
        return None
    a, b, m, ja, jb = parts
    la_vec, lb_vec = _pin(m, a) - _pin(ja, a), _pin(m, b) - _pin(jb, b)
    la, lb = _norm(la_vec), _norm(lb_vec)
    if np.any(la == 0) or np.any(lb == 0):
        return None
    oa, ob = _other(ja, a), _other(jb, b)
    pa0 = _world(system, q0, oa, _pin(ja, oa))
    pb0 = _world(system, q0, ob, _pin(jb, ob))
    pm0 = _world(system, q0, a, _pin(m, a))
    sigma = np.sign(cross(pb0 - pa0, pm0 - pa0))

    def write(w: _Pass, g: int) -> None:
        sg = w.sign(g, sigma)
        pax, pay = w.world(oa, _pin(ja, oa))
        pbx, pby = w.world(ob, _pin(jb, ob))
        dx, dy = w.let(f"{pbx} - {pax}"), w.let(f"{pby} - {pay}")
        d2 = w.let(f"{dx} * {dx} + {dy} * {dy}")
        d = w.let(f"np.sqrt({d2})")
        x = w.let(f"({w.const(la * la - lb * lb)} + {d2}) / (2 * {d})")
        h2 = w.let(f"{w.const(la * la)} - {x} * {x}")
        sh = w.let(f"{sg} * np.sqrt(np.maximum({h2}, 0.0))")
        ex, ey = w.let(f"{dx} / {d}"), w.let(f"{dy} / {d}")
        pmx = w.let(f"{pax} + {x} * {ex} + {sh} * -{ey}")
        pmy = w.let(f"{pay} + {x} * {ey} + {sh} * {ex}")
        for link, (px, py), vec in ((a, (pax, pay), la_vec), (b, (pbx, pby), lb_vec)):
            vx, vy = w.let(f"{pmx} - {px}"), w.let(f"{pmy} - {py}")
            frame = w.heading(vx, vy, _heading(vec))
            w.set_angle(link, f"np.arctan2({vy}, {vx}) - {w.const(_heading(vec))}", frame)
        w.place(a, pax, pay, _pin(ja, a))
        w.place(b, pbx, pby, _pin(jb, b))
        w.lines.append(f"    D[..., {g}] = {h2} / {w.const(np.minimum(la, lb) ** 2)}")

    return write


def _rrp(system, plan, joints, q0) -> Group | None:
    """R (a, known) – R (a, b) – P (known link k carries the axis, b slides)."""
    parts = _split(plan, joints)
    if parts is None:
        return None
    a, b, m, ja, s = parts
    if not (
        isinstance(m, Revolute)
        and isinstance(ja, Revolute)
        and isinstance(s, Prismatic)
        and s.links[1] == b
    ):
        return None
    k = s.links[0]  # known link carrying the axis
    la_vec = _pin(m, a) - _pin(ja, a)
    la = _norm(la_vec)
    offset = _pin(m, b) - s.p  # from the sliding point to the pin, b's frame
    oa = _other(ja, a)
    tb0 = _angle(system, q0, k) + s.angle
    u0 = rotate(_angle(system, q0, k), s.u)
    pa0 = _world(system, q0, oa, _pin(ja, oa))
    w0 = _world(system, q0, k, s.a) + rotate(tb0, offset) - pa0
    pm0 = _world(system, q0, a, _pin(m, a))
    sigma = np.sign(dot(pm0 - pa0 - w0, u0) + dot(w0, u0))

    def write(w: _Pass, g: int) -> None:
        sg = w.sign(g, sigma)
        w.set_angle(b, f"{w.angle(k)} + {w.const(s.angle)}", w.turned_by(k, s.angle), k)
        ux, uy = w.turned(k, s.u)
        kax, kay = w.world(k, s.a)
        ox, oy = w.turned(b, offset)
        pax, pay = w.world(oa, _pin(ja, oa))
        wx, wy = w.let(f"{kax} + {ox} - {pax}"), w.let(f"{kay} + {oy} - {pay}")
        wu = w.let(f"{wx} * {ux} + {wy} * {uy}")
        la2 = w.const(la * la)
        disc = w.let(f"{wu} * {wu} - ({wx} * {wx} + {wy} * {wy}) + {la2}")
        sval = w.let(f"-{wu} + {sg} * np.sqrt(np.maximum({disc}, 0.0))")
        pmx, pmy = w.let(f"{pax} + {wx} + {sval} * {ux}"), w.let(f"{pay} + {wy} + {sval} * {uy}")
        vx, vy = w.let(f"{pmx} - {pax}"), w.let(f"{pmy} - {pay}")
        frame = w.heading(vx, vy, _heading(la_vec))
        w.set_angle(a, f"np.arctan2({vy}, {vx}) - {w.const(_heading(la_vec))}", frame)
        w.place(a, pax, pay, _pin(ja, a))
        w.place(b, pmx, pmy, _pin(m, b))
        w.lines.append(f"    D[..., {g}] = {disc} / {la2}")

    return write


def _rpr(system, plan, joints, q0) -> Group | None:
    """R (a, known) – P (axis on b, a slides) – R (b, known)."""
    parts = _split(plan, joints)
    if parts is None or not isinstance(parts[2], Prismatic):
        return None
    s = parts[2]
    b, a = s.links  # b carries the axis, a slides on it
    ja, jb = (parts[3], parts[4]) if parts[0] == a else (parts[4], parts[3])
    if not (isinstance(ja, Revolute) and isinstance(jb, Revolute)):
        return None
    delta = s.p - _pin(ja, a)  # a's frame: pin -> sliding point
    e = s.a - _pin(jb, b)  # b's frame: pivot -> axis point
    n_l = perp(s.u)
    nu_ang = _heading(n_l)
    k_const = dot(n_l, e - rotate(s.angle, delta))
    oa, ob = _other(ja, a), _other(jb, b)
    dv0 = _world(system, q0, oa, _pin(ja, oa)) - _world(system, q0, ob, _pin(jb, ob))
    sigma = -np.sign(wrap_angle(_heading(dv0) - nu_ang - _angle(system, q0, b)))

    def write(w: _Pass, g: int) -> None:
        sg = w.sign(g, sigma)
        pax, pay = w.world(oa, _pin(ja, oa))
        pbx, pby = w.world(ob, _pin(jb, ob))
        dx, dy = w.let(f"{pax} - {pbx}"), w.let(f"{pay} - {pby}")
        c = w.let(f"{w.const(k_const)} / np.hypot({dx}, {dy})")
        cc = w.let(f"np.clip({c}, -1.0, 1.0)")
        ss = w.let(f"{sg} * np.sqrt((1.0 - {cc}) * (1.0 + {cc}))")  # sin(σ arccos c)
        vx, vy = w.let(f"{dx} * {cc} - {dy} * {ss}"), w.let(f"{dy} * {cc} + {dx} * {ss}")
        arc = f"{sg} * np.arccos({cc})"
        w.set_angle(
            b, f"np.arctan2({dy}, {dx}) - {w.const(nu_ang)} + {arc}", w.heading(vx, vy, nu_ang)
        )
        w.set_angle(a, f"t{w.index(b)} + {w.const(s.angle)}", w.turned_by(b, s.angle), b)
        w.place(b, pbx, pby, _pin(jb, b))
        w.place(a, pax, pay, _pin(ja, a))
        w.lines.append(f"    D[..., {g}] = 1.0 - {c} * {c}")

    return write


def _driven(system, plan, joints, q0) -> Group | None:
    """A single link on a revolute to a known link, its angle set by a driver."""
    if len(plan.group.links) != 1 or len(plan.group.drivers) != 1 or len(plan.group.joints) != 1:
        return None
    (link,) = plan.group.links
    j = joints[plan.group.joints[0]]
    drivers = system.motion_drivers
    d_index = [d.name for d in drivers].index(plan.group.drivers[0])
    d = drivers[d_index]
    if not isinstance(j, Revolute) or d.joint is not j:
        return None
    other = _other(j, link)
    turn = 1.0 if j.links[1] == link else -1.0  # coordinate θ_j − θ_i

    def write(w: _Pass, g: int) -> None:
        psi = f"(psi[..., {d_index}] - {w.const(d.driver.offset)})"
        w.set_angle(link, f"{w.angle(other)} + {turn!r} * {psi}", like=other)
        atx, aty = w.world(other, _pin(j, other))
        w.place(link, atx, aty, _pin(j, link))
        w.lines.append(f"    D[..., {g}] = 1.0")

    return write


def closed_form(system: System, plan: GroupPlan, q0: np.ndarray) -> Group | None:
    """The closed form of a group, given its Newton solution ``q0`` at the sketched pose
    (which fixes the branch): the writer of its part of the pass, or ``None``."""
    joints = {j.name: j for j in system.model.joints}
    if plan.group.kind == "driven":
        return _driven(system, plan, joints, q0)
    if plan.group.kind != "dyad":
        return None
    return {"RRR": _rrr, "RRP": _rrp, "RPR": _rpr}.get(plan.group.letters, lambda *a: None)(
        system, plan, joints, q0
    )


def closed_forms(system: System, q0: np.ndarray) -> ClosedForms | None:
    """Every group's closed form (:func:`closed_form`) as one generated pass, or None
    where a group has none.  ``q0``: the start pose, ``(n_q,)`` or ``(V, 1, n_q)``."""
    groups = [closed_form(system, plan, q0) for plan in system.plans]
    if any(g is None for g in groups):
        return None
    w = _Pass(system)
    w.lines.append(f"    D = np.empty(q.shape[:-1] + ({len(groups)},))")
    for g, write in enumerate(groups):
        write(w, g)
    if w.placed != set(range(len(system.links))):  # the pass must fill every column of q
        raise AssertionError(f"closed forms place links {sorted(w.placed)} of {system.links}")
    source = "\n".join(["def run(q, psi, signs, F=None):", *w.lines, "    return q, D"]) + "\n"
    exec(_compiled(source), w.env)  # noqa: S102  our own generated text
    return ClosedForms(source, w.env["run"], len(groups), tuple(sorted(w.wrapping)))


@functools.lru_cache(maxsize=64)
def _compiled(source: str):
    """The code of a pass's source, compiled once: the constants are names, so the
    variants of a batch and the designs of an optimisation (each population a new
    stacked system) share the text of their topology, and compiling is most of the cost
    of making a pass."""
    return compile(source, "<closed forms>", "exec")
