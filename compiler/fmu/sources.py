"""The C sources of an FMU: the model's functions written by CasADi's CodeGenerator
(dyfmu_functions.c/.h), the tables of the model (dyfmu_model.h), and dyadc's own runtime shipped
beside this module: one core (fmu_model.c and what it includes, fmu_numerics.c) and the FMI
version's functions that wrap it (fmi2_functions.c or fmi3_functions.c).

Every output is dense (CasADi writes only the structural nonzeros of a sparse one), and the
Jacobians the FMU needs are exact: the algebraic Newton step, the initialization system's, and
the eliminated Jacobians of compiler/linear/elimination.py for the directional derivatives.
"""
from __future__ import annotations

import os
import tempfile
from dataclasses import dataclass
from pathlib import Path

import casadi as ca

from compiler.fmu.layout import FmuLayout
from compiler.linear.elimination import EliminatedSystem
from compiler.runtime import CompiledModel
from compiler.runtime.checks import bound_indicators

FUNCTIONS_NAME = "dyfmu_functions"
CORE_FILES = ("fmu_instance.h", "fmu_core.h", "fmu_numerics.c", "fmu_model.c", "fmu_values.inc", "fmu_state.inc",
              "fmu_cosimulation.inc")
_OPERATORS = {">": 0, ">=": 1, "<": 2, "<=": 3}


@dataclass(frozen=True)
class CSources:
    """File name -> text, and the names of the files to compile."""
    files: dict[str, str]
    compiled: tuple[str, ...]


def runtime_files(fmi: int) -> tuple[tuple[str, ...], tuple[str, ...]]:
    """(the runtime's files, those of them compiled) for FMI version `fmi`."""
    wrapper = f"fmi{fmi}_functions.c"
    return CORE_FILES + (f"fmi{fmi}_api.h", wrapper), ("fmu_numerics.c", "fmu_model.c", wrapper)


def _dense(function_name: str, inputs: list, outputs: list) -> ca.Function:
    return ca.Function(function_name, inputs, [ca.densify(o) for o in outputs])


def model_functions(model: CompiledModel, layout: FmuLayout) -> list[ca.Function]:
    """The functions the C runtime calls, under the names dyfmu_model.h binds."""
    x, z, p, t = model.symbols()
    ode, alg = model.dae(x, z, p, t)
    user, mask = ca.SX.sym("p_user", len(model.parameter_names)), ca.SX.sym("mask", len(model.parameter_names))
    residuals = model.init(x, z, p, t)
    eliminated = EliminatedSystem(model, layout.input_parameters, layout.output_names).function()
    functions = [
        _dense("dyfmu_params", [user, mask], [model.params(user, mask)]),
        _dense("dyfmu_init", [x, z, p, t], [residuals, ca.jacobian(residuals, ca.vertcat(x, z))]),
        _dense("dyfmu_dae", [x, z, p, t], [ode, alg]),
        _dense("dyfmu_newton", [x, z, p, t], [alg, ca.jacobian(alg, z)]),
        _dense("dyfmu_outputs", [x, z, p, t], [model.outputs(x, z, p, t)]),
        _dense("dyfmu_eliminated", [x, z, p, t], list(eliminated(x, z, p, t))),
    ]
    if layout.event_count:
        functions.append(_dense("dyfmu_events", [x, z, p, t], [model.events(x, z, p, t)]))
    if layout.time_event_count:
        functions.append(_dense("dyfmu_time_events", [p], list(model.time_events(p))))
    rows, labels = bound_indicators(model, model.outputs(x, z, p, t))
    if labels:
        functions.append(_dense("dyfmu_bounds", [x, z, p, t], [rows]))
    return functions


def _string_array(name: str, values) -> str:
    text = ", ".join('"' + v.replace("\\", "\\\\").replace('"', '\\"') + '"' for v in values) or '""'
    return f"static const char *const {name}[] = {{{text}}};"


def bound_tables(model: CompiledModel) -> list[str]:
    """The declared min/max the FMU checks (compiler/runtime/checks.py's indicators, in their
    order): each bound's variable, output row, kind (0 min, 1 max) and value."""
    labels = bound_indicators(model, model.outputs(*model.symbols()))[1]
    return [f"#define DY_NBOUND {len(labels)}",
            _string_array("DY_BOUND_NAME", [name for name, _, _ in labels]),
            _array("int", "DY_BOUND_ROW", [model.output_index(name) for name, _, _ in labels]),
            _array("int", "DY_BOUND_KIND", [int(key == "max") for _, key, _ in labels]),
            _array("double", "DY_BOUND_VALUE", [bound for _, _, bound in labels])]


def generated_functions(functions: list[ca.Function]) -> dict[str, str]:
    generator = ca.CodeGenerator(FUNCTIONS_NAME, {"with_header": True})
    for function in functions:
        generator.add(function)
    with tempfile.TemporaryDirectory(prefix="dyadc-fmu-") as tmp:
        generator.generate(tmp + os.sep)
        return {name: (Path(tmp) / name).read_text(encoding="utf-8")
                for name in (FUNCTIONS_NAME + ".c", FUNCTIONS_NAME + ".h")}


def _array(c_type: str, name: str, values) -> str:
    values = list(values)
    text = ", ".join(repr(float(v)) if c_type == "double" else str(int(v)) for v in values) or "0"
    return f"static const {c_type} {name}[] = {{{text}}};"


def model_header(model: CompiledModel, layout: FmuLayout, functions: list[ca.Function], guid: str) -> str:
    """dyfmu_model.h: sizes, default parameters (the -p values applied), guesses, the relation
    locks, which parameters are settable, and the functions by role."""
    names = [f.name() for f in functions]
    locks = model.metadata.get("relation_locks") or []
    index = {n: i for i, n in enumerate(model.parameter_names)}
    clock = model.metadata.get("event_clock")
    input_of = [-1] * len(model.parameter_names)
    for k, i in enumerate(layout.input_parameters):
        input_of[i] = k
    output_of = [-1] * len(model.output_names)
    for k, name in enumerate(layout.output_names):
        output_of[model.output_index(name)] = k
    lines = [
        "/* The model's tables, written by dyadc (compiler/fmu/sources.py). */",
        f'#include "{FUNCTIONS_NAME}.h"',
        f'#define DY_GUID "{guid}"',
        *(f"#define DY_{key} {value}" for key, value in (
            ("NX", len(model.state_names)), ("NZ", len(model.algebraic_names)),
            ("NP", len(model.parameter_names)), ("NY", len(model.output_names)),
            ("NEV", layout.event_count), ("NTE", layout.time_event_count), ("NLOCK", len(locks)),
            ("NU", len(layout.input_parameters)), ("NOUT", len(layout.output_names)),
            ("NINIT", model.init.size1_out(0)), ("CLOCK", index[clock] if clock else -1))),
        _array("double", "DY_P_DEFAULT", layout.parameter_start),
        _array("double", "DY_P_MASK", layout.parameter_mask),
        _array("double", "DY_X_GUESS", model.x_guess),
        _array("double", "DY_Z_GUESS", model.z_guess),
        _array("int", "DY_LOCK_PARAM", [index[lock["parameter"]] for lock in locks]),
        _array("int", "DY_LOCK_ROW", [lock["row"] for lock in locks]),
        _array("int", "DY_LOCK_SIGN", [lock["sign"] for lock in locks]),
        _array("int", "DY_LOCK_OP", [_OPERATORS[lock["operator"]] for lock in locks]),
        _array("int", "DY_SETTABLE", layout.settable),
        _array("int", "DY_INPUT_OF_PARAMETER", input_of),
        _array("int", "DY_OUTPUT_OF_ROW", output_of),
        *bound_tables(model),
        *(f"#define DY_{n[len('dyfmu_'):].upper()} {n}" for n in names),
        "static dy_work DY_WORKS[] = {" + ", ".join(f"(dy_work){n}_work" for n in names) + "};",
    ]
    return "\n".join(lines) + "\n"


def fmu_sources(model: CompiledModel, layout: FmuLayout, guid: str, fmi: int) -> CSources:
    functions = model_functions(model, layout)
    files = generated_functions(functions)
    files["dyfmu_model.h"] = model_header(model, layout, functions, guid)
    here = Path(__file__).resolve().parent
    shipped, compiled = runtime_files(fmi)
    for name in shipped:
        files[name] = (here / name).read_text(encoding="utf-8")
    return CSources(files, (FUNCTIONS_NAME + ".c", *compiled))
