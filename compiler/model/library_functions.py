"""How a library resolves the functions Dyad code calls: built-ins, Python plugins
(`dyad_functions.py`, run only from roots on the search path) and functions a package defines in
Julia (compiler.julia.functions). A mixin of compiler.model.library.Library, kept apart because
finding functions is a concern of its own beside finding definitions."""
from __future__ import annotations

from pathlib import Path

from compiler.errors import DyadError, Span
from compiler.julia.functions import JuliaFunction, UnreadableFunction, julia_source_files, \
    read_julia_functions
from compiler.model.builtins import builtin, suggest_function
from compiler.model.functions import FunctionImpl
from compiler.model.library_path import LIBRARY_PATH_VARIABLE
from compiler.syntax import ast
from compiler.syntax.modelica_forms import modelica_form_error

FUNCTION_PLUGIN_FILE = "dyad_functions.py"


class FunctionLookup:
    """Function resolution for a library: it needs `registry`, `search_path`, `roots_for` and
    `candidates` from the class it is mixed into."""

    def resolve_function(self, name: str, package: str, file: ast.File | None,
                         span: Span | None) -> FunctionImpl | JuliaFunction:
        entry = builtin(name)
        if entry is not None and entry.function is not None:
            return entry.function
        candidates = self.candidates(name, package, file)
        for candidate in candidates:
            self._load_plugins_for(candidate)
            found = self.registry.get(candidate)
            if found is not None:
                return found
        found_julia = [self.julia_function(candidate) for candidate in candidates]
        if file is not None and "." not in name:
            # a file given by path from a project's dyad/ folder: its package's src/ is beside it
            found_julia.append(self.julia_function_beside(Path(file.path), name))
        for julia in found_julia:
            if isinstance(julia, UnreadableFunction):
                raise julia.error(span)
            if julia is not None:
                return julia
        skipped = [plugin for candidate in candidates for plugin in self.plugin_files(candidate, False)]
        if skipped:
            raise DyadError(f"unknown function `{name}`", span,
                            hint=f"{skipped[0]} was not run: dyadc runs a library's Python only "
                                 f"from folders named with -L DIR or {LIBRARY_PATH_VARIABLE}; if you "
                                 f"trust it, add -L {skipped[0].parent}")
        modelica = modelica_form_error(name, span)          # `pre(x)`, `edge(b)`
        if modelica is not None:
            raise modelica
        suggestion = suggest_function(name, self.registry)
        raise DyadError(f"unknown function `{name}`", span,
                        hint=f"did you mean `{suggestion}`?" if suggestion else None)

    def julia_function(self, qualified_name: str) -> JuliaFunction | UnreadableFunction | None:
        """A function `Pkg.name` that package `Pkg` defines in Julia (compiler.julia.functions),
        from the first root whose folder `Pkg` defines it, as for definitions."""
        package, _, name = qualified_name.rpartition(".")
        if not package or "." in package:
            return None
        for root in self.roots_for(qualified_name):
            if (root / package).is_dir():
                found = self.julia_functions_in(root / package, package).get(qualified_name)
                if found is not None:
                    return found
        return None

    def julia_function_beside(self, dyad_file: Path, name: str) -> JuliaFunction | UnreadableFunction | None:
        """`name` defined in Julia by the project whose dyad/ folder holds `dyad_file`."""
        folder = dyad_file.parent
        package = folder.resolve().parent.name.removesuffix(".jl")
        return self.julia_functions_in(folder, package).get(f"{package}.{name}")

    def julia_functions_in(self, folder: Path, package: str) -> dict:
        """The functions package `package` defines in the Julia sources of `folder`, read once."""
        key = str(folder.resolve())
        if key not in self._julia:
            functions: dict = {}
            for path in julia_source_files(folder):
                for qualified, value in read_julia_functions(path, package).items():
                    functions.setdefault(qualified, value)
            self._julia[key] = functions
        return self._julia[key]

    def plugin_files(self, qualified_name: str, runs_code: bool) -> list[Path]:
        """The plugin files for the package of `qualified_name` in the roots that may (or may
        not) run code."""
        package_parts = qualified_name.split(".")[:-1]
        allowed = set(self.roots_for(qualified_name))
        plugins = (root.path.joinpath(*package_parts) / FUNCTION_PLUGIN_FILE
                   for root in self.search_path if root.runs_code == runs_code and root.path in allowed)
        return [plugin for plugin in plugins if plugin.is_file()]

    def _load_plugins_for(self, qualified_name: str) -> None:
        for plugin in self.plugin_files(qualified_name, True):
            try:
                self.registry.load_plugin(plugin)
            except Exception as exc:  # a broken plugin is a library error, not a crash
                raise DyadError(f"cannot load function plugin {plugin}: {exc}") from exc
