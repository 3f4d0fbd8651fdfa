"""Connector sets without a reference: potentials that only occur as differences.

A circuit without a ground determines every voltage only up to a common constant: the equations
count and match, yet the Jacobian is singular, and the structure stage can only report some
equation that became `0 = 0`. The test here is exact: if shifting the potential `v` of a cluster
of connectors by the same constant leaves every equation unchanged (the sum of the partial
derivatives by those potentials is identically zero), the shift direction is a null vector of the
Jacobian, so the model is singular, whatever the parameter values. A potential that is also
differentiated (a mass's position) is a state whose initial value fixes the constant: skipped.

A cluster is one (connector type, potential field) linked through shared equations: connect
equations join sets, component equations such as `v = p.v - n.v` join a component's pins.
"""
from __future__ import annotations

from dataclasses import dataclass

import sympy

from compiler.model.flat import FlatSystem

# The reference component users know for each connector type of the shipped library.
REFERENCES = {
    "Pin": "`Ground` (fixes v = 0)",
    "Flange": "`Fixed` (fixes the position s)",
    "Spline": "`Fixed` (fixes the angle phi)",
    "Frame2D": "`Fixed` or `World` (fixes x, y and phi)",
    "HydraulicPort": "a pressure source such as `PressureSource` (fixes p)",
    "HeatPort": "`FixedTemperature` (fixes T)",
    "Node": "`FixedTemperature` (fixes T)",
}


@dataclass(frozen=True)
class FloatingCluster:
    connector_type: str
    field: str
    connect_sets: tuple[tuple[str, ...], ...]    # connector paths, one tuple per connect set
    span_text: str | None                        # where the first of its sets is connected

    def reference(self) -> str:
        return REFERENCES.get(self.connector_type, "a reference component (like `Ground` or "
                              f"`Fixed`) that fixes `{self.field}`")


class _UnionFind:
    def __init__(self, items):
        self.parent = {item: item for item in items}

    def find(self, item):
        while self.parent[item] != item:
            self.parent[item] = self.parent[self.parent[item]]
            item = self.parent[item]
        return item

    def union(self, a, b):
        ra, rb = self.find(a), self.find(b)
        if ra != rb:
            self.parent[rb] = ra


def floating_clusters(flat: FlatSystem) -> list[FloatingCluster]:
    connectors = flat.metadata.get("connectors") or {}
    domains: dict[tuple[str, str, int], dict[str, str]] = {}    # key -> {potential name: connector}
    for path, info in connectors.items():
        for field_name, names in info["potentials"].items():
            for k, name in enumerate(names):
                domains.setdefault((info["type"], field_name, k), {})[name] = path
    if not domains:
        return []
    symbols_of = [{s.name for s in e.residual.free_symbols} for e in flat.equations]
    equations_with: dict[str, list[int]] = {}
    for e, names in enumerate(symbols_of):
        for name in names:
            equations_with.setdefault(name, []).append(e)
    differentiated = set(flat.derivatives.values())
    found = []
    for (type_name, field_name, _), owner in sorted(domains.items()):
        links = _UnionFind(owner)
        for name in owner:
            for e in equations_with.get(name, ()):
                for other in symbols_of[e]:
                    if other in owner:
                        links.union(name, other)
        clusters: dict[str, list[str]] = {}
        for name in owner:
            clusters.setdefault(links.find(name), []).append(name)
        for names in clusters.values():
            if differentiated.intersection(names) or not _shift_invariant(flat, names, equations_with):
                continue
            found.append(_describe(flat, type_name, field_name, names, owner))
    return found


def _shift_invariant(flat: FlatSystem, names: list[str], equations_with: dict[str, list[int]]) -> bool:
    members = set(names)
    touched = sorted({e for n in names for e in equations_with.get(n, ())})
    if not touched:
        return False                 # occurs nowhere: the matching reports it, not this check
    # An equation with one of them alone (a ground, `g.v = 0`) breaks invariance: try those first.
    touched.sort(key=lambda e: sum(1 for s in flat.equations[e].residual.free_symbols if s.name in members))
    for e in touched:
        residual = flat.equations[e].residual
        change = sympy.Add(*[residual.diff(s) for s in residual.free_symbols if s.name in members])
        if change != 0 and sympy.expand(change) != 0:
            return False
    return True


def _describe(flat: FlatSystem, type_name: str, field_name: str, names: list[str],
              owner: dict[str, str]) -> FloatingCluster:
    """Group the cluster's connectors by connect set (potential equalities written by `connect`)."""
    paths = sorted({owner[n] for n in names}, key=list(dict.fromkeys(owner.values())).index)
    sets = _UnionFind(paths)
    member_names = set(names)
    first_span = None
    for equation in flat.equations:
        if equation.kind != "connect":
            continue
        inside = [owner[s.name] for s in equation.residual.free_symbols if s.name in member_names]
        if len(inside) == 2:
            sets.union(inside[0], inside[1])
            if first_span is None and equation.origin.span is not None:
                span = equation.origin.span
                first_span = f"{span.file}:{span.line}:{span.column}"
    groups: dict[str, list[str]] = {}
    for path in paths:
        groups.setdefault(sets.find(path), []).append(path)
    return FloatingCluster(type_name, field_name, tuple(tuple(g) for g in groups.values()),
                           first_span)
