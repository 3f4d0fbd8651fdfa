"""Print a rewritten formulation: `python -m tests.metamorphic.show LABEL SEED` (what a failing
metamorphic case ran)."""
from __future__ import annotations

import sys

from compiler.syntax.format import format_file
from compiler.syntax.parser import parse_file
from tests.metamorphic import agreement, rewrites
from tests.metamorphic.corpus import BY_LABEL


def main(argv: list[str]) -> int:
    label, seed = argv[0], int(argv[1])
    base = BY_LABEL[label]
    file = parse_file(base.path)
    component = agreement.definition(file, base.name)
    rewritten, applied = rewrites.rewrite(component, seed)
    print(f"# {label} seed {seed}: {', '.join(applied)}; renamed {rewritten.renamed}")
    print(format_file(file.__class__(file.path, file.usings, (rewritten.component,))))
    return 0


if __name__ == "__main__":
    raise SystemExit(main(sys.argv[1:]))
