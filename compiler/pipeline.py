"""The whole compiler as one function per stage boundary, with timings for every stage, and the
compilation cache in front of it (`compile_or_load`, docs/cache.md).

The stages are imported when they run, not with this module: a run whose compiled model comes
from the cache never imports sympy or lark.
"""
from __future__ import annotations

import time
import warnings
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Sequence

from compiler.model.collection import fewer_collections      # gc thresholds only: imports nothing heavy

if TYPE_CHECKING:
    from compiler.cache.models import CachedCompilation
    from compiler.model.flat import FlatSystem
    from compiler.model.library import Library
    from compiler.runtime import CompiledModel
    from compiler.structure.reduce import Analysis, StructureReport
    from compiler.structure.reduced import ReducedSystem


class CacheWarning(UserWarning):
    """The compilation cache could not be used; the run goes on without it."""


@dataclass
class Compilation:
    flat: FlatSystem
    reduced: ReducedSystem
    model: CompiledModel
    report: StructureReport
    timings: dict[str, float] = field(default_factory=dict)
    analysis: Analysis | None = None
    variant: object | None = None        # a state_set_variants.Variant when the state set may have to switch
    cache_key: str | None = None         # the cache entry this compilation was stored under

    @property
    def dynamic(self) -> bool:
        return self.variant is not None


def flatten_spec(spec: str, lib_dirs: Sequence[str] = (), *,
                 library: Library | None = None) -> tuple[FlatSystem, dict[str, float]]:
    """`library`: the one to read sources with (default: a new Library on `lib_dirs`)."""
    from compiler.model.flatten import flatten_resolved
    from compiler.model.library import Library
    from compiler.model.model_spec import resolve_model
    began = time.perf_counter()
    library = Library(lib_dirs) if library is None else library
    flat = flatten_resolved(resolve_model(spec, library), library)
    return flat, {"parse+flatten": time.perf_counter() - began}


@fewer_collections()
def compile_flat(flat: FlatSystem, timings: dict[str, float] | None = None) -> Compilation:
    from compiler.lower.state_set_variants import build_variant, with_variants
    from compiler.lower.universal_variant import with_universal
    from compiler.structure.state_selection.monitored import monitored_levels
    from compiler.lower.to_casadi import lower
    from compiler.model.model_check import require_standalone
    from compiler.structure.reduce import StructureReport, analyse, reduce

    timings = dict(timings or {})
    report = StructureReport()
    began = time.perf_counter()
    require_standalone(flat)         # the checks `dyadc check` runs: both say the same
    analysis = analyse(flat)
    report.timings["alias+rank+index"] = time.perf_counter() - began
    reduced = reduce(flat, point=flat.initial_values(), report=report, analysis=analysis)
    timings["structure"] = time.perf_counter() - began
    began = time.perf_counter()
    variant = None
    if monitored_levels(flat, analysis, report):
        variant = build_variant(flat, analysis, None, reduced=reduced, report=report)
        variant = with_variants(flat, analysis, variant)      # every state set, built once now
        if not variant.model.variants:       # too many to build: any one made at run time from one system
            variant = with_universal(analysis, variant)
        model = variant.model
    else:
        model = lower(reduced)
    timings["lower"] = time.perf_counter() - began
    return Compilation(flat, reduced, model, report, timings, analysis, variant)


def compile_spec(spec: str, lib_dirs: Sequence[str] = (), *, library: Library | None = None) -> Compilation:
    flat, timings = flatten_spec(spec, lib_dirs, library=library)
    return compile_flat(flat, timings)


def _library(lib_dirs: Sequence[str]) -> Library:
    """A library that takes the shipped library's trees made at install (cache/library_trees.py),
    as Python takes a module's installed bytecode: nothing of the user's cache is read."""
    from compiler.cache import library_trees
    from compiler.model.library import Library
    return Library(lib_dirs, parser=library_trees.parse_file)


def compile_or_load(spec: str, lib_dirs: Sequence[str] = (), *, cache: bool = True,
                    for_runs: bool = False, codegen: str | None = None,
                    c_folder: str | None = None) -> Compilation | CachedCompilation:
    """The compiled model of `spec`: from the compilation cache when every source it was compiled
    from is unchanged (a CachedCompilation: model only), else compiled (a Compilation, stored in
    the cache unless its state sets are more than the compiler builds one by one: such a model
    carries its universal system instead and is compiled again at every run).
    `cache=False` or DYADC_CACHE_DIR=off: compile, read and write nothing.
    `for_runs`: the model put on the code its runs take (compiler/cache/native.py; `codegen` "c",
    "vm" or None: C where a compiler is present), its C built while the compile is stored, its
    libraries in `c_folder` (default: the C library cache)."""
    if not cache:
        compilation = compile_spec(spec, lib_dirs, library=_library(lib_dirs))
        if for_runs:
            _put_on_code(compilation, _start_code(compilation, codegen, c_folder))
        return compilation
    from compiler.cache import models
    from compiler.cache.store import CacheError
    try:
        found = models.load(spec, lib_dirs)
    except (OSError, CacheError) as err:
        warnings.warn(f"compilation cache not used: {err}", CacheWarning, stacklevel=2)
        return compile_or_load(spec, lib_dirs, cache=False, for_runs=for_runs, codegen=codegen,
                               c_folder=c_folder)
    if found is not None and _units_reported(found):
        if for_runs:
            from compiler.cache import native
            began = time.perf_counter()
            found.model = native.cached_on_its_code(found.model, found.key, codegen)
            found.timings["C code"] = time.perf_counter() - began
        return found
    from compiler.cache import library_trees, parsed
    from compiler.cache.recording import RecordingLibrary
    parses = parsed.open_cache()           # the trees of files parsed before, unchanged since
    library = RecordingLibrary(lib_dirs, parser=library_trees.parse_file if parses is None else parses.parse)
    compilation = compile_spec(spec, lib_dirs, library=library)
    if parses is not None:
        parses.prune()
    started = _start_code(compilation, codegen, c_folder) if for_runs else None
    if compilation.dynamic and not getattr(compilation.model, "variants", None):
        _put_on_code(compilation, started)
        return compilation          # over the variant limit: not stored (docs/cache.md)
    began = time.perf_counter()
    try:
        compilation.cache_key = models.store(spec, lib_dirs, library.recorded_inputs(), compilation,
                                             start_notes(compilation))
    except (OSError, CacheError) as err:
        warnings.warn(f"compilation cache not written: {err}", CacheWarning, stacklevel=2)
    compilation.timings["cache write"] = time.perf_counter() - began
    _put_on_code(compilation, started)
    return compilation


def _start_code(compilation: Compilation, codegen: str | None, c_folder: str | None):
    from compiler.cache import native
    return native.start(compilation.model, codegen, c_folder)


def _put_on_code(compilation: Compilation, started) -> None:
    """The compilation's model on its code once `started` (a native.Started, or None) is done;
    a cached model gets the link to its libraries."""
    if started is None:
        return
    compilation.model = started.finish()
    compilation.timings["C code"] = started.seconds
    if compilation.cache_key is not None and started.build is not None \
            and compilation.model.metadata.get("codegen") == "c":
        from compiler.cache import native
        native.write_link(compilation.cache_key, started.build)


def _units_reported(found: CachedCompilation) -> bool:
    """Report the unit findings kept with a cached compilation as the current --units says;
    False when it was compiled with the check off and the check is now on (compile again)."""
    if found.unit_findings is None:
        from compiler.units.mode import current_mode
        return current_mode() == "off"
    if found.unit_findings:                 # a clean model imports nothing of compiler.units here
        from compiler.units.findings import Finding
        from compiler.units.mode import report
        report([Finding.from_dict(data) for data in found.unit_findings])
    return True


def start_notes(compilation: Compilation | CachedCompilation) -> list[str]:
    """What `dyadc simulate` prints before a run, as whole lines: the warning on connectors left
    unconnected and the note on start values chosen for an under-determined initialization (as
    compiler.testing.golden.initialization_notes); a cached compilation kept them."""
    if not isinstance(compilation, Compilation):
        return list(compilation.notes)
    from compiler.model.flatten_report import open_connector_warning
    from compiler.structure.initialization import describe_chosen
    chosen = compilation.reduced.initial.chosen
    warning = open_connector_warning(compilation.flat)
    return [f"warning: {warning}"] * bool(warning) + [f"note: {describe_chosen(chosen)}"] * bool(chosen)


def recompile(cached: CachedCompilation) -> Compilation:
    """The full compilation behind a cached one, for what only the sources can tell (its unit
    findings were reported when it was loaded: not again)."""
    from compiler.units.mode import units_mode
    with units_mode("off"):
        compilation = compile_spec(cached.spec, cached.lib_dirs)
    compilation.timings = {**cached.timings, **compilation.timings}
    return compilation
