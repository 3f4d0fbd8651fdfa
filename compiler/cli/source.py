"""`dyadc` commands that read a model and print or write what a stage made of it: parse, fmt,
check, flatten, inspect, compile."""
from __future__ import annotations

import os
import sys
from pathlib import Path

from compiler.cli.arguments import add_model_arguments


def add_parse(sub) -> None:
    p = sub.add_parser("parse", help="parse a .dyad file and print its definitions")
    p.add_argument("file", metavar="FILE")
    p.set_defaults(run=run_parse)


def add_fmt(sub) -> None:
    p = sub.add_parser("fmt", help="reprint a .dyad file in canonical form")
    p.add_argument("file", metavar="FILE")
    p.add_argument("--write", "-w", action="store_true", help="rewrite the file in place")
    p.set_defaults(run=run_fmt)


def add_check(sub) -> None:
    p = sub.add_parser("check", help="flatten a model (or every model under a directory) and check balance")
    add_model_arguments(p)
    p.set_defaults(run=run_check)


def add_flatten(sub) -> None:
    p = sub.add_parser("flatten", help="print the flat equations with their origins")
    add_model_arguments(p)
    p.set_defaults(run=run_flatten)


def add_inspect(sub) -> None:
    p = sub.add_parser("inspect", help="print every pass of the structural analysis")
    add_model_arguments(p)
    p.add_argument("--stop", type=float, metavar="T",
                   help="also simulate to T and list the state-set switches and events of the run")
    p.add_argument("--rtol", type=float, default=1e-6, help="relative tolerance of that run (default 1e-6)")
    p.set_defaults(run=run_inspect)


def add_compile(sub) -> None:
    p = sub.add_parser("compile", help="write a Python module for a model")
    add_model_arguments(p)
    p.add_argument("-o", "--output-dir", default="generated", metavar="DIR")
    p.add_argument("--name", help="module name (default: the qualified model name in snake_case, "
                                  "packages joined by `__`, e.g. component_tests__pendulum)")
    p.add_argument("--standalone", action="store_true",
                   help="copy the runtime package beside the module (then it needs only casadi and numpy)")
    p.add_argument("--codegen", choices=["c", "vm"],
                   help="the code the module runs on, as for `dyadc simulate`: c (the model's compiled C "
                        "libraries written beside the module) or vm (CasADi's virtual machine); default: "
                        "c where a C compiler is present ($DYADC_CODEGEN may say otherwise)")
    p.set_defaults(run=run_compile)


ADDERS = {"parse": add_parse, "fmt": add_fmt, "check": add_check, "flatten": add_flatten,
          "inspect": add_inspect, "compile": add_compile}


# ----------------------------------------------------------------------------------------- commands

def run_parse(args) -> int:
    from compiler.syntax.parser import parse_file, summarize
    print(summarize(parse_file(args.file)))
    return 0


def run_fmt(args) -> int:
    from compiler.syntax.format_comments import format_source
    from compiler.syntax.parser import read_source
    text = format_source(read_source(args.file), args.file)
    if args.write:
        Path(args.file).write_text(text, encoding="utf-8")
    else:
        sys.stdout.write(text)
    return 0


def run_check(args) -> int:
    from compiler.model.flatten import check_library, flatten_model, summarize
    from compiler.model.model_check import check_model
    if os.path.isdir(args.model):
        problems = check_library(args.model)
        for line in problems:
            print(line)
        return 1 if any("error" in line for line in problems) else 0
    flat = flatten_model(args.model, args.lib)
    verdict = check_model(flat)      # the same checks as `simulate` runs before compiling
    print(summarize(flat, verdict))
    return 0


def run_flatten(args) -> int:
    from compiler.model.flatten import flatten_model, format_flat
    print(format_flat(flatten_model(args.model, args.lib)))
    return 0


def run_inspect(args) -> int:
    from compiler.cli.inspect_report import format_report, format_switch_log
    from compiler.pipeline import compile_spec
    compilation = compile_spec(args.model, args.lib)
    print(format_report(compilation))
    if args.stop is not None:
        from compiler import api
        from compiler.runtime.options import SimulationOptions
        SimulationOptions(stop=args.stop, rtol=args.rtol, atol=args.rtol).validated()   # clear errors first
        print()
        print(format_switch_log(api.simulate_compiled(compilation, args.stop, rtol=args.rtol,
                                                      atol=args.rtol, progress=False)))
    return 0


def run_compile(args) -> int:
    from compiler.cli.outputs import check_output_folder
    from compiler.compiled_runs import model_for_runs
    from compiler.lower.codegen import write_module
    from compiler.lower.generate import module_name
    from compiler.pipeline import compile_spec
    check_output_folder(args.output_dir, "-o")      # before the compile it would otherwise waste
    compilation = compile_spec(args.model, args.lib)
    name = args.name or module_name(compilation.model.name)
    # on the code `dyadc simulate` runs it on, so that the module's runs take the same path
    model = model_for_runs(compilation, args.codegen)
    path = write_module(model, name, args.output_dir, standalone=args.standalone)
    print(f"wrote {path}")
    return 0
