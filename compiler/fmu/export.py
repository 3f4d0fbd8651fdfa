"""`dyadc fmu` / `compiler.api.export_fmu`: a model compiled into an FMI 2.0 or 3.0 FMU, Model
Exchange (the importer integrates) or Co-Simulation (the FMU integrates itself: fmu_cosimulation.inc).

The model is compiled with its free top-level inputs made parameters (the FMU's inputs,
compiler/linear/inputs.py); its C sources (sources.py) are compiled by gcc into the FMU's binary
for this platform and zipped with the sources and modelDescription.xml (description.py for FMI
2.0, description3.py for 3.0). A model
whose state set switches during a run is refused: the FMU integrates one state set.
"""
from __future__ import annotations

import re
import subprocess
import tempfile
import uuid
import zipfile
from pathlib import Path
from typing import Callable, Mapping, Sequence

from compiler.errors import DyadError
from compiler.fmu import description, description3
from compiler.fmu.layout import fmu_layout
from compiler.fmu.sources import CSources, fmu_sources
from compiler.fmu.variables import ModelInfo
from compiler.runtime import ModelInputError
from compiler.runtime.native_build import find_compiler

FMI_VERSIONS = (2, 3)
KINDS = ("me", "cs")
PLATFORMS = {2: "linux64", 3: "x86_64-linux"}     # the binaries' folder, as each FMI version names it
DESCRIBERS = {2: description.model_description, 3: description3.model_description}
FLAGS = ["-O1", "-fPIC", "-shared", "-fvisibility=hidden"]
COMPILE_TIMEOUT = 600


def check_request(fmi: int, kind: str) -> None:
    """Refuse what is not built: FMI versions other than 2.0 and 3.0, kinds other than me and cs."""
    if fmi not in FMI_VERSIONS:
        raise DyadError(f"--fmi {fmi}: dyadc exports FMI 2.0 and 3.0 (FMI {fmi} is not an FMI version it writes)",
                        hint="give --fmi 2 or --fmi 3")
    if kind not in KINDS:
        raise DyadError(f"--kind {kind}: an FMU is `me` (Model Exchange: the importer integrates) or "
                        f"`cs` (Co-Simulation: the FMU integrates itself)", hint="give --kind me or --kind cs")


def export_fmu(model_spec: str, output: str | Path, *, lib_dirs: Sequence[str] = (),
               params: Mapping[str, float] | None = None, fmi: int = 2, kind: str = "me",
               stop_time: float | None = None,
               convert_params: Callable[[Mapping[str, float], Mapping[str, str]], dict] | None = None) -> Path:
    """Write the FMU of `model_spec` to `output` (a .fmu file) and return its path. `params`:
    start values of parameters (the FMU's importer may set them again); `convert_params`:
    (parameters, their declared units) -> params, the command line's `-p L=100mm`."""
    check_request(fmi, kind)
    output = Path(output)
    if output.suffix.lower() != ".fmu":
        raise DyadError(f"--output {output}: an FMU is written as a .fmu file",
                        hint=f"e.g. --output {output.with_suffix('.fmu')}")
    compilation, inputs = _compile(model_spec, lib_dirs)
    model = compilation.model
    _refuse_switching(compilation)
    flat = compilation.flat
    from compiler.model.flat import OUTPUT
    outputs = [v.name for v in flat.variables if v.kind == OUTPUT and v.name in model.output_names]
    if convert_params is not None:
        params = convert_params(model.parameters, model.metadata.get("units", {}))
    try:
        layout = fmu_layout(model, inputs, outputs, dict(params or {}))
    except ModelInputError as err:
        raise DyadError(f"-p: {err}", hint=f"its parameters: dyadc flatten {model_spec}"
                                 + "".join(f" -L {folder}" for folder in lib_dirs)) from None
    identifier = re.sub(r"\W", "_", model.name.rsplit(".", 1)[-1]) or "model"
    guid = "{" + str(uuid.uuid4()) + "}"
    descriptions = {v.name: v.description for v in flat.variables if v.description}
    descriptions.update({p.name: p.description for p in flat.parameters if p.description})
    info = ModelInfo(identifier, guid, f"{model.name}, compiled by dyadc", descriptions,
                     model.metadata.get("units", {}), _tool(), stop_time, kind)
    sources = fmu_sources(model, layout, guid, fmi)
    _write_fmu(output, identifier, DESCRIBERS[fmi](model, layout, info, sources.compiled), sources,
               PLATFORMS[fmi])
    return output


def _tool() -> str:
    from compiler import __version__
    return f"dyadc {__version__}"


def _compile(model_spec: str, lib_dirs: Sequence[str]):
    from compiler.linear.inputs import check_not_differentiated, free_inputs, with_linear_inputs
    from compiler.pipeline import compile_flat, flatten_spec
    flat = flatten_spec(model_spec, lib_dirs)[0]
    if not free_inputs(flat):
        return compile_flat(flat), []
    changed = with_linear_inputs(flat)
    compilation = compile_flat(changed)
    inputs = list(changed.metadata["linear_inputs"])
    check_not_differentiated(changed, compilation.analysis, inputs)
    return compilation, inputs


def _refuse_switching(compilation) -> None:
    model = compilation.model
    if not (compilation.dynamic or model.state_sets or model.variants or model.universal is not None):
        return
    level = model.state_sets[0] if model.state_sets else {"candidates": []}
    candidates = list(level.get("candidates", []))
    base = candidates[0] if candidates else ""
    while base.startswith("der(") and base.endswith(")"):
        base = base[4:-1]
    span = None
    try:
        span = compilation.flat.variable(base).origin.span if base else None
    except (KeyError, ValueError, AttributeError):
        span = None
    raise DyadError(f"`{model.name}` switches its state set during a run (level 0 of its dummy-derivative "
                    f"choice: {', '.join(candidates) or 'several candidates'}, {level.get('rows', '?')} of "
                    f"them dummy derivatives, chosen at run time): an FMU integrates one fixed state set",
                    span, hint="prefer states that serve the whole run (`variable phi::Angle(state_priority = "
                               "10)`), or run the model with `dyadc simulate`")


def compile_binary(sources: CSources, identifier: str, folder: Path) -> Path:
    compiler = find_compiler()
    if compiler is None:
        raise DyadError("exporting an FMU needs a C compiler (gcc, cc or clang) on the PATH",
                        hint="install gcc (e.g. apt-get install gcc) and run the command again")
    for name, text in sources.files.items():
        (folder / name).write_text(text, encoding="utf-8")
    built = folder / f"{identifier}.so"
    done = subprocess.run([compiler, *FLAGS, *sources.compiled, "-o", built.name, "-lm"], cwd=folder,
                          capture_output=True, text=True, timeout=COMPILE_TIMEOUT)
    if done.returncode != 0:
        raise DyadError(f"{Path(compiler).name} could not compile the FMU's C code: "
                        f"{done.stderr.strip()[-2000:]}")
    return built


def _write_fmu(output: Path, identifier: str, description: str, sources: CSources, platform: str) -> None:
    with tempfile.TemporaryDirectory(prefix="dyadc-fmu-") as tmp:
        binary = compile_binary(sources, identifier, Path(tmp))
        output.parent.mkdir(parents=True, exist_ok=True)
        with zipfile.ZipFile(output, "w", zipfile.ZIP_DEFLATED) as fmu:
            fmu.writestr("modelDescription.xml", description)
            fmu.write(binary, f"binaries/{platform}/{identifier}.so")
            for name, text in sorted(sources.files.items()):
                fmu.writestr(f"sources/{name}", text)
