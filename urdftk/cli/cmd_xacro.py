"""``urdftk xacro IN [name:=value ...] [-o OUT] [--deps] [-p DIR]``: expand a xacro file.

The output on stdout is byte-identical to stock ``xacro``'s. ``-`` reads the document from stdin
(relative includes are then relative to the current directory). ``-o`` writes atomically: on
error no file is created or truncated.
"""

from __future__ import annotations

import argparse
import sys

from urdftk.cli._common import add_package_path_arg, split_mappings

__all__ = ["register", "run"]


def register(subparsers: argparse._SubParsersAction) -> None:
    """Add the ``xacro`` subcommand."""
    p = subparsers.add_parser(
        "xacro",
        help="expand a .xacro file to URDF (stock-identical output, no ROS needed)",
        description=__doc__.split("\n\n", 1)[1] if __doc__ else None,
    )
    p.add_argument("input", metavar="IN", help="input .xacro file, or - for stdin")
    p.add_argument("mappings", nargs="*", metavar="name:=value", help="xacro arguments")
    p.add_argument("-o", "--output", metavar="OUT", help="write the result to OUT (atomically)")
    p.add_argument("--deps", action="store_true", help="list included files and resolved packages instead")
    p.add_argument("-q", "--quiet", action="store_true", help="suppress warnings")
    add_package_path_arg(p)
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    """Expand ``args.input`` and write the document (or the dependencies)."""
    from urdftk.xacro import expand

    extra, mappings = split_mappings(args.mappings)
    if extra:
        raise ValueError(f"unexpected argument(s) {' '.join(extra)!r}: mappings are name:=value")
    verbosity = 0 if args.quiet else 1
    if args.input == "-":
        text = sys.stdin.read()
        result = expand(
            None, mappings, text=text, filename=None, package_paths=args.package_path, verbosity=verbosity
        )
    else:
        result = expand(args.input, mappings, package_paths=args.package_path, verbosity=verbosity)
    if args.deps:
        lines = [str(p) for p in result.includes]
        lines += [f"package {name} {path}" for name, path in sorted(result.packages.items())]
        out = "".join(line + "\n" for line in lines)
    else:
        out = result.text
    if args.output:
        from urdftk._atomic import write_atomic

        write_atomic(args.output, out)
    else:
        sys.stdout.write(out)
        sys.stdout.flush()
    return 0
