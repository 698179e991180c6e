"""The ``units:`` and ``parameters:`` sections: unit factors and parameter values, read
before any other number of the file."""

from __future__ import annotations

import yaml

from ..base import expressions, units
from ..base.spec import Entry, describe_node, expression_message, name_problem
from ..errors import Location, did_you_mean


class ParameterSections:
    """Reads ``units:`` and ``parameters:`` into the context.

    A mixin of :class:`~kinetostatics.io.builder.Builder`: it uses the builder's ``top``, ``ctx``,
    ``problems`` and name bookkeeping (``_claim``, ``_broken``, ``_not_a``).
    """

    def _units(self) -> dict[str, str]:
        spec: dict[str, str] = {}
        u = self.top.get("units")
        if u is None or not u.mapping():
            return spec
        for kind, e in u.items():
            if kind not in units.QUANTITY_KINDS:
                self.problems.add(
                    u.key_where(kind),
                    f"unknown quantity kind '{kind}'"
                    f"{did_you_mean(kind, units.QUANTITY_KINDS)}; "
                    f"known: {', '.join(units.QUANTITY_KINDS)}",
                )
                continue
            unit = e.text()
            if unit is None:
                continue
            try:
                self.ctx.units[kind] = units.factor(kind, unit)
            except units.UnitError as exc:
                e.error(str(exc))
                continue
            spec[kind] = self.ctx.unit_names[kind] = unit
        return spec

    def _parameters(self) -> None:
        """Evaluate the parameters in dependency order, each problem reported at its
        parameter; a parameter that uses a broken one is skipped silently."""
        p = self.top.get("parameters")
        overrides = self.ctx.overrides
        self.parameter_texts: dict[str, str] = {}
        if p is None or not p.mapping():
            if overrides:
                self._unknown_overrides([])
            return
        broken = self.ctx.broken_parameters
        declared = p.keys()
        self._unknown_overrides(declared)
        pending: dict[str, tuple[Entry, str, list[str]]] = {}
        for key, e in p.items():
            where = p.key_where(key)
            if problem := name_problem("parameter", key, expression=True):
                self.problems.add(where, problem)
            elif key in expressions.FUNCTIONS:
                self.problems.add(
                    where, f"'{key}' is the name of a function; choose another parameter name"
                )
            elif not isinstance(e.node, yaml.ScalarNode) or e.node.value == "":
                e.error(f"expected a number or an expression, got {describe_node(e.node)}")
            else:
                try:
                    used = sorted(expressions.names_in(e.node.value))
                except expressions.ExpressionError as exc:
                    e.error(expression_message(exc))
                else:
                    if key in overrides:  # a number: evaluated as such, nothing to parse
                        pending[key] = (e, float(overrides[key]), [])
                        continue
                    pending[key] = (e, e.node.value, [n for n in used if n in declared])
                    self.parameter_texts[key] = e.node.value
                    undefined = [
                        n for n in used if n not in declared and n not in expressions.CONSTANTS
                    ]
                    if not undefined:
                        continue
                    others = [k for k in declared if k != key]
                    e.error(
                        f"undefined parameter '{undefined[0]}'{did_you_mean(undefined[0], others)}"
                    )
                    del pending[key]
            broken.add(key)
        env: dict[str, float] = {}
        progress = True
        while pending and progress:
            progress = False
            for key, (e, text, deps) in list(pending.items()):
                if any(d in broken for d in deps):
                    broken.add(key)  # silent: the cause is reported
                elif all(d in env for d in deps):
                    try:
                        env[key] = expressions.evaluate(text, env)
                    except expressions.ExpressionError as exc:
                        e.error(expression_message(exc))
                        broken.add(key)
                else:
                    continue
                del pending[key]
                progress = True
        reported: set[str] = set()
        for key in list(pending):  # what is left depends on a cycle
            if key in reported:
                continue
            path, node = [key], key
            while True:
                node = next(d for d in pending[node][2] if d in pending)
                if node in path:
                    cycle = path[path.index(node) :] + [node]
                    break
                path.append(node)
            if not reported & set(cycle):
                pending[cycle[0]][0].error(f"the parameters form a cycle: {' -> '.join(cycle)}")
            reported |= set(cycle)
        broken |= set(pending)
        self.ctx.env.update((k, env[k]) for k in declared if k in env)

    def _unknown_overrides(self, declared: list[str]) -> None:
        for key in self.ctx.overrides:
            if key not in declared:
                known = ", ".join(declared) or "none"
                self.problems.add(
                    Location(self.ctx.file, path="parameters"),
                    f"a variant sets the parameter '{key}', which the file does not "
                    f"declare{did_you_mean(key, declared)}; its parameters: {known}",
                )
