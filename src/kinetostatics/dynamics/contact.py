"""Contact–impact in a clearance joint (model b): the Lankarani–Nikravesh force.

With the clearance expanded by :func:`kinetostatics.dynamics.clearance.expand`
(``model: contact``), the distance s between the journal and bushing centres
is a free coordinate (the ``<joint>_contact`` effort driver on the slide of
the clearance link).  Penetration δ = s − e; the normal contact force is

    F_n = K δ^n [1 + 3(1 − c_e²)/4 · δ̇/δ̇⁻]   (δ > 0; 0 otherwise, never pulling)

(Lankarani & Nikravesh 1990), K the Hertzian stiffness
K = (4/3) E* √R*, 1/E* = (1 − ν_i²)/E_i + (1 − ν_j²)/E_j,
R* = R_j R_b/(R_b − R_j) (journal R_j, bushing R_b = R_j + e), n = 3/2, c_e the
coefficient of restitution and δ̇⁻ the normal speed at the start of this
contact (at least ``floor``, for a contact that starts at rest).  The driver's
effort is −F_n (the force of the clearance link on its slider end pushes the
pins together).  :func:`simulate_contact` integrates the motion with every
contact start and end as a terminal event, so that δ̇⁻ is known in each contact
and every integration piece has a smooth right-hand side.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from ..io.clearance import read_contact
from ..model.contact_law import ContactLaw, hertz_stiffness
from .engine import Dynamics

__all__ = ["ContactLaw", "hertz_stiffness", "read_contact", "simulate_contact", "ContactRun"]


@dataclass
class ContactRun:
    """A contact simulation: ``sample(t)`` the states (ψ_f, ψ̇_f, W); ``impacts`` the
    contact starts (time, joint, impact speed); ``nfev`` right-hand-side evaluations."""

    dynamics: object
    pieces: list
    impacts: list
    separations: list
    nfev: int

    def sample(self, t) -> np.ndarray:
        t = np.atleast_1d(np.asarray(t, dtype=float))
        starts = np.array([p[0] for p in self.pieces])
        idx = np.clip(np.searchsorted(starts, t, side="right") - 1, 0, len(self.pieces) - 1)
        out = np.empty((t.size, self.pieces[0][2](self.pieces[0][0]).size))
        for k in np.unique(idx):
            sel = idx == k
            out[sel] = self.pieces[k][2](t[sel]).T
        return out


IMPLICIT = ("BDF", "Radau", "LSODA")  # the solve_ivp methods given _stiff_jacobian


def _stiff_jacobian(dyn, contacts):
    """∂(ψ̇_f, ψ̈_f, Ẇ)/∂(ψ_f, ψ̇_f, W) keeping only the contact forces' dependence:
    ψ̈_f = M⁻¹(τ_app − h), ∂ψ̈_f/∂(δ, δ̇) = −M⁻¹ e_k ∂F_n/∂(δ, δ̇).  M and h change
    slowly; the contact terms carry the stiffness (a finite-difference Jacobian would
    cost 2 n_f + 1 evaluations of the right-hand side each time)."""
    nf = dyn.n_f

    def jac(t, y):
        ev = dyn.state(t, y)
        mass = ev.dtau[:, dyn.free].T + np.diag(dyn.added)
        d_app = np.zeros((nf, 2 * nf))
        for k in contacts:
            law = dyn.laws[k]
            kd, kv = law.partials(float(y[k]) - law.clearance, float(y[nf + k]))
            d_app[k, k], d_app[k, nf + k] = -kd, -kv
        out = np.zeros((2 * nf + 1, 2 * nf + 1))
        out[:nf, nf : 2 * nf] = np.eye(nf)
        out[nf : 2 * nf, : 2 * nf] = np.linalg.solve(mass, d_app)
        return out

    return jac


def simulate_contact(  # noqa: PLR0913  the public keywords (docs/clearance.md)
    model,
    until: float,
    *,
    initial=None,
    method: str = "Radau",
    rtol: float = 1e-6,
    atol: float | None = None,
    max_step: float = np.inf,
    max_pieces: int = 20000,
    jacobian: bool = True,
) -> ContactRun:
    """Forward dynamics of a model with ``contact`` clearances: contact starts and ends
    are terminal events; at each start the impact speed δ̇⁻ of that contact is set.

    ``initial``: {free driver: coordinate or (coordinate, speed)}; the clearance
    coordinates default to their expanded pose (in contact, at rest).  ``atol``
    defaults to ``rtol``·(1 rad, L_ref, and those per second).  ``jacobian``: give the
    implicit methods (BDF, Radau, LSODA) the contact terms' analytic Jacobian (else
    solve_ivp's finite differences).
    """
    from scipy.integrate import solve_ivp

    dyn = Dynamics(model)
    nf = dyn.n_f
    contacts = [k for k, law in enumerate(dyn.laws) if isinstance(law, ContactLaw)]
    y = np.concatenate((dyn.start(), np.zeros(nf), [0.0]))
    for name, v in (initial or {}).items():
        k = dyn.free_names.index(name)
        y[k], y[nf + k] = v if isinstance(v, (tuple, list)) else (v, 0.0)
    scale = dyn.scale[dyn.free]
    tol = rtol if atol is None else atol
    atol_v = np.concatenate((tol * scale, tol * scale, [np.inf]))
    clear = {k: dyn.laws[k].clearance for k in contacts}
    inside = {k: y[k] - clear[k] >= 0 for k in contacts}
    pieces, impacts, separations = [], [], []
    jac = _stiff_jacobian(dyn, contacts) if jacobian and method in IMPLICIT else None
    t = 0.0
    ev0 = dyn.evaluations
    for _ in range(max_pieces):
        if t >= until:
            break
        events = []
        for k in contacts:
            f = lambda tt, yy, k=k: yy[k] - clear[k]
            f.terminal, f.direction = True, (-1.0 if inside[k] else 1.0)
            events.append(f)
        dyn._cache.clear()
        opts = {"jac": jac} if jac is not None else {}
        sol = solve_ivp(
            lambda tt, yy: dyn.rhs(tt, yy),
            (t, until),
            y,
            method=method,
            rtol=rtol,
            atol=atol_v,
            dense_output=True,
            events=events or None,
            max_step=max_step,
            **opts,
        )
        if sol.status == -1:
            raise RuntimeError(
                f"contact integration failed at t = {sol.t[-1]:.6g} s: {sol.message}"
            )
        t_e = float(sol.t[-1])
        pieces.append((t, t_e, sol.sol))
        y = sol.y[:, -1].copy()
        if sol.status == 0:
            t = t_e
            break
        for n, k in enumerate(contacts):
            if sol.t_events[n].size:
                if inside[k]:
                    separations.append((t_e, dyn.free_names[k]))
                    inside[k] = False
                else:
                    v = float(y[nf + k])
                    impacts.append((t_e, dyn.free_names[k], v))
                    dyn.laws[k] = replace(dyn.laws[k], impact_speed=abs(v))
                    inside[k] = True
        t = t_e
    else:
        raise RuntimeError("too many contact events (chattering?)")
    return ContactRun(dyn, pieces, impacts, separations, dyn.evaluations - ev0)
