"""The optional compiled backend: the joints' per-position formulas compiled by numba.

NumPy is the default backend.  With the backend ``"numba"`` (:func:`set_backend`, or the
environment variable ``KINETOSTATICS_BACKEND=numba`` read at the first analysis; the
extra ``pip install 'kinetostatics[numba]'``), a joint type that declares kernels
(:attr:`~kinetostatics.joints.Joint.jacobian_kernel`, ...) has its Φ_q entries, γ,
coordinate gradients and friction magnitudes evaluated by them: one compiled loop over
the positions per set of joints, instead of one whole-array NumPy operation per term of
the formula.  A type without kernels is evaluated by NumPy as before, in the same
analysis.  Two joint-agnostic stages have kernels beside their NumPy code: the adjugate
inverses (``base/linalg.py``) and the friction fixed point's step
(``kinetics/friction.py``).

A kernel is plain Python (it runs, slowly, without numba) written with the same
operations in the same order as the type's NumPy formula, so both backends give the same
numbers to the bit (tests/base/test_kernels.py checks every kernel, and whole analyses of
the shipped mechanisms).  Compiling takes a few seconds at a process's first analysis;
the machine code is cached on disk for the next processes (numba's ``cache=True``).
"""

from __future__ import annotations

import functools
import os
from collections.abc import Callable
from dataclasses import dataclass

from ..errors import Location, ModelError
from .optional import require

__all__ = [
    "BACKENDS",
    "Kernels",
    "backend",
    "set_backend",
    "active",
    "compiled",
    "helper",
    "scatter_blocks",
]

BACKENDS = ("numpy", "numba")
ENVIRONMENT = "KINETOSTATICS_BACKEND"

_chosen: list[str] = []  # the backend set, once read (a list: no module-level rebinding)


def backend() -> str:
    """The backend in use: ``"numpy"`` (the default) or ``"numba"``."""
    if not _chosen:
        name = os.environ.get(ENVIRONMENT, "numpy").strip().lower() or "numpy"
        set_backend(name, where=f"the environment variable {ENVIRONMENT}")
    return _chosen[0]


def set_backend(name: str, where: str = "set_backend") -> None:
    """Use the backend ``name`` for the analyses that follow.

    The backend evaluates the constraint Jacobians and accelerations: NumPy (the
    default) or the joints' kernels compiled by numba.  Both give the same numbers to
    round-off.  The environment variable ``KINETOSTATICS_BACKEND`` sets it at start.

    Parameters
    ----------
    name : {"numpy", "numba"}
        The backend.
    where : str, optional
        What the error message names as the source of ``name`` (default
        ``"set_backend"``).

    Raises
    ------
    ModelError
        ``name`` is not a known backend.
    MissingPackageError
        ``name`` is ``"numba"`` and numba is not installed (the message gives the
        line that installs it).

    Examples
    --------
    >>> import kinetostatics as ks
    >>> ks.set_backend("numba")  # doctest: +SKIP
    >>> ks.set_backend("fortran")
    Traceback (most recent call last):
    ...
    kinetostatics.errors.ModelError: set_backend: unknown backend 'fortran'; known: numpy, numba
    """
    if name not in BACKENDS:
        known = ", ".join(BACKENDS)
        raise ModelError([(Location(where), f"unknown backend '{name}'; known: {known}")])
    if name == "numba":
        require("numba", "numba", f"the compiled backend ({where} = numba)")
    _chosen[:] = [name]


def active() -> bool:
    """Whether the compiled backend is in use."""
    return backend() == "numba"


def helper(function):
    """Mark a plain function that kernels call (a joint's frame, say): compiled with them."""
    function.kernel_helper = True
    return function


@functools.cache
def compiled(kernel):
    """``kernel`` compiled by numba (once per process; cached on disk across processes),
    with the :func:`helper` functions of its module."""
    numba = require("numba", "numba", "the compiled backend")
    for value in list(kernel.__globals__.values()):
        if getattr(value, "kernel_helper", False) and not getattr(value, "kernel_ready", False):
            numba.extending.register_jitable(value)
            value.kernel_ready = True
    return numba.njit(cache=True, error_model="numpy")(kernel)  # x/0: inf or NaN, as NumPy


@dataclass(frozen=True)
class Kernels:
    """A constraint set's compiled evaluations, its parameters bound: ``jacobian(P, ends,
    ji, jj)`` fills ``ji, jj (k, n_eq, 3, N)`` (each link's Φ_q entries) and ``gamma(P, V,
    ends, extra, out)`` fills ``out (k, n_eq, N)``, from the poses ``P (n + 1, 5, N)`` and
    rates ``V (n + 1, 3, N)`` (component-major, ground last), the set's links ``ends (2,
    k)`` and ``extra (N,)``: ψ̈ of a motion driver (unused by a joint)."""

    jacobian: Callable
    gamma: Callable


def scatter_blocks(buf, to_i, to_j, ji, jj):
    """Φ_q's entries of a set into the group blocks' buffer ``buf (size + 1, N)``, as
    :func:`~kinetostatics.structure.evaluation.jacobian_blocks_all` puts them: link i's
    ``ji (k, n_eq, 3, N)`` at its slots ``to_i (k, n_eq, 3)`` as 0 + J (a −0 written as
    +0), then link j's added onto what is there."""
    k, rows, cols = to_i.shape
    n = ji.shape[3]
    for m in range(k):
        for r in range(rows):
            for x in range(cols):
                dst, src = buf[to_i[m, r, x]], ji[m, r, x]
                for p in range(n):
                    dst[p] = src[p] + 0.0
        for r in range(rows):
            for x in range(cols):
                dst, src = buf[to_j[m, r, x]], jj[m, r, x]
                for p in range(n):
                    dst[p] += src[p]
