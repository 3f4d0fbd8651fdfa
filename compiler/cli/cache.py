"""`dyadc cache info` (where the cache is, what it holds) and `dyadc cache clear` (empty it)."""
from __future__ import annotations


def add_cache(sub) -> None:
    p = sub.add_parser("cache", help="where the compilation cache is and what it holds; clear it")
    p.add_argument("action", choices=["info", "clear"])
    p.set_defaults(run=run_cache)


ADDERS = {"cache": add_cache}


def run_cache(args) -> int:
    from compiler.cache import contents
    if args.action == "clear":
        removed = contents.clear()
        print(f"removed {len(removed)} files from the compilation cache")
        return 0
    print("\n".join(contents.info_lines()))
    return 0
