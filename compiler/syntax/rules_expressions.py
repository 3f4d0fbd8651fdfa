"""Parse-tree rules for expressions and for the JSON of metadata."""
from __future__ import annotations

import json

from lark import Token

from compiler.syntax import ast
from compiler.syntax.build_support import (
    OPERATOR_SPELLINGS, CallArgs, LiteralError, RuleBase, join_spans, number_value,
    string_content,
)


class ExpressionRules(RuleBase):

    def if_expr(self, meta, children):
        *pairs, otherwise = children
        result = otherwise
        for index in range(len(pairs) - 2, -1, -2):
            condition, then = pairs[index], pairs[index + 1]
            if index == 0:
                span = self._span(meta)
            else:
                span = join_spans(condition.span, result.span)
            result = ast.IfExpr(condition, then, result, span=span)
        return result

    def ternary(self, meta, children):
        # `c ? a : b` means `if c then a else b`, and prints that way.
        condition, then, _, otherwise = children
        return ast.IfExpr(condition, then, otherwise, span=self._span(meta))

    def binary(self, meta, children):
        left, op, right = children
        return ast.BinaryOp(OPERATOR_SPELLINGS.get(op.value, op.value), left, right,
                            span=self._span(meta))

    def unary(self, meta, children):
        op, operand = children
        return ast.UnaryOp(op.value, operand, span=self._span(meta))

    def range(self, meta, children):
        if len(children) == 2:
            return ast.Range(children[0], children[1], span=self._span(meta))
        start, step, stop = children
        return ast.Range(start, stop, step, span=self._span(meta))

    def ref(self, meta, children):
        return ast.Ref(children[0], span=self._span(meta))

    def call(self, meta, children):
        parts, *rest = children
        span = self._span(meta)
        if any(p.indices for p in parts):
            raise self._error("only a plain (possibly dotted) name can be called, not an indexed "
                              "one", span)
        args = rest[0] if rest else CallArgs((), ())
        return ast.Call(".".join(p.name for p in parts), args.args, args.kwargs, span=span)

    def name_path(self, meta, children):
        return tuple(children)

    def name_part(self, meta, children):
        name, *indices = children
        return ast.RefPart(name.value, indices[0] if indices else ())

    def generator_args(self, meta, children):
        """`sum(x[i] for i in 1:n)`: Julia's generator argument, the comprehension `[x[i] for ...]`."""
        generator = comprehension_of(children, self._span(meta), generator=True)
        return CallArgs((generator,), ())

    def call_args(self, meta, children):
        args, kwargs = [], []
        for child in children:
            if isinstance(child, ast.KeywordArg):
                kwargs.append(child)
            elif isinstance(child, tuple):
                kwargs.extend(child)
            else:
                if kwargs:
                    raise self._error("a positional argument cannot follow a keyword argument",
                                      child.span)
                args.append(child)
        seen = set()
        for kwarg in kwargs:
            if kwarg.name in seen:
                raise self._error(f"keyword argument `{kwarg.name}` is given twice", kwarg.span)
            seen.add(kwarg.name)
        return CallArgs(tuple(args), tuple(kwargs))

    def keyword_args(self, meta, children):
        return tuple(children)

    def keyword_arg(self, meta, children):
        return ast.KeywordArg(children[0].value, children[1], span=self._span(meta))

    def index_args(self, meta, children):
        return tuple(children)

    def colon(self, meta, children):
        return ast.Colon(span=self._span(meta))

    def number(self, meta, children):
        tok = children[0]
        try:
            value = number_value(tok.value)
        except LiteralError as err:
            raise self._error(str(err), self._tspan(tok),
                              hint="write it with an exponent, e.g. `1.5e300`") from None
        return ast.Number(value, span=self._tspan(tok), text=tok.value)

    def string(self, meta, children):
        tok = children[0]
        return ast.String(string_content(tok.value), span=self._tspan(tok))

    def true(self, meta, children):
        return ast.Boolean(True, span=self._tspan(children[0]))

    def false(self, meta, children):
        return ast.Boolean(False, span=self._tspan(children[0]))

    def end_index(self, meta, children):
        return ast.End(span=self._tspan(children[0]))

    def array_empty(self, meta, children):
        return ast.ArrayLit((), span=self._span(meta))

    def array_literal(self, meta, children):
        return ast.ArrayLit(tuple(children), span=self._span(meta))

    def comprehension(self, meta, children):
        return comprehension_of(children, self._span(meta))

    def comprehension_for(self, meta, children):
        return ast.ForClause(children[0], children[1] if len(children) > 1 else None,
                             span=self._span(meta))

    def matrix(self, meta, children):
        span = self._span(meta)
        if len(children) == 1 and len(children[0]) == 1:
            return ast.ArrayLit(children[0], span=span)
        rows = tuple(ast.ArrayLit(row, span=join_spans(row[0].span, row[-1].span))
                     for row in children)
        return ast.ArrayLit(rows, is_matrix=True, span=span)

    def matrix_row(self, meta, children):
        return tuple(children)

    # ------------------------------------------------------------------ JSON

    def json_object(self, meta, children):
        obj = {}
        for key, value, key_span in children:
            if key in obj:
                raise self._error(f"JSON key \"{key}\" is given twice", key_span)
            obj[key] = value
        return obj

    def json_pair(self, meta, children):
        key_token, value = children
        return (self._json_string(key_token), value, self._tspan(key_token))

    def json_array(self, meta, children):
        return list(children)

    def json_string(self, meta, children):
        return self._json_string(children[0])

    def _json_string(self, tok: Token) -> str:
        try:
            return json.loads(tok.value)
        except ValueError:
            raise self._error("invalid escape sequence in JSON string", self._tspan(tok)) from None

    def json_number(self, meta, children):
        text = "".join(t.value for t in children)
        try:
            return json.loads(text)
        except ValueError:
            raise self._error(f"`{text}` is not a JSON number", self._span(meta)) from None

    def json_true(self, meta, children):
        return True

    def json_false(self, meta, children):
        return False

    def json_name(self, meta, children):
        tok = children[0]
        if tok.value == "null":
            return None
        raise self._error(f"expected a JSON value, found name `{tok.value}`", self._tspan(tok),
                          hint="JSON strings need double quotes")


def comprehension_of(children, span, generator: bool = False) -> ast.Comprehension:
    """The element expression and its `for` clauses as one Comprehension."""
    expr, first, *more = children
    return ast.Comprehension(expr, first.iterators, span=span, generator=generator,
                             condition=first.condition, more=tuple(more))
