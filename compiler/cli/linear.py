"""`dyadc linearize MODEL`: the linear model at an operating point (compiler/linear/), written to
--output (.json, .mat, .npz) and summarized on the terminal (poles, DC gain, transfer functions of
a small system)."""
from __future__ import annotations

import sys

from compiler.cli.arguments import add_lib_argument, add_params_argument, add_units_argument

LINEARIZE_HELP = "linearize a model at an operating point: (A, B, C, D) from inputs to outputs"
CLOSED_LOOP = ("sensitivity", "comp_sensitivity", "loop_transfer")


def add_linearize(sub) -> None:
    p = sub.add_parser("linearize", help=LINEARIZE_HELP, description=LINEARIZE_HELP + ". Inputs are "
                       "free top-level inputs and analysis points (NAME: analysis_point(out, in)); "
                       "outputs any variable or analysis point. The algebraic unknowns are "
                       "eliminated exactly through the Jacobians (docs/analysis.md).")
    p.add_argument("model", metavar="MODEL", help="file path or qualified name")
    add_lib_argument(p)
    add_units_argument(p)
    p.add_argument("--inputs", nargs="+", default=[], metavar="NAME",
                   help="free inputs or analysis points (default: every free top-level input)")
    p.add_argument("--outputs", nargs="+", default=[], metavar="NAME",
                   help="variables or analysis points (default: the top-level outputs, else the states)")
    where = p.add_mutually_exclusive_group()
    where.add_argument("--at", type=float, metavar="T", help="linearize at the state of a run at time T "
                       "(default: the consistent initial point)")
    where.add_argument("--steady", action="store_true",
                       help="linearize at a steady state found by Newton from the initial point")
    p.add_argument("--op", action="append", default=[], metavar="NAME=VALUE",
                   help="the value of an input at the operating point (default 0; repeatable)")
    add_params_argument(p, "override a parameter (repeatable)")
    p.add_argument("--open", nargs="+", default=[], metavar="NAME",
                   help="analysis points whose connection is removed")
    closed = p.add_mutually_exclusive_group()
    closed.add_argument("--sensitivity", metavar="P", help="the sensitivity function S at analysis point P")
    closed.add_argument("--comp-sensitivity", metavar="P",
                        help="the complementary sensitivity T = I - S at analysis point P")
    closed.add_argument("--loop-transfer", metavar="P",
                        help="the loop transfer L at analysis point P (S = (I + L)^-1)")
    p.add_argument("--minimal", action="store_true", help="a minimal realization")
    p.add_argument("--output", metavar="FILE", help="write the linear model: .json, .mat or .npz")
    p.add_argument("--plot", metavar="FILE.png", help="a Bode plot of every input-output pair")
    p.set_defaults(run=run_linearize)


ADDERS = {"linearize": add_linearize}


def run_linearize(args) -> int:
    from compiler.cli import options
    from compiler.errors import DyadError
    from compiler.linear.files import FORMATS, summary, write

    if args.output and not args.output.lower().endswith(FORMATS):
        raise DyadError(f"--output {args.output}: a linear model is written as {', '.join(FORMATS)}",
                        hint=f"e.g. --output {args.output.rsplit('.', 1)[0]}.json")
    if args.output and args.output.lower().endswith(".mat"):
        import importlib.util
        if importlib.util.find_spec("scipy") is None:
            raise DyadError("writing .mat needs scipy: pip install 'dyadc[io]' (or pip install scipy)",
                            hint=f"or write .json or .npz: --output {args.output[:-4]}.json")
    if args.plot and not args.plot.lower().endswith(".png"):
        raise DyadError(f"--plot {args.plot}: the plot is written as .png", hint="e.g. --plot bode.png")
    if args.at is not None:
        options.check_finite("--at", args.at)
    point = next(((kind, getattr(args, kind)) for kind in CLOSED_LOOP if getattr(args, kind)), None)
    if point is not None and (args.inputs or args.outputs):
        raise DyadError(f"--{point[0].replace('_', '-')} gives its own input and output: leave out "
                        f"--inputs and --outputs")
    overrides = [options.parse_override(text) for text in args.params]
    op = {o.name: o.value for o in map(options.parse_override, args.op)}
    system = _linearized(args, point, lambda known, units: options.convert_overrides(overrides, known, units), op)
    print(summary(system))
    if args.output:
        write(system, args.output)
        print(f"wrote {args.output}", file=sys.stderr)
    if args.plot:
        from compiler.linear.plots import bode_plot, frequency_grid
        curves = [(system.select([j], [i]).to_control(), f"{o} / {u}")
                  for i, o in enumerate(system.outputs) for j, u in enumerate(system.inputs)]
        bode_plot(curves, frequency_grid([system]), args.plot, "Bode plot of the linear model")
        print(f"wrote {args.plot}", file=sys.stderr)
    return 0


def _linearized(args, point, convert_params, op):
    from compiler.linear.elimination import AlgebraicSolveFailed
    from compiler.linear.operating_point import SteadyStateFailed
    from compiler.linear.request import Request, closed_loop_function, linearize_spec
    from compiler.errors import DyadError
    request = Request(inputs=tuple(args.inputs), outputs=tuple(args.outputs), at=args.at,
                      steady=args.steady, op=op, opened=tuple(args.open), minimal=args.minimal,
                      convert_params=convert_params)
    try:
        if point is not None:
            return closed_loop_function(args.model, point[0], point[1], request, args.lib)
        return linearize_spec(args.model, request, args.lib)
    except (AlgebraicSolveFailed, SteadyStateFailed) as err:
        raise DyadError(f"cannot linearize {args.model}: {err}",
                        hint="try another operating point (--at T) or give the inputs' values "
                             "there (--op NAME=VALUE)") from None
