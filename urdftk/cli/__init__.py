"""The ``urdftk`` console script: argparse subcommands, one module each (``urdftk/cli/cmd_*.py``).

Each ``cmd_*`` module defines ``register(subparsers)``, which adds its subcommand(s) and sets
``func`` to a callable ``(args) -> int``; :data:`COMMANDS` maps each subcommand to its module.
Only the module of the command being run is imported, and modules import heavy libraries only
inside ``func``, so that ``urdftk xacro`` starts fast.

Every error a user can cause ends as one line on stderr and exit status 2, never a traceback.
"""

from __future__ import annotations

import os
import sys

TYPE_CHECKING = False  # as typing.TYPE_CHECKING, without importing typing at start-up
if TYPE_CHECKING:
    import argparse
    from collections.abc import Sequence

__all__ = ["COMMANDS", "main"]


def _parser_class() -> type[argparse.ArgumentParser]:
    """The ArgumentParser subclass of the CLI (argparse is imported only when a parser is built).

    Its usage errors are one line and exit 2. Its help formatter gets a fixed width
    (``COLUMNS``, else 100): argparse would otherwise import ``shutil`` to measure the terminal
    on every ``add_argument``, which is start-up time.
    """
    import argparse

    class _Parser(argparse.ArgumentParser):
        def _get_formatter(self) -> argparse.HelpFormatter:
            try:
                width = int(os.environ.get("COLUMNS", "100")) - 2
            except ValueError:
                width = 98
            return self.formatter_class(prog=self.prog, width=max(width, 40))

        def error(self, message: str) -> None:  # type: ignore[override]
            self.exit(2, f"{self.prog}: error: {message}\n")

    return _Parser


COMMANDS: dict[str, str] = {
    "bag": "cmd_bag",
    "check": "cmd_check",
    "fk": "cmd_fk",
    "graph": "cmd_graph",
    "joint-state-publisher": "cmd_nodes",
    "play": "cmd_bag",
    "record": "cmd_bag",
    "robot-state-publisher": "cmd_nodes",
    "router": "cmd_router",
    "tf": "cmd_tf",
    "topic": "cmd_topic",
    "view": "cmd_view",
    "xacro": "cmd_xacro",
}
"""Subcommand -> the ``urdftk.cli`` module that registers it (a test keeps this complete)."""


def _build_parser(only: str | None = None) -> argparse.ArgumentParser:
    """Build the parser; with ``only``, register just the module of that subcommand (fast start)."""
    import importlib

    parser_class = _parser_class()
    parser = parser_class(
        prog="urdftk",
        description="Robot descriptions, kinematics and frames without ROS.",
    )
    from urdftk import __version__

    parser.add_argument("--version", action="version", version=f"urdftk {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", parser_class=parser_class)
    sub.required = True
    modules = [COMMANDS[only]] if only in COMMANDS else sorted(set(COMMANDS.values()))
    for name in modules:
        importlib.import_module(f"{__name__}.{name}").register(sub)
    return parser


def _is_user_error(exc: BaseException) -> bool:
    from urdftk.errors import UrdftkError

    if isinstance(exc, (UrdftkError, OSError, ValueError)):
        return True
    tf_mod = sys.modules.get("tf")
    root = getattr(tf_mod, "TransformException", None) if tf_mod else None
    return root is not None and isinstance(exc, root)


def main(argv: Sequence[str] | None = None) -> int:
    """Run the ``urdftk`` command line.

    Args:
        argv: Arguments without the program name; ``sys.argv[1:]`` when None.

    Returns:
        The exit status: 0 success, 1 findings (``check``), 2 bad input or failure.
    """
    argv = list(sys.argv[1:] if argv is None else argv)
    args = None
    if argv and argv[0] == "xacro":  # the common forms skip argparse (start-up time)
        from urdftk.cli.cmd_xacro import quick_args

        args = quick_args(argv[1:])
    if args is None:
        args = _build_parser(argv[0] if argv else None).parse_args(argv)
    try:
        return int(args.func(args) or 0)
    except KeyboardInterrupt:
        return 130
    except BrokenPipeError:
        import contextlib

        with contextlib.suppress(OSError):
            sys.stdout = open(os.devnull, "w")  # noqa: SIM115 - silence the flush at exit
        return 0
    except Exception as exc:  # the CLI edge: one line, never a traceback
        if os.environ.get("URDFTK_DEBUG"):
            raise
        text = " ".join(str(exc).split()) or type(exc).__name__
        if not _is_user_error(exc):
            text = f"internal error ({type(exc).__name__}): {text} (set URDFTK_DEBUG=1 for a traceback)"
        print(f"urdftk {args.command}: error: {text}", file=sys.stderr)
        return 2
