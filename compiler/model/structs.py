"""Parameters of a `struct` type: a record of named values, e.g. a material's data.

    struct Material
      mu_i::Real = 1
      label::String = "generic"
    end
    type Steel = Material(mu_i = 200, label = "steel")     # an alias with values

    component Core
      parameter mat::Material = Steel()                    # or Material(mu_i = 3), or no value
    relations
      mu = mat.mu_i * mu_0
    end

A struct parameter becomes a nested instance whose fields are ordinary parameters (`mat.mu_i`,
tunable with `-p core.mat.mu_i=...` like any parameter). These are pure AST helpers; the instance is
built by compiler/model/instantiate.py. Field values, highest precedence first: modifiers where the
component is used (`Core(mat(mu_i = 3))`), the constructor given as value (`= Steel()`, or one
given from outside, `Core(mat = Steel())`), the modifiers of the declared type
(`mat::Material(mu_i = 3)`) and of the aliases it goes through, the fields' defaults.
"""
from __future__ import annotations

from dataclasses import dataclass

from compiler.errors import DyadError
from compiler.syntax import ast

MAX_ALIAS_DEPTH = 20


@dataclass(frozen=True)
class StructType:
    resolved: object                    # compiler.model.library.Resolved of the StructDef
    # modifications of the aliases it was reached through, highest precedence first, each with
    # the Resolved definition whose file and package its expressions belong to (None: the use site)
    modifications: tuple[tuple[ast.Modification, object], ...]


def struct_type(library, spec: ast.TypeSpec, package: str, file) -> StructType | None:
    """The struct behind a type name (through `type Alias = Struct(mods)` aliases), or None when
    the name is a primitive, an ordinary value type or unknown (the caller reports those)."""
    if spec.name in ("Real", "Integer", "Boolean", "String"):
        return None
    found = library.lookup(spec.name, package, file)
    mods: list[tuple[ast.Modification, object]] = [(m, None) for m in spec.modifications]
    depth = 0
    while found is not None and isinstance(found.definition, ast.TypeDef):
        base = found.definition.base
        if base.name in ("Real", "Integer", "Boolean", "String") or depth > MAX_ALIAS_DEPTH:
            return None
        mods += [(m, found) for m in base.modifications]
        found = library.lookup(base.name, found.package, found.file)
        depth += 1
    if found is None or not isinstance(found.definition, ast.StructDef):
        return None
    return StructType(found, tuple(mods))


# The dataset types of Dyad's Julia package DyadData (help.juliahub.com, "Working with Data"):
# declared as `ds::DyadData.DyadDataset`, or unqualified in a file that says `using DyadData`.
DYADDATA_PACKAGE = "DyadData"
DYADDATA_TYPES = ("DyadDataset", "DyadTimeseries", "DyadTable", "DyadInterpolationTable2D")


def is_dyaddata_type(name: str, file) -> bool:
    """Does `name` name one of DyadData's dataset types where it is written?"""
    package, _, short = name.rpartition(".")
    if package:
        return package == DYADDATA_PACKAGE and short in DYADDATA_TYPES
    return any(using.written == DYADDATA_PACKAGE and using.imported(short) in DYADDATA_TYPES
               for using in getattr(file, "usings", ()))


def is_julia_object(library, spec: ast.TypeSpec, package: str, file) -> bool:
    """Is a parameter of this type a Julia object dyadc keeps opaque: `Native` (a dataset, an
    interpolator), directly or through aliases, one of DyadData's dataset types, or a function
    type (`func(::Real)::Real`)?"""
    depth = 0
    while depth <= MAX_ALIAS_DEPTH:
        if spec.name in ("Native", "Dyad.Native"):
            return True
        if is_dyaddata_type(spec.name, file) and library.lookup(spec.name, package, file) is None:
            return True
        if spec.name in ("Real", "Integer", "Boolean", "String"):
            return False
        found = library.lookup(spec.name, package, file)
        if found is None:
            return False
        if isinstance(found.definition, ast.FunctionTypeDef):
            return True
        if not isinstance(found.definition, ast.TypeDef):
            return False
        spec, package, file = found.definition.base, found.package, found.file
        depth += 1
    return False


def as_component(struct: ast.StructDef) -> ast.ComponentDef:
    """The struct as a component whose declarations are its fields, as parameters."""
    for field_decl in struct.fields:
        if field_decl.kind is not None:
            raise DyadError(f"a `{field_decl.kind}` field in struct `{struct.name}`",
                            field_decl.span)
    return ast.ComponentDef(
        name=struct.name, doc=struct.doc, span=struct.span, prefix="struct",
        declarations=tuple(ast.ParameterDecl(name=f.name, type=f.type, default=f.value, doc=f.doc,
                                             span=f.span) for f in struct.fields))


def constructor_type(value: ast.Expr, name: str) -> ast.Call:
    if not isinstance(value, ast.Call):
        raise DyadError(f"struct parameter `{name}` takes a constructor such as `Type(field = "
                        f"value)`", getattr(value, "span", None))
    return value
