"""Client side, before anything runs: compile the model (once, or once per structural case with
`recompile`), put it on the code a `dyadc simulate` of it runs on (compiled C where a C compiler is
present, compiled_runs.model_for_runs), check every swept name against it, and pack what the
workers get: one payload per compiled model (with its C libraries) with the samples that run on it."""
from __future__ import annotations

from dataclasses import dataclass
from typing import Mapping, Sequence

from compiler.errors import DyadError, Note
from compiler.runtime import CompiledModel, did_you_mean
from compiler.sweep.design import Design
from compiler.sweep.recompile import Case, case_of, compile_case, describe
from compiler.sweep.worker import ModelPayload

Sample = tuple[int, dict[str, float]]


@dataclass
class Prepared:
    model: CompiledModel                       # the first compiled model (names, signals)
    parts: list[tuple[ModelPayload, list[Sample]]]
    structural: tuple[str, ...] = ()           # swept or fixed names compiled in per case
    compiled: int = 1                          # how many models were compiled
    cases: tuple = ((),)                       # the structural values of each part


def prepare(model, design: Design, lib_dirs: Sequence[str], recompile: bool) -> Prepared:
    compiled, flat_parameters, _ = compile_model(model, lib_dirs)
    names = list(design.names) + [n for n in design.fixed if n not in design.names]
    samples = [(i, design.sample(i)) for i in range(len(design))]
    structural = compiled_in(compiled, names, flat_parameters) if recompile else []
    if not structural:
        check_parameters(compiled, names, flat_parameters)
        return Prepared(compiled, [(payload_of(compiled), samples)])
    if not isinstance(model, str):
        raise DyadError(f"cannot recompile {compiled.name} for {', '.join(structural)}: it was given "
                        "compiled", hint="pass the model as a MODEL spec (a file or a qualified name)")
    runtime_names = [n for n in names if n not in structural]
    groups: dict[Case, list[Sample]] = {}
    for sample, params in samples:
        groups.setdefault(case_of(params, structural), []).append(
            (sample, {k: v for k, v in params.items() if k not in structural}))
    parts, first = [], None
    for case, members in groups.items():            # compiled once per distinct value
        case_compilation = compile_case(model, lib_dirs, case)
        case_model = on_its_code(case_compilation)
        try:
            check_parameters(case_model, runtime_names,
                             {p.name: p for p in case_compilation.flat.parameters})
        except DyadError as err:
            raise DyadError(f"with {describe(case)}: {err.message}", err.span, err.hint, err.notes) from None
        parts.append((payload_of(case_model), members))
        first = case_model if first is None else first
    return Prepared(first, parts, tuple(structural), len(parts), tuple(groups))


def compile_model(model, lib_dirs: Sequence[str]):
    """(the compiled model on its code, its flat parameters by name, the Compilation or None)."""
    from compiler.compiled_runs import model_on_its_code
    if isinstance(model, CompiledModel):
        return model_on_its_code(model), {}, None
    if isinstance(model, str):
        from compiler.pipeline import compile_spec
        model = compile_spec(model, lib_dirs)
    if not hasattr(model, "model") or not hasattr(model, "flat"):
        raise DyadError(f"cannot sweep a {type(model).__name__}",
                        hint="pass a MODEL spec, a Compilation (compiler.api.compile) or a CompiledModel")
    return on_its_code(model), {p.name: p for p in model.flat.parameters}, model


def on_its_code(compilation) -> CompiledModel:
    """The compilation's model on the code its `dyadc simulate` runs on: the same object, so the
    same C library and the same numbers (a CompiledModel given alone is put on the same code)."""
    from compiler.compiled_runs import model_for_runs
    return model_for_runs(compilation, None)


def payload_of(model: CompiledModel) -> ModelPayload:
    """The model as it travels. A model whose state set switches must carry its other state sets
    (CompiledModel.variants, built at compile time): a worker has no compiler to build them."""
    if model.state_sets and not model.variants:
        raise DyadError(f"cannot sweep {model.name}: its state set switches during the run, and its "
                        "compiled model does not carry its other state sets (the compiler builds them "
                        "ahead of time only up to a limit; beyond it `dyadc simulate` builds them "
                        "as the run reaches them, which a worker cannot)",
                        hint="simulate its cases one by one with `dyadc simulate -p NAME=VALUE`")
    return ModelPayload.of(model)


def compiled_in(model: CompiledModel, names: Sequence[str], flat_parameters: Mapping) -> list[str]:
    """The names that are parameters fixed when the model is compiled (not constants)."""
    tunable = dict(zip(model.parameter_names, model.parameter_tunable))
    return [n for n in names if not tunable.get(n) and n in flat_parameters
            and not flat_parameters[n].tunable and flat_parameters[n].variability != "constant"]


def check_parameters(model: CompiledModel, names: Sequence[str], flat_parameters: Mapping) -> None:
    """Refuse, naming them all, parameters that a compiled model cannot take as run-time inputs."""
    tunable = dict(zip(model.parameter_names, model.parameter_tunable))
    problems, notes, compile_time = [], [], False
    for name in names:
        if tunable.get(name):
            continue
        declared = flat_parameters.get(name)
        span = getattr(getattr(declared, "origin", None), "span", None)
        if declared is not None and declared.variability == "structural":
            problems.append(f"`{name}` is a structural parameter (it fixes array sizes or branches "
                            "and is compiled into the model)")
            compile_time = True
        elif name in tunable or (declared is not None and not declared.tunable):
            kind = declared.variability if declared is not None else "final"
            kind = "final" if kind == "parameter" else kind
            problems.append(f"`{name}` is {kind} and cannot be changed")
            compile_time = compile_time or kind != "constant"
        elif declared is not None:
            problems.append(f"`{name}` does not enter the compiled model (nothing it simulates depends "
                            "on it), so sweeping it would change nothing")
        else:
            problems.append(f"`{name}` is not a parameter of {model.name}"
                            + did_you_mean(name, model.parameter_names))
            continue
        if span is not None:
            notes.append(Note(f"`{name}` is declared here", span))
    if problems:
        hint = ("a sweep compiles the model once and changes only tunable parameters; "
                "`dyadc inspect MODEL` lists them")
        if compile_time:
            hint += ("; a parameter compiled into the model (an array size, a branch; not a final "
                     "one) can be swept by compiling once per value: --recompile (recompile=True)")
        raise DyadError("cannot sweep: " + "; ".join(problems), notes=notes, hint=hint)
