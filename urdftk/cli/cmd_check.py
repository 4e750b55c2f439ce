"""``urdftk check FILE [name:=value ...]``: check_urdf's summary, then every problem with its line.

Exit status: 0 clean (warnings allowed), 1 when any finding is an error, 2 when the file cannot
be read (missing, malformed XML, DOCTYPE, xacro failure).
"""

from __future__ import annotations

import argparse

from urdftk.cli._common import add_robot_args, split_mappings

__all__ = ["register", "run"]


def register(subparsers: argparse._SubParsersAction) -> None:
    """Add the ``check`` subcommand."""
    parser = subparsers.add_parser(
        "check",
        help="check a URDF/xacro: link tree (as check_urdf) and lint with line numbers",
        description=(
            "Print what check_urdf prints (robot name, root link, link tree), then every problem found, "
            "as FILE:LINE: error|warning: [code] element: message. Exit 0 clean (warnings allowed), "
            "1 with errors, 2 when the file cannot be read."
        ),
    )
    add_robot_args(parser)
    parser.add_argument(
        "--format", choices=("text", "json"), default="text", help="output format (default text)"
    )
    parser.add_argument(
        "--no-meshes",
        action="store_true",
        help="only check that mesh files exist; do not load them with trimesh",
    )
    parser.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    """Run ``urdftk check``; return the exit status."""
    import json
    import sys

    from urdftk.check import check, format_text

    extra, mappings = split_mappings(args.mappings)
    if extra:
        raise ValueError(f"unexpected argument(s) {' '.join(extra)}; xacro arguments are written name:=value")
    report = check(args.robot, args=mappings, package_paths=args.package_path, load_meshes=not args.no_meshes)
    if args.format == "json":
        sys.stdout.write(json.dumps(report.to_dict(), indent=2) + "\n")
    else:
        sys.stdout.write(format_text(report, args.robot))
    return 0 if report.ok else 1
