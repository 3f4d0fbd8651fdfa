"""The verdict on a flat model (compiler/model/model_check.py reaches it): whether it runs on its
own, and if not, what `dyadc check` prints about it and the error `simulate` raises, with its
open connectors and inputs named."""
from __future__ import annotations

from dataclasses import dataclass

from compiler.errors import DyadError, Note


@dataclass(frozen=True)
class Verdict:
    """What the checks found: the counts, what is open, and why the model cannot run on its own
    (`reason`, None when it can)."""
    model: str
    equations: int
    unknowns: int
    open_connectors: tuple[str, ...] = ()     # physical connectors of the model itself
    open_inputs: tuple[str, ...] = ()         # its input signals
    declared_partial: bool = False
    component_equations: int = 0              # without the zero flows of its open connectors
    component_unknowns: int = 0               # without those flows and its inputs
    reason: DyadError | None = None           # why it cannot run on its own (None: it can)
    declared_external: bool = False           # `external component`: equations written in Julia
    julia_object_calls: tuple[str, ...] = ()  # functions of a medium (compiler/julia/objects.py)
    julia_object_span: object = None          # the first equation that calls one

    @property
    def is_partial(self) -> bool:
        return self.reason is not None

    @property
    def open_count(self) -> int:
        return len(self.open_connectors) + len(self.open_inputs)

    def open_list(self) -> str:
        return ", ".join(self.open_connectors + self.open_inputs)

    def describe(self) -> str:
        """One status line for `dyadc check`."""
        if not self.is_partial:
            return f"balanced: {self.equations} equations, {self.unknowns} unknowns" \
                + self._julia_object_note()
        opened = (f"{self.open_count} open connector{'s' if self.open_count != 1 else ''}"
                  + (f" ({self.open_list()})" if self.open_count else ""))
        if self.declared_external:
            return (f"external: interface only, {self.unknowns} unknowns and {opened}; its "
                    f"equations are implemented in Julia, so dyadc cannot simulate it")
        if self.component_equations == self.component_unknowns:
            state = "balanced as a component"
        else:
            state = (f"{self.component_equations} equations for {self.component_unknowns} unknowns "
                     f"as a component")
        declared = "declared partial, " if self.declared_partial else ""
        return f"partial: {declared}{state}, {opened}; it cannot be simulated on its own" \
            + self._julia_object_note()

    def _julia_object_note(self) -> str:
        if not self.julia_object_calls:
            return ""
        return (f"; dyadc cannot simulate it: {_calls(self.julia_object_calls)} of a Julia "
                f"object (a medium, a dataset, an interpolator), kept opaque for these checks")

    def julia_object_error(self) -> DyadError:
        return DyadError(f"`{self.model}` cannot be simulated by dyadc: it calls "
                         f"{_calls(self.julia_object_calls)} with a Julia object (a medium, a "
                         f"dataset, an interpolator) whose value dyadc cannot represent",
                         self.julia_object_span,
                         hint="`dyadc check` still checks its structure; a run needs Dyad's Julia "
                              "runtime, or a medium declared in the model (`path medium::M = "
                              "Struct(...)`) whose Julia struct and methods dyadc can read")

    def error(self) -> DyadError:
        """Why `simulate` refuses a partial model: what is open, and (as a note) what goes wrong
        when it is closed as it stands."""
        reason = self.reason
        opened = {1: f"its connector {self.open_list()} is left open"}.get(
            self.open_count, f"its {self.open_count} connectors {self.open_list()} are left open")
        if self.declared_external:
            return DyadError(f"`{self.model}` is an external component: its equations are "
                             f"implemented in Julia, which dyadc cannot run", reason.span,
                             hint="replace it by a component whose relations are written in Dyad")
        if self.declared_partial:
            head = f"`{self.model}` is declared partial: an incomplete component, it cannot be simulated"
            hint = "simulate a model that uses a component extending it"
        else:
            head = f"`{self.model}` is a partial model: it cannot be simulated on its own"
            hint = "simulate a model that uses it"
        if self.open_count:
            head += f"; {opened}"
            hint += f" and connects {self.open_list()}"
        if self.open_connectors:
            hint += " (e.g. to sources and a reference such as Ground or Fixed)"
        if self.open_inputs:
            hint += "; an input is driven by connecting it to an output (e.g. a Constant block)"
        notes = [Note(f"closed as it stands, {reason.message}", reason.span)]
        return DyadError(head, reason.span, hint=hint, notes=notes)


def _calls(names: tuple[str, ...]) -> str:
    shown = ", ".join(f"`{name}`" for name in names[:3])
    return ("function " if len(names) == 1 else "functions ") + shown \
        + (f" and {len(names) - 3} more" if len(names) > 3 else "")
