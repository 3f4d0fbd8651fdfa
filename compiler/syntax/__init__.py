"""The language front end: grammar, parser to AST, diagnostics and the canonical formatter."""
