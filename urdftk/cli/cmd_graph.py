"""``urdftk graph FILE [name:=value ...] [-o OUT.{gv,svg,png,pdf}]``: urdf_to_graphviz's picture.

Without ``-o`` the DOT text goes to standard output. Robot text never reaches a shell.
"""

from __future__ import annotations

import argparse

from urdftk.cli._common import add_robot_args, split_mappings

__all__ = ["register", "run"]


def register(subparsers: argparse._SubParsersAction) -> None:
    """Add the ``graph`` subcommand."""
    parser = subparsers.add_parser(
        "graph",
        help="draw the link/joint tree with Graphviz, as urdf_to_graphviz (.gv, .svg, .png, .pdf)",
        description=(
            "Draw links as boxes and joints as ellipses, each edge labelled with the joint origin "
            "(xyz, rpy). "
            "The output suffix picks the format: .gv/.dot (DOT text), .svg, .png or .pdf (rendered by "
            "Graphviz `dot`). Without -o, the DOT text is printed."
        ),
    )
    add_robot_args(parser)
    parser.add_argument("-o", "--output", metavar="OUT", help="output file: .gv, .dot, .svg, .png or .pdf")
    parser.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    """Run ``urdftk graph``; return the exit status."""
    import sys

    from urdftk.description import structure_errors
    from urdftk.graph import output_format, read_robot, to_dot, write_dot

    extra, mappings = split_mappings(args.mappings)
    if extra:
        raise ValueError(f"unexpected argument(s) {' '.join(extra)}; xacro arguments are written name:=value")
    if args.output is not None:
        output_format(args.output)  # refuse a bad suffix before any work
    root, tree = read_robot(args.robot, args=mappings, package_paths=args.package_path)
    text = to_dot(tree)
    if args.output is None:
        sys.stdout.write(text)
    else:
        write_dot(text, args.output)
        print(f"Created file {args.output}")
    problems = structure_errors(root, tree)
    if problems:
        print(
            f"urdftk graph: warning: {len(problems)} structural problem(s), drawn as found; "
            f"run `urdftk check {args.robot}` for details",
            file=sys.stderr,
        )
    return 0
