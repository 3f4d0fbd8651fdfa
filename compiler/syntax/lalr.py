"""The LALR(1) parser object, built without any file cache outside the package.

lark's `cache=True` kept its tables as a pickle in the shared temp folder under a predictable name,
so another local user who planted that file ran code in every `dyadc` process. Instead the tables
are generated once into the package (`lalr_tables.json`, plain JSON data, never pickle) and loaded
from there; they are used only when their fingerprint (a hash of the grammar text, the parser
options and lark's version) matches, otherwise the tables are built in memory (~0.25 s). Nothing is
read from or written to any other place.

Regenerate the tables after editing grammar.lark:  python -m compiler.syntax.lalr
(tests/syntax/test_parser_tables.py fails while they are stale).
"""
from __future__ import annotations

import hashlib
import json
from pathlib import Path

import lark
from lark import Lark
from lark.grammar import Rule
from lark.lexer import Lexer, TerminalDef

GRAMMAR_PATH = Path(__file__).with_name("grammar.lark")
TABLES_PATH = Path(__file__).with_name("lalr_tables.json")
START_SYMBOLS = ("start", "expression_start")
# One LALR table serves files and lone expressions.
_EXTRA_RULES = "\nexpression_start: expr\n"


class TokenListLexer(Lexer):
    """The parser receives the token list already arranged by compiler.syntax.layout."""

    def __init__(self, lexer_conf):
        pass

    def lex(self, tokens):      # noqa: D102 - lark's custom-lexer protocol
        return iter(tokens)


def grammar_text() -> str:
    return GRAMMAR_PATH.read_text(encoding="utf-8") + _EXTRA_RULES


def _options() -> dict:
    return dict(start=list(START_SYMBOLS), parser="lalr", lexer=TokenListLexer,
                propagate_positions=True, maybe_placeholders=False, cache=False)


def fingerprint(text: str, lark_version: str = lark.__version__) -> str:
    """What the tables depend on: grammar, options (the lexer by name) and lark's version."""
    options = {k: (v.__name__ if isinstance(v, type) else v) for k, v in _options().items()}
    payload = json.dumps([text, options, lark_version], sort_keys=True)
    return hashlib.sha256(payload.encode("utf-8")).hexdigest()


def build_parser(text: str | None = None) -> Lark:
    """The tables computed from the grammar, in memory only."""
    return Lark(text if text is not None else grammar_text(), **_options())


def load_parser() -> Lark:
    """The packaged tables when they match the grammar, else a fresh in-memory build."""
    text = grammar_text()
    tables = _read_tables()
    if tables is not None and tables.get("fingerprint") == fingerprint(text):
        try:
            return _from_tables(tables)
        except (KeyError, TypeError, ValueError):
            pass        # damaged tables are only slower, never wrong: build them instead
    return build_parser(text)


def _read_tables() -> dict | None:
    try:
        return json.loads(TABLES_PATH.read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return None


# JSON turns integer keys into strings; these are the places where lark's tables use them.
def _int_keys(mapping: dict) -> dict:
    return {int(k): v for k, v in mapping.items()}


def _from_tables(tables: dict) -> Lark:
    data, memo = tables["data"], _int_keys(tables["memo"])
    frontend = dict(data["parser"])
    frontend["lexer_conf"] = dict(frontend["lexer_conf"], lexer_type=TokenListLexer)
    lalr = dict(frontend["parser"])
    lalr["tokens"] = _int_keys(lalr["tokens"])
    lalr["states"] = {int(state): _int_keys(actions) for state, actions in lalr["states"].items()}
    frontend["parser"] = lalr
    data = dict(data, parser=frontend, options=dict(data["options"], lexer=TokenListLexer))
    return Lark._load_from_dict(data, memo)


def serialize_tables(parser: Lark, text: str) -> str:
    data, memo = parser.memo_serialize([TerminalDef, Rule])
    # The custom lexer class is restored on load; JSON cannot hold it.
    data["options"] = {k: v for k, v in data["options"].items() if k != "lexer"}
    data["parser"]["lexer_conf"] = {k: v for k, v in data["parser"]["lexer_conf"].items()
                                    if k != "lexer_type"}
    return json.dumps({"fingerprint": fingerprint(text), "lark": lark.__version__,
                       "data": data, "memo": memo}, sort_keys=True, separators=(",", ":"))


def write_tables(path: Path = TABLES_PATH) -> Path:
    text = grammar_text()
    content = serialize_tables(build_parser(text), text)
    temporary = path.with_name(path.name + ".tmp")
    temporary.write_text(content + "\n", encoding="utf-8")
    temporary.replace(path)
    return path


if __name__ == "__main__":
    # lark's state numbering differs from run to run (equivalent tables, different bytes), so
    # current tables are left alone: git shows a change only when the grammar changed.
    current = _read_tables()
    if current is not None and current.get("fingerprint") == fingerprint(grammar_text()):
        print(f"{TABLES_PATH} is current")
    else:
        print(f"wrote {write_tables()}")
