"""Substitution arguments: ``$(arg)``, ``$(find)``, ``$(env)``, ``$(optenv)``, ``$(dirname)``, ``$(eval)``.

Resolution follows roslaunch/stock xacro: the command words are collected, each ``$(...)`` is
replaced by its value, then a second pass resolves any ``$(find ...)`` the first pass produced.
``$(eval ...)`` runs in the expression sandbox with the args as names. ``$(find)`` uses
urdftk's ROS-free package resolution; ``$(dirname)`` gives the folder of the file being
processed (stock's never receives it).
"""

from __future__ import annotations

import math
import os

from urdftk.errors import XacroError, close_names

TYPE_CHECKING = False
if TYPE_CHECKING:
    from typing import Any

__all__ = ["COMMANDS", "EvalScope", "collect", "convert_auto", "resolve"]

COMMANDS = ("find", "env", "optenv", "dirname", "arg")


def collect(text: str) -> list[str]:
    """Return the insides of the ``$(...)`` groups of ``text`` (no nesting, no escapes)."""
    n = text.count("$(")
    if text.count("$") == n and text.count("(") == n:
        # every '$' and '(' opens a group: unless a group is left open before the next one
        # (an error, reported by the scan below), split instead of scanning
        segs = text.split("$(")[1:]
        ends = [seg.find(")") for seg in segs]
        if -1 not in ends[:-1]:
            return [seg[:end] for seg, end in zip(segs, ends, strict=True) if end > 0]
    out: list[str] = []
    buf: list[str] = []
    state = 0  # 0 outside, 1 after '$', 2 after '$(', 3 inside
    for c in text:
        if c == "$":
            if state == 0:
                state = 1
            elif state != 1:
                raise XacroError(f'Dollar signs "$" cannot be inside of substitution args [{text}]')
        elif c == "(":
            if state == 1:
                state = 2
            elif state != 0:
                raise XacroError(f'Invalid left parenthesis "(" in substitution args [{text}]')
        elif c == ")":
            if state == 3:
                out.append("".join(buf))
                buf = []
            state = 0
        elif state == 1:
            state = 0
        elif state == 2:
            state = 3
        if state == 3:
            buf.append(c)
    return out


def convert_auto(value: str) -> Any:
    """Convert an arg value for ``$(eval)``: float if it has a '.', else int, bool, or text."""
    try:
        return float(value) if "." in value else int(value)
    except ValueError:
        pass
    low = value.lower()
    if low == "true":
        return True
    if low == "false":
        return False
    return value


def _arg(ctx: Any, name: str) -> str:
    try:
        return ctx.args[name]
    except KeyError:
        hint = close_names(name, ctx.args)
        msg = f"Undefined substitution argument {name}"
        if hint:
            msg += f" (did you mean {', '.join(map(repr, hint))}?)"
        elif ctx.args:
            msg += f" (defined args: {', '.join(sorted(ctx.args))})"
        raise XacroError(
            msg + f'; pass it as {name}:=VALUE or declare <xacro:arg name="{name}" default="..."/>'
        ) from None


def _env(name: str) -> str:
    try:
        return os.environ[name]
    except KeyError:
        raise XacroError(f"environment variable {name} is not set") from None


def _one(cmd: str, args: list[str], a: str) -> str:
    if len(args) != 1:
        raise XacroError(f"$({cmd} ...) takes exactly one argument [{a}]")
    return args[0]


def _pass(ctx: Any, text: str, only_find: bool) -> str:
    resolved = text
    for a in collect(text):
        words = [w for w in a.split(" ") if w]
        if not words or words[0] not in COMMANDS:
            raise XacroError(f"Unknown substitution command [{a}]. Valid commands are {list(COMMANDS)}")
        cmd, args = words[0], words[1:]
        if only_find and cmd != "find":
            continue
        if cmd == "arg":
            value = _arg(ctx, _one(cmd, args, a))
        elif cmd == "find":
            value = ctx.find(_one(cmd, args, a))
        elif cmd == "env":
            value = _env(_one(cmd, args, a))
        elif cmd == "optenv":
            if not args:
                raise XacroError(f"$(optenv var) must specify an environment variable [{a}]")
            value = os.environ.get(args[0], " ".join(args[1:]))
        else:
            value = ctx.dirname()
        resolved = resolved.replace(f"$({a})", value)
    return resolved


def resolve(ctx: Any, text: str) -> str:
    """Resolve the substitution args in ``text`` (a whole ``$(...)`` group).

    Args:
        ctx: The expansion (args, package resolution, current file, sandboxed eval).
        text: E.g. ``$(find pkg)`` or ``$(eval 1 + 1)``.

    Returns:
        The resolved text.
    """
    if text.startswith("$(eval ") and text.endswith(")"):
        return str(ctx.eval_subst(text[7:-1]))
    if not text:
        return text
    return _pass(ctx, _pass(ctx, text, False), True)


class EvalScope(dict):
    """Names inside ``$(eval)``: helper functions and math first, then the args (auto-typed)."""

    __slots__ = ("ctx", "funcs")

    def __init__(self, ctx: Any, base: dict[str, Any]):
        dict.__init__(self)
        self.ctx = ctx
        funcs = dict(base)
        funcs.update({k: v for k, v in vars(math).items() if not k.startswith("_")})
        funcs.update(
            {
                "true": True,
                "false": False,
                "True": True,
                "False": False,
                "arg": lambda name: convert_auto(_arg(ctx, name)),
                "dirname": ctx.dirname,
                "env": _env,
                "optenv": lambda name, default="": os.environ.get(name, default),
                "find": ctx.find,
            }
        )
        self.funcs = funcs

    def __getitem__(self, key: str) -> Any:
        try:
            return self.funcs[key]
        except KeyError:
            return convert_auto(self.ctx.args[key])
