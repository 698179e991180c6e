"""libyaml's composer gives the tree PyYAML's gives, and every refusal stays PyYAML's
(base/document.py): the nodes' tags, values and start marks of every YAML file of the
repository are the same both ways, and texts where the two composers differ (a tab, a
``?`` in a flow key, an empty value in a flow mapping, nesting past the limits) are read
by PyYAML's composer, so their messages do not depend on whether libyaml is there."""

from __future__ import annotations

import gc

import pytest
import yaml

import kinetostatics as ks
from kinetostatics.base import document
from kinetostatics.base.limits import MAX_DEPTH
from tests.chains import dyad_chain
from tests.helpers import ROOT

pytestmark = pytest.mark.skipif(document._CLoader is None, reason="PyYAML without libyaml")


def _flat(root) -> list:
    """Every node reached, aliases once, as (kind, tag, scalar value, line, column)."""
    out, stack, seen = [], [root], set()
    while stack:
        n = stack.pop()
        value = n.value if isinstance(n, yaml.ScalarNode) else None
        out.append((type(n).__name__, n.tag, value, n.start_mark.line, n.start_mark.column))
        if id(n) in seen:
            continue
        seen.add(id(n))
        if isinstance(n, yaml.MappingNode):
            for k, v in n.value:
                stack += [k, v]
        elif isinstance(n, yaml.SequenceNode):
            stack += list(n.value)
    return out


def _files() -> list:
    return sorted(
        p
        for pattern in ("mechanisms/**/*.yaml", "tests/**/*.yaml", "src/**/*.yaml")
        for p in ROOT.glob(pattern)
    )


def test_every_yaml_file_of_the_repository_composes_the_same_both_ways():
    fast = 0
    for path in _files():
        try:
            text = path.read_text(encoding="utf-8")
        except UnicodeDecodeError:  # a broken file of tests/broken
            continue
        try:
            slow = yaml.compose(text, Loader=document._Loader)
        except (yaml.YAMLError, document._TooDeep):  # _TooMany is one too
            assert not document._compose_fast(text)[0], path  # refused: PyYAML says why
            continue
        ok, root = document._compose_fast(text)
        if slow is None:  # an empty file
            assert root is None, path
        elif ok:
            fast += 1
            assert _flat(root) == _flat(slow), path
    assert fast > 100  # the shipped mechanisms and most test files take libyaml's path


def _message(text: str, monkeypatch, libyaml: bool) -> str:
    with monkeypatch.context() as m:
        if not libyaml:
            m.setattr(document, "_CLoader", None)
        with pytest.raises(ks.ModelError) as info:
            ks.loads(text, file="t.yaml")
    return str(info.value)


@pytest.mark.parametrize(
    "text",
    [
        "name: x\nunits: {length: mm, ma?ss: kg}\nlinks: {}\n",  # libyaml accepts it
        "name: x\nunits: {length: mm, mass: , force: N}\nlinks: {}\n",  # a column later
        "name: x\nlinks:\n\tground: {}\n",  # a tab
        "name: x\nlinks: " + "[" * (MAX_DEPTH + 1) + "]" * (MAX_DEPTH + 1) + "\n",
        "name: x\nlinks: {a: 1, a: 2}\njoints: {}\n",  # a duplicate key
        "name: x\nlinks: [1, 2\n",  # a syntax error
    ],
)
def test_a_refusal_is_the_same_with_and_without_libyaml(text, monkeypatch):
    assert _message(text, monkeypatch, True) == _message(text, monkeypatch, False)


def test_a_chain_loads_the_same_with_and_without_libyaml(monkeypatch):
    text = dyad_chain(4)
    fast = ks.loads(text)
    monkeypatch.setattr(document, "_CLoader", None)
    slow = ks.loads(text)
    assert fast.sketch_where == slow.sketch_where
    assert [link.where for link in fast.links] == [link.where for link in slow.links]
    assert [j.where for j in fast.joints] == [j.where for j in slow.joints]


def test_reading_leaves_the_garbage_collector_as_it_was():
    text = dyad_chain(2)
    assert gc.isenabled()
    ks.loads(text)
    assert gc.isenabled()
    with pytest.raises(ks.ModelError):
        ks.loads(text.replace("mass: 2.0", "mass: -2.0"))
    assert gc.isenabled()
    gc.disable()
    try:
        ks.loads(text)
        assert not gc.isenabled()
    finally:
        gc.enable()


def test_path_resolvers_still_resolve_as_pyyaml_does():
    """Without path resolvers the composer's resolver calls are C callables (a tag by
    kind and text); a loader with one added resolves every tag as PyYAML does."""

    class WithPath(document._CLoader):
        pass

    yaml.add_path_resolver("!here", ["a"], yaml.ScalarNode, Loader=WithPath)
    text = "a: x\nb: y\n"
    for loader in (WithPath, document._CLoader):
        root = yaml.compose(text, Loader=loader)
        tags = {k.value: v.tag for k, v in root.value}
        here = "!here" if loader is WithPath else "tag:yaml.org,2002:str"
        assert tags == {"a": here, "b": "tag:yaml.org,2002:str"}
