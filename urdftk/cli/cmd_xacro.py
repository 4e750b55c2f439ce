"""``urdftk xacro IN [name:=value ...] [-o OUT] [--deps] [-p DIR]``: expand a xacro file.

The output on stdout is byte-identical to stock ``xacro``'s. ``-`` reads the document from stdin
(relative includes are then relative to the current directory). ``-o`` writes atomically: on
error no file is created or truncated.
"""

from __future__ import annotations

import sys

from urdftk.cli._common import add_package_path_arg, split_mappings

TYPE_CHECKING = False
if TYPE_CHECKING:
    import argparse

__all__ = ["Args", "quick_args", "register", "run"]

_FLAGS = {"--deps": "deps", "-q": "quiet", "--quiet": "quiet"}
_VALUED = {"-o": "output", "--output": "output", "-p": "package_path", "--package-path": "package_path"}


class Args:
    """The parsed arguments of ``urdftk xacro`` (as the argparse namespace :func:`register` gives)."""

    command = "xacro"

    def __init__(self) -> None:
        self.input: str = ""
        self.mappings: list[str] = []
        self.output: str | None = None
        self.deps = False
        self.quiet = False
        self.package_path: list[str] = []
        self.func = run


def quick_args(argv: list[str]) -> Args | None:
    """Parse the common forms of the arguments without argparse (its import is start-up time).

    Args:
        argv: The words after ``xacro``.

    Returns:
        The arguments, exactly as argparse would parse them; None for anything else (help, an
        unknown or abbreviated option, a missing input, positionals split by an option...), which
        then goes through argparse and gets its messages.
    """
    args = Args()
    words: list[str] = []
    block = 0  # positional blocks seen: argparse rejects words after an option once IN is taken
    prev_positional = False
    i = 0
    while i < len(argv):
        word = argv[i]
        i += 1
        if word[:1] != "-" or word == "-":
            if not prev_positional:
                block += 1
            prev_positional = True
            words.append(word)
            continue
        prev_positional = False
        if word in _FLAGS:
            setattr(args, _FLAGS[word], True)
            continue
        name, eq, value = word.partition("=")
        if name not in _VALUED or (eq and name[:2] != "--"):
            return None
        if not eq:
            if i >= len(argv) or argv[i][:1] == "-":
                return None
            value = argv[i]
            i += 1
        dest = _VALUED[name]
        if dest == "package_path":
            args.package_path.append(value)
        else:
            args.output = value
    if not words or block > 1:
        return None
    args.input, args.mappings = words[0], words[1:]
    return args


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
