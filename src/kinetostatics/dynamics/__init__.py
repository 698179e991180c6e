"""Forward dynamics from the inverse-dynamics engine (:func:`~kinetostatics.analysis.kinetics`).

The free coordinates are the coordinates of the ``effort:`` drivers; ``motion:``
drivers stay prescribed (mixed cases).  For the equations of motion every
effort driver is turned into a motion driver of a *fully driven* copy of the
model, so that the Newton–Euler solution of :func:`kinetics` gives, at any state
(ψ, ψ̇, ψ̈), the efforts the drivers must apply.  Those are affine in the free
accelerations a = ψ̈_f (frictionless):

    τ_f(ψ, ψ̇, a) = M(ψ) a + h(ψ, ψ̇)

so one batched call with a = 0 and a = unit vectors gives the generalised
mass matrix M (the equivalent inertia J_e for one coordinate) and the bias h
(velocity products, gravity, external loads, prescribed accelerations).  The
motion follows from the applied efforts τ_app(ψ, ψ̇) (constant, table, motor
curve) and added inertias J_x (a flywheel on a free coordinate):

    (M + J_x) a = τ_app − h.

With friction, τ_f is not affine in a: the consistent friction solution of
:func:`kinetics` is used and the small nonlinear equation
τ_app − J_x a − τ_f(a) = 0 is solved at every right-hand-side evaluation
(Broyden's method started from the frictionless a with the Jacobian −(M + J_x)).
Coulomb friction is *not* regularised.  At rest the sense of friction is
undetermined: a breakaway check compares the applied effort with the efforts
needed to start moving either way (friction and velocity-opposing loads taken
in that sense); the machine starts in that sense or stays at rest (stuck).

Positions are not integrated: the state is (ψ_f, ψ̇_f), and the positions are
solved from ψ at every evaluation (:func:`~kinetostatics.kinematics.positions.positions_near`),
so they lie on the constraint manifold to the Newton tolerance; the guess is a
second-order Taylor prediction from the last solved state along ψ, in steps
≤ 10° with a jump check, which keeps the solver's branch.

Loads switch (``active:`` conditions, a resistance reversing, a friction joint's
relative speed through zero) at exactly located times: each switching function
is a terminal event of ``solve_ivp``.  An integration piece holds the loads'
switching state it started with (:meth:`Dynamics.load_mode`), so its right-hand
side is smooth and continues smoothly past the switch; the switch is the root on
the piece's dense output and the next piece starts from the state there, with the
loads' state read a little past it on the old piece's continuation.  (Friction
senses still come from the state inside the friction solution.)

``scipy.integrate`` is imported only by :func:`simulate`.
"""

import importlib

_HOME = {  # name -> its module: loaded on first use (a flywheel sizing needs none of them)
    "STEP": "engine",
    "Dynamics": "engine",
    "simulate": "integration",
    "equivalent": "reduced",
    "with_effort": "reduced",
    "Simulation": "simulation",
    "speed_fluctuation": "simulation",
    "write_csv": "simulation",
    "Cycle": "stages",
    "cycle_stage": "stages",
    "full_summary": "stages",
}

__all__ = [
    "Dynamics",
    "Simulation",
    "simulate",
    "with_effort",
    "equivalent",
    "speed_fluctuation",
    "write_csv",
    "STEP",
    "Cycle",
    "cycle_stage",
    "full_summary",
]


def __getattr__(name):
    if name in _HOME:
        return getattr(importlib.import_module(f"{__name__}.{_HOME[name]}"), name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
