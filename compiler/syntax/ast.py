"""Typed AST of the Dyad-like language: every node type, gathered from ast_expressions.py,
ast_declarations.py, ast_relations.py and ast_definitions.py, so that the rest of the compiler
writes `ast.Number`, `ast.ComponentDef`, ...

Every node carries its source `span`; spans are excluded from equality so that
`parse(fmt(x)) == parse(x)` compares structure only. Sequences are tuples so nodes stay immutable.
Metadata JSON is kept as a canonical JSON string (`json.dumps(obj, sort_keys=True)`) to stay hashable;
use `metadata_dict()` to read it.
"""
from __future__ import annotations

from compiler.syntax.ast_declarations import ComponentDecl, Declaration, Extends, Modification, \
    ParameterDecl, TypeSpec, TypedDecl, VariableDecl
from compiler.syntax.ast_definitions import AnalysisDef, ComponentDef, ConnectorDef, \
    ConnectorField, Definition, EnumDef, File, FunctionParam, FunctionTypeDef, SignalConnectorDef, \
    StructDef, TypeDef, Using, metadata_dict
from compiler.syntax.ast_expressions import ArrayLit, BinaryOp, Boolean, Call, Colon, \
    Comprehension, End, Expr, ForClause, IfExpr, Iterator, KeywordArg, Number, Range, Ref, RefPart, String, \
    UnaryOp, left_chain
from compiler.syntax.ast_relations import Connect, Continuity, Equation, ForLoop, Guess, IfBranch, \
    IfRelation, Relation, Switch, SwitchCase, SwitchValue

__all__ = ["AnalysisDef", "ArrayLit", "BinaryOp", "Boolean", "Call", "Colon", "ComponentDecl",
           "ComponentDef", "Comprehension", "Connect", "ConnectorDef", "ConnectorField",
           "Continuity", "Declaration", "Definition", "End", "EnumDef", "Equation", "Expr",
           "Extends", "File", "ForClause", "ForLoop", "FunctionParam", "FunctionTypeDef", "Guess", "IfBranch",
           "IfExpr", "IfRelation", "Iterator", "KeywordArg", "Modification", "Number",
           "ParameterDecl", "Range", "Ref", "RefPart", "Relation", "SignalConnectorDef", "String",
           "StructDef", "Switch", "SwitchCase", "SwitchValue", "TypeDef", "TypeSpec", "TypedDecl", "UnaryOp",
           "Using", "VariableDecl", "left_chain", "metadata_dict"]
