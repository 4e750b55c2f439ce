"""Stock xacro's command-line parsing (``xacro.cli``): ``process_args`` and ``load_mappings``."""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence

__all__ = ["REMAP", "load_mappings", "process_args"]

REMAP = ":="


def load_mappings(argv: Sequence[str]) -> dict[str, str]:
    """Collect ``name:=value`` arguments (``_private:=`` parameter assignments are skipped).

    Raises:
        RuntimeError: For a malformed remapping.
    """
    mappings: dict[str, str] = {}
    for arg in argv:
        if REMAP in arg:
            try:
                src, dst = (x.strip() for x in arg.split(REMAP))
            except ValueError:
                raise RuntimeError(f"Invalid remapping argument '{arg}'\n") from None
            if src and dst and not (len(src) > 1 and src[0] == "_" and src[1] != "_"):
                mappings[src] = dst
    return mappings


class _Parser(argparse.ArgumentParser):
    def error(self, message: str) -> None:  # type: ignore[override]
        self.exit(2, f"{self.prog}: error: {message}\n")


def process_args(argv: Sequence[str], require_input: bool = True) -> tuple[argparse.Namespace, str | None]:
    """Parse stock ``xacro`` options.

    Args:
        argv: Command-line words (without the program name).
        require_input: Whether exactly one input file must be given.

    Returns:
        The options (``output``, ``just_deps``, ``in_order``, ``root_dir``, ``verbosity``,
        ``mappings``) and the input file (None when not required and not given).
    """
    p = _Parser(prog="xacro", usage="xacro [options] <input>")
    p.add_argument("-o", dest="output", metavar="FILE", help="write output to FILE instead of stdout")
    p.add_argument("--deps", action="store_true", dest="just_deps", help="print file dependencies")
    p.add_argument("--inorder", "-i", action="store_true", dest="in_order", help="accepted for compatibility")
    p.add_argument("--root-dir", dest="root_dir", metavar="DIR", default=None, help="root for relative paths")
    p.add_argument("-q", action="store_const", dest="verbosity", const=0, help="quiet operation")
    p.add_argument("-v", action="count", dest="verbosity", help="increase verbosity")
    p.add_argument("--verbosity", metavar="level", dest="verbosity", type=int, help="set verbosity level")
    p.add_argument("input", nargs="*")
    mappings = load_mappings(argv)
    opts = p.parse_args([a for a in argv if REMAP not in a])
    if opts.verbosity is None:
        opts.verbosity = 1
    if opts.in_order:
        print(
            "xacro: in-order processing became default in ROS Melodic. You can drop the option.",
            file=sys.stderr,
        )
    opts.in_order = True
    inputs = opts.input
    del opts.input
    if len(inputs) != 1:
        if require_input:
            p.error("expected exactly one input file as argument")
        inputs = [None]
    opts.mappings = mappings
    return opts, inputs[0]
