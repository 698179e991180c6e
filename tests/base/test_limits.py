"""The loader's link limit and the memory an analysis of a large linkage is checked
against (base/limits.py, base/memory.py; docs/errors.md)."""

from __future__ import annotations

import pytest

import kinetostatics as ks
from kinetostatics.base import memory
from kinetostatics.base.limits import MAX_LINKS
from tests.chains import dyad_chain


def test_the_memory_of_a_row_grows_with_the_moving_links(monkeypatch):
    per_link = memory.BYTES_PER_LINK_POSITION
    monkeypatch.setattr(memory, "available_memory", lambda: 1000 * 400 * per_link)
    assert memory.memory_shortfall(1000, "the analysis", links=400) is None
    why = memory.memory_shortfall(1000, "the analysis", links=401)
    assert why is not None and why.startswith("the analysis at 1000 positions needs about")
    # a small linkage costs the floor of BYTES_PER_POSITION a row
    monkeypatch.setattr(memory, "available_memory", lambda: 1000 * memory.BYTES_PER_POSITION)
    assert memory.memory_shortfall(1000, "x", links=2) is None
    assert memory.memory_shortfall(1001, "x", links=2) is not None


def test_a_large_chain_is_refused_by_memory_before_it_is_analysed(monkeypatch):
    model = ks.loads(dyad_chain(40, positions=2000))  # 81 moving links
    need = 2000 * 81 * memory.BYTES_PER_LINK_POSITION
    monkeypatch.setattr(memory, "available_memory", lambda: need - 1)
    with pytest.raises(ks.ModelError, match=r"analysis\.positions: the analysis at 2000 positions"):
        ks.analyze(model)


@pytest.mark.slow  # about 1 s on a quiet machine: 999 links read and decomposed
def test_a_chain_of_dyads_near_the_link_limit_loads_and_decomposes():
    n = (MAX_LINKS - 2) // 2  # 2n + 1 moving links and the ground
    model = ks.loads(dyad_chain(n, positions=4))
    assert len(model.links) <= MAX_LINKS
    system = ks.build_system(model)
    assert len(system.plans) == n + 1  # the crank, then one dyad per stage
