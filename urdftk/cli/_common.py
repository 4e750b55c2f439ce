"""Argument helpers shared by the subcommands."""

from __future__ import annotations

TYPE_CHECKING = False  # as typing.TYPE_CHECKING: argparse is not needed to call these helpers
if TYPE_CHECKING:
    import argparse
    from collections.abc import Sequence

__all__ = ["add_package_path_arg", "add_robot_args", "split_mappings"]


def split_mappings(items: Sequence[str]) -> tuple[list[str], dict[str, str]]:
    """Split ``name:=value`` items from plain positional items.

    Args:
        items: Command-line words.

    Returns:
        The plain words, in order, and a dict of the ``name:=value`` mappings.
    """
    plain: list[str] = []
    mappings: dict[str, str] = {}
    for item in items:
        if ":=" in item:
            name, value = item.split(":=", 1)
            mappings[name] = value
        else:
            plain.append(item)
    return plain, mappings


def add_package_path_arg(parser: argparse.ArgumentParser) -> None:
    """Add the repeatable ``-p/--package-path DIR`` option."""
    parser.add_argument(
        "-p",
        "--package-path",
        action="append",
        default=[],
        metavar="DIR",
        help="folder to search for ROS packages (package.xml); repeatable; searched first",
    )


def add_robot_args(parser: argparse.ArgumentParser) -> None:
    """Add ``ROBOT [name:=value ...]`` and ``-p DIR`` for commands that load a robot."""
    parser.add_argument("robot", metavar="ROBOT", help=".urdf or .xacro file")
    parser.add_argument("mappings", nargs="*", metavar="name:=value", help="xacro arguments")
    add_package_path_arg(parser)
