"""Straight-line source from the joints' kernels (base/trace.py): the traced lines, run
over whole arrays, give the numbers of the kernel run position by position; identities
with numbers are applied, not written; a kernel that branches on a value is refused."""

import numpy as np
import pytest

from kinetostatics.base.trace import Lines, Sym, operand, pruned
from kinetostatics.joints import Prismatic, Revolute


class _Leaves:
    def __init__(self, lines, array, rows):
        self.lines, self.array, self.shape = lines, array, (rows, 5, 1)

    def __getitem__(self, key):
        i, c, _ = key
        return self.lines.value(f"{self.array}[{i}, {c}]")


def _run(lines: list[str], out: str, env: dict) -> None:
    exec("\n".join(["def f():", *lines, f"    return {out}"]) + "\n", env)  # noqa: S102


@pytest.mark.parametrize("cls", [Revolute, Prismatic])
def test_traced_kernels_give_the_kernels_numbers(cls):
    rng = np.random.default_rng(3)
    n_links, n, k = 3, 50, 2
    poses = rng.normal(size=(n_links, 5, n))
    poses[:, 3], poses[:, 4] = np.cos(poses[:, 2]), np.sin(poses[:, 2])
    rates = rng.normal(size=(n_links, 3, n))
    par = rng.normal(size=(k, 8 if cls is Prismatic else 4))
    par[0, 1] = 0.0  # a zero coordinate: x·0 folded
    ends = np.array([[0, 1], [1, 2]])

    ji = np.empty((k, 2, 3, n))
    jj = np.empty((k, 2, 3, n))
    gam = np.empty((k, 2, n))
    cls.jacobian_kernel(par, poses, ends, ji, jj)
    cls.gamma_kernel(par, poses, rates, ends, gam)

    lines = Lines()
    sym_p, sym_v = _Leaves(lines, "P", n_links), _Leaves(lines, "V", n_links)
    tji, tjj = np.empty((k, 2, 3, 1), dtype=object), np.empty((k, 2, 3, 1), dtype=object)
    tgam = np.empty((k, 2, 1), dtype=object)
    cls.jacobian_kernel(par, sym_p, ends, tji, tjj)
    cls.gamma_kernel(par, sym_p, sym_v, ends, tgam)
    entries = [*tji.reshape(-1), *tjj.reshape(-1), *tgam.reshape(-1)]
    body = lines.lines + [f"    out_{m} = {operand(e)}" for m, e in enumerate(entries)]
    names = ", ".join(f"out_{m}" for m in range(len(entries)))
    env = {"P": poses, "V": rates}
    _run(pruned(body, "e"), f"[{names}]", env)
    got = [np.broadcast_to(v, (n,)) for v in env["f"]()]
    want = [*ji.reshape(-1, n), *jj.reshape(-1, n), *gam.reshape(-1, n)]
    for g, w in zip(got, want):
        assert np.array_equal(g, w)  # the same operations in the same order
    assert len(set(lines.names)) == len(lines.lines)  # each operation written once


def test_identities_are_applied_and_numbers_written_exactly():
    lines = Lines()
    x = lines.value("X")
    assert x * 1.0 is x and 1.0 * x is x and x / 1.0 is x
    assert x + 0.0 is x and 0.0 + x is x and x - 0.0 is x
    assert x * 0.0 == 0.0 and 0.0 * x == 0.0
    assert (0.0 - x).name == (-x).name == (x * -1.0).name
    y = x * 0.1 + np.float64(1 / 3)
    assert isinstance(y, Sym)
    assert lines.lines[-2:] == [
        f"    {(x * 0.1).name} = e0 * 0.1",
        f"    {y.name} = {(x * 0.1).name} + 0.3333333333333333",
    ]
    assert operand(np.float64(-2.5)) == "(-2.5)"
    env: dict = {"X": np.array([3.0])}
    _run(lines.lines, y.name, env)
    assert env["f"]()[0] == 3.0 * 0.1 + 1 / 3


def test_a_double_negation_is_the_value_itself():
    """−(−x) is x bit for bit (a negation is exact): not written, whichever way the
    second negation comes (−y, y·(−1), 0 − y)."""
    lines = Lines()
    x = lines.value("X")
    y = -x
    assert -y is x and y * -1.0 is x and 0.0 - y is x
    assert lines.lines == ["    e0 = X", f"    {y.name} = -e0"]


def test_a_branch_on_a_value_is_refused():
    x = Lines().value("X")
    with pytest.raises(TypeError, match="branched"):
        if x:
            pass


def test_pruned_drops_unread_locals_only():
    lines = ["    e0 = A", "    e1 = e0 * 2.0", "    e2 = e0 + 1.0", "    out = e2"]
    assert pruned(lines) == ["    e0 = A", "    e2 = e0 + 1.0", "    out = e2"]
