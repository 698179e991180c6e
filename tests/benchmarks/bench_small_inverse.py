"""The group-block inverses (base/linalg.py, ``small_inverse``) against ``np.linalg.inv``.

1. The real diagonal blocks larger than 3×3 of the shipped slider-crank and slotting
   machine (Φ_q's dyad blocks along a full cycle) at 360 and 36,000 positions: wall
   time of ``np.linalg.inv``, of ``small_inverse`` (LAPACK below ``SPARSE_FROM``) and of
   the elimination whatever the count, the ratios to LAPACK, the nonzeros of the block
   pattern, the plan's operations, and the elimination's largest difference to LAPACK
   relative to the inverse's largest entry.
2. The choice between the two (``_sparse_pays``): random patterns (n = 4, 6, 9, from
   a diagonal alone to dense), diagonally dominant so that no matrix falls back, at
   32 to 4,096 matrices: the sparse elimination forced, LAPACK, and whether the model
   picked the faster one (a miss where both are within 20 % is no loss).

    PYTHONPATH=src python tests/benchmarks/bench_small_inverse.py   # --quick: part 1 only
"""

from __future__ import annotations

import sys

import numpy as np
from _common import best_of

import kinetostatics as ks
from kinetostatics.base import linalg
from kinetostatics.structure.system import jacobian_blocks, system_of

MECHANISMS = ["slider_crank", "slotting_machine"]


def real_blocks(name: str, count: int) -> list[np.ndarray]:
    model = ks.load(f"mechanisms/{name}.yaml")
    r = ks.analyze(model, positions=np.linspace(0.0, 2 * np.pi, count), kinematics_only=True)
    return [d for d, _ in jacobian_blocks(system_of(model), r.q) if d.shape[-1] > 3]


def plan_of(a: np.ndarray) -> tuple[np.ndarray, linalg._Plan]:
    n = a.shape[-1]
    m = np.moveaxis(a, (-2, -1), (0, 1)).reshape(n, n, -1)
    return m, linalg._plan(np.any(m != 0, axis=-1), linalg._first_pivots(m[:, :, 0]))


def part_real() -> None:
    print("real blocks: np.linalg.inv, small_inverse, and the elimination at any count")
    for name in MECHANISMS:
        for count in (360, 36_000):
            for k, d in enumerate(real_blocks(name, count)):
                m, plan = plan_of(d)
                t_lapack = best_of(lambda d=d: np.linalg.inv(d))
                t_ks = best_of(lambda d=d: linalg.small_inverse(d))
                t_elim = best_of(lambda m=m, p=plan: linalg._sparse_gauss_jordan(m, p))
                ref = np.linalg.inv(d)
                err = np.abs(linalg._sparse_gauss_jordan(m, plan) - ref).max() / np.abs(ref).max()
                nnz = int(np.any(d != 0, axis=0).sum())
                f, unit = (1e6, "µs") if count < 10_000 else (1e3, "ms")
                print(
                    f"  {name} block {k} ({d.shape[-1]}×{d.shape[-1]}, {nnz} nonzeros, "
                    f"{len(plan.ops)} ops), {count} positions: LAPACK {t_lapack * f:.3g} {unit}, "
                    f"small_inverse {t_ks * f:.3g} {unit} ({t_lapack / t_ks:.1f}×), elimination "
                    f"{t_elim * f:.3g} {unit} ({t_lapack / t_elim:.1f}×); its difference to "
                    f"LAPACK {err:.1e} of the largest entry"
                )


def part_choice() -> None:
    print("choice: sparse elimination (forced) vs LAPACK, random diagonally dominant patterns")
    rng = np.random.default_rng(5)
    misses = 0
    for n in (4, 6, 9):
        for density in (0.0, 0.3, 0.6, 1.0):
            mask = (rng.random((n, n)) < density) | np.eye(n, dtype=bool)
            for count in (32, 128, 512, 4096):
                a = rng.normal(size=(n, n, count)) * mask[..., None]
                a[np.arange(n), np.arange(n)] = 2.0 * n + rng.random((n, count))
                a = np.moveaxis(a, -1, 0)  # entries contiguous, as the blocks arrive
                m, plan = plan_of(a)
                t_sparse = best_of(lambda m=m, p=plan: linalg._sparse_gauss_jordan(m, p), repeat=5)
                t_lapack = best_of(lambda a=a: np.linalg.inv(a), repeat=5)
                pays = linalg._sparse_pays(n, count, plan)
                faster = t_sparse < t_lapack
                close = max(t_sparse, t_lapack) < 1.2 * min(t_sparse, t_lapack)
                misses += pays != faster and not close
                print(
                    f"  n={n} density {density:.1f} ({int(mask.sum())} nonzeros, "
                    f"{len(plan.ops)} ops) × {count}: sparse {t_sparse * 1e6:.0f} µs, "
                    f"LAPACK {t_lapack * 1e6:.0f} µs; chosen {'sparse' if pays else 'LAPACK'}"
                    f"{'' if pays == faster or close else '  <-- the slower'}"
                )
    print(f"choices of the slower one (by more than 20 %): {misses}")


if __name__ == "__main__":
    part_real()
    if "--quick" not in sys.argv:
        part_choice()
