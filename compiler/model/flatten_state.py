"""What flattening gathers while it walks the instance tree (compiler/model/flatten.py): equations,
initial equations, guesses, starts, priorities, units, bounds, connections, visual components and
warnings, with the scalar helpers the flattening modules share."""
from __future__ import annotations

from typing import Any

from compiler.errors import DyadError
from compiler.model.expressions import is_array
from compiler.model.flat import Equation
from compiler.model.flatten_connect import ConnectionGraph
from compiler.model.instantiate import Instance, Model, VariableInstance


def scalars(value: Any) -> list[Any]:
    return value.ravel().tolist() if is_array(value) else [value]


def to_float(value: Any) -> float | None:
    try:
        return float(value)
    except (TypeError, ValueError):
        return None


def owner_of(variable: VariableInstance) -> Instance:
    """The component a variable belongs to (a connector's field belongs to its owner)."""
    node = variable.node
    return node.parent if node.kind == "connector" and node.parent is not None else node


class FlattenState:
    """The flat system under construction, for one instantiated model."""

    def __init__(self, model: Model):
        self.model = model
        self.root: Instance = model.root
        self.equations: list[Equation] = []
        self.initial: list[Equation] = []
        self.guesses: dict[str, float] = {}
        self.starts: dict[str, float] = {}
        self.priorities: dict[str, int] = {}
        self.units: dict[str, str] = {}
        self.bounds: dict[str, dict[str, float]] = {}
        self.graph = ConnectionGraph()
        self.visual: dict[str, dict] = {}
        self.warnings: list[str] = []
        self.strings: dict[str, str] = {}
        self._parameter_values: dict[str, Any] | None = None

    def numeric_or_none(self, value: Any) -> float | None:
        """A start value from a symbolic expression in parameters, if every one has a value."""
        if not getattr(value, "free_symbols", None):
            return to_float(value)
        substitutions = {}
        for sym in value.free_symbols:
            number = self.parameter_value(sym.name)
            if number is None:
                return None
            substitutions[sym] = number
        return to_float(value.xreplace(substitutions))

    def parameter_value(self, name: str) -> Any:
        """The value of tunable scalar parameter `name`, None when it has none."""
        if self._parameter_values is None:
            self._parameter_values = {}
            for node in self.root.walk():
                for parameter in node.parameters.values():
                    if parameter.is_string or parameter.fixed_at_compile_time:
                        continue
                    try:
                        value = parameter.value()
                    except DyadError:
                        continue
                    if value is None:
                        continue
                    for flat_name, number in zip(parameter.flat_names(), scalars(value)):
                        self._parameter_values[flat_name] = number
        return self._parameter_values.get(name)
