"""`dyadc fmu MODEL --output Model.fmu`: the model as an FMI 2.0 or 3.0 FMU, Model Exchange or
Co-Simulation (compiler/fmu/, docs/fmu.md)."""
from __future__ import annotations

import sys

from compiler.cli.arguments import add_lib_argument, add_params_argument, add_units_argument

FMU_HELP = "export a model as an FMU (FMI 2.0 or 3.0, Model Exchange or Co-Simulation) for other tools"


def add_fmu(sub) -> None:
    p = sub.add_parser("fmu", help=FMU_HELP, description=FMU_HELP + ". The FMU holds the compiled "
                       "binary for this platform and its C sources; it needs neither dyadc nor Python "
                       "to run. Free top-level inputs are its inputs, -p values the start values of "
                       "its parameters (docs/fmu.md).")
    p.add_argument("model", metavar="MODEL", help="file path or qualified name")
    add_lib_argument(p)
    add_units_argument(p)
    p.add_argument("-o", "--output", required=True, metavar="FILE.fmu", help="the FMU to write")
    p.add_argument("--fmi", type=int, default=2, metavar="VERSION", help="the FMI version: 2 (default) or 3")
    p.add_argument("--kind", default="me", metavar="KIND",
                   help="me: Model Exchange (the importer integrates; default); cs: Co-Simulation (the FMU "
                        "integrates itself, TR-BDF2 at the experiment's tolerance)")
    add_params_argument(p, "the start value of a parameter (repeatable)")
    p.add_argument("--stop", type=float, metavar="T", help="the stop time of the FMU's default experiment")
    p.set_defaults(run=run_fmu)


ADDERS = {"fmu": add_fmu}


def run_fmu(args) -> int:
    from compiler.cli import options
    from compiler.fmu.export import check_request, export_fmu
    from compiler.units.mode import units_mode

    check_request(args.fmi, args.kind)
    if args.stop is not None:
        options.check_finite("--stop", args.stop)
    overrides = [options.parse_override(text) for text in args.params]
    with units_mode(args.units):
        written = export_fmu(args.model, args.output, lib_dirs=args.lib, fmi=args.fmi, kind=args.kind,
                             stop_time=args.stop,
                             convert_params=lambda known, units: options.convert_overrides(overrides, known, units))
    print(f"wrote {written}", file=sys.stderr)
    return 0
