"""Parse-tree rules for the `relations` section."""
from __future__ import annotations

from dataclasses import dataclass

from lark import Token

from compiler.syntax import ast
from compiler.syntax.build_support import Else, RuleBase, split_doc, split_suffixes
from compiler.syntax.modelica_forms import modelica_form_error


@dataclass(frozen=True)
class _CaseClause:
    """A parsed `case`: the AST case, and whether its own `end` closed it (Dyad's form)."""
    case: ast.SwitchCase
    closed: bool


class RelationRules(RuleBase):

    def equation(self, meta, children):
        doc, rest = split_doc(children)
        suffixes, rest = split_suffixes(rest, "a relation")
        if len(rest) == 1:
            return self._lone_expression(rest[0], doc, suffixes, self._span(meta))
        lhs, rhs = rest
        return ast.Equation(lhs, rhs, doc=doc, span=self._span(meta), metadata=suffixes.metadata,
                            link=suffixes.link)

    def _lone_expression(self, expr, doc, suffixes, span):
        if isinstance(expr, ast.Call) and expr.function == "continuity":
            if not expr.args or expr.kwargs:
                raise self._error("`continuity` takes the connector media to join, like "
                                  "`continuity(a.medium, b.medium)`", expr.span)
            return ast.Continuity(expr.args, doc=doc, span=span, metadata=suffixes.metadata,
                                  link=suffixes.link)
        if isinstance(expr, ast.Call):
            modelica = modelica_form_error(expr.function, expr.span)     # `reinit(v, 0)`
            if modelica is not None:
                raise modelica
        end = expr.span
        where = None if end is None else type(end)(end.file, end.end_line, end.end_column + 1,
                                                    end.end_line, end.end_column + 1)
        raise self._error("expected `=` after this expression: a relation is `lhs = rhs`",
                          where or span, hint="`connect(...)` and `continuity(...)` are the only "
                                              "relations without `=`")

    def initial_equation(self, meta, children):
        doc, (_, lhs, rhs) = split_doc(children)
        return ast.Equation(lhs, rhs, initial=True, doc=doc, span=self._span(meta))

    def guess_stmt(self, meta, children):
        doc, (_, target, value) = split_doc(children)
        if not isinstance(target, ast.Ref):
            raise self._error("`guess` needs a variable name on the left of `=`", target.span)
        return ast.Guess(target, value, span=self._span(meta), doc=doc)

    def _connector_refs(self, refs, what: str):
        for ref in refs:
            if not isinstance(ref, ast.Ref):
                raise self._error(f"`{what}` takes connector names, like `{what}(a.p, b.n)`",
                                  ref.span)
        return tuple(refs)

    def connect_stmt(self, meta, children):
        doc, rest = split_doc(children)
        suffixes, refs = split_suffixes(rest, "a `connect`")
        return ast.Connect(self._connector_refs(refs, "connect"), doc=doc, span=self._span(meta),
                           metadata=suffixes.metadata, link=suffixes.link)

    def analysis_point(self, meta, children):
        doc, rest = split_doc(children)
        suffixes, (name, _, _, *refs) = split_suffixes(rest, "an analysis point")
        return ast.Connect(self._connector_refs(refs, "analysis_point"), doc=doc,
                           span=self._span(meta), metadata=suffixes.metadata, link=suffixes.link,
                           analysis_point=name.value)

    def for_block(self, meta, children):
        doc, (iterators, body) = split_doc(children)
        return ast.ForLoop(iterators, body, span=self._span(meta), doc=doc)

    def if_block(self, meta, children):
        doc, (condition, body, *clauses) = split_doc(children)
        branches = [ast.IfBranch(condition, body, span=self._span(meta))]
        otherwise: tuple = ()
        for clause in clauses:
            if isinstance(clause, Else):
                otherwise = clause.body
            else:
                branches.append(clause)
        return ast.IfRelation(tuple(branches), otherwise, span=self._span(meta), doc=doc)

    def elseif_clause(self, meta, children):
        return ast.IfBranch(children[0], children[1], span=self._span(meta))

    def else_clause(self, meta, children):
        return Else(children[0], closed=len(children) > 1)

    def switch_block(self, meta, children):
        doc, (_, subject, *clauses) = split_doc(children)
        cases = tuple(c.case for c in clauses if isinstance(c, _CaseClause))
        otherwise = next((c.body for c in clauses if isinstance(c, Else)), ())
        closed = any(c.closed for c in clauses)
        self._check_unique_members(cases)
        return ast.Switch(subject, cases, otherwise, span=self._span(meta), doc=doc,
                          closed_cases=closed)

    def _check_unique_members(self, cases) -> None:
        seen: set[str] = set()
        for case in cases:
            for name in case.members:
                if name in seen:
                    raise self._error(f"case `{name}` appears twice in this `switch`", case.span)
                seen.add(name)

    def case_clause(self, meta, children):
        closed = isinstance(children[-1], Token) and children[-1].type == "CASE_END"
        _, *names, body = children[:-1] if closed else children
        return _CaseClause(ast.SwitchCase(tuple(names), body, span=self._span(meta)), closed)

    def switch_value(self, meta, children):
        _, subject, *clauses = children
        cases = tuple(c for c in clauses if isinstance(c, ast.SwitchCase))
        otherwise = next((c.body for c in clauses if isinstance(c, Else)), ())
        self._check_unique_members(cases)
        return ast.SwitchValue(subject, cases, otherwise, span=self._span(meta))

    def value_case(self, meta, children):
        names = [c for c in children[1:] if isinstance(c, str) and not isinstance(c, Token)]
        value = next(c for c in children[1:] if not isinstance(c, (str, Token)))
        return ast.SwitchCase(tuple(names), (value,), span=self._span(meta))

    def value_else(self, meta, children):
        value = next(c for c in children if not isinstance(c, Token))
        return Else((value,))

    def case_label(self, meta, children):
        """The member as written: `Low`, `Gear.Low`."""
        return children[0]

    def case_value(self, meta, children):
        """`Gear.Low()`: the member as a value of its enum, kept as written."""
        return children[0] + "()"

    def case_binding(self, meta, children):
        """`InitialState(x0)`: the member and the names its fields are bound to, kept as written."""
        return f"{children[0]}({', '.join(str(name) for name in children[1:])})"

    def relation_list(self, meta, children):
        return tuple(children)

    def iterators(self, meta, children):
        return tuple(children)

    def iterator(self, meta, children):
        return ast.Iterator(children[0].value, children[1], span=self._span(meta))
