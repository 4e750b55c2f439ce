"""The global symbols every expression sees: safe builtins, ``python.*``, ``math.*`` and ``xacro.*``.

The set matches stock xacro 2.1.1, minus what reaches the interpreter: ``python.vars`` is not
exposed and ``python.type`` only answers the one-argument question.
"""

from __future__ import annotations

import builtins
import math
from functools import lru_cache

from urdftk.xacro._eval import GETATTR, LSHIFT, POW, guarded_getattr, guarded_lshift, guarded_pow, safe_type
from urdftk.xacro._scope import NameSpace
from urdftk.xacro._yaml import YamlDict, YamlList

TYPE_CHECKING = False
if TYPE_CHECKING:
    from collections.abc import Callable
    from typing import Any

__all__ = ["make_root", "tokenize"]

_DIRECT = [
    "list",
    "dict",
    "map",
    "len",
    "str",
    "float",
    "int",
    "bool",
    "True",
    "False",
    "min",
    "max",
    "round",
]
_PYTHON = [
    *_DIRECT,
    "abs",
    "all",
    "any",
    "complex",
    "divmod",
    "enumerate",
    "filter",
    "frozenset",
    "hash",
    "isinstance",
    "issubclass",
    "ord",
    "repr",
    "reversed",
    "slice",
    "set",
    "sum",
    "tuple",
    "zip",
    "sorted",
    "range",
]


def tokenize(s: str, sep: str = ",; ", skip_empty: bool = True) -> list[str]:
    """Split ``s`` at any character of ``sep`` (``xacro.tokenize``)."""
    import re

    parts = re.split(f"[{sep}]", s)
    return [p for p in parts if p] if skip_empty else parts


def _deprecated(ctx: Any, f: Callable, name: str, ns: str) -> Callable:
    def wrapper(*args: Any, **kwargs: Any) -> Any:
        ctx.warn(f"Using {name}() directly is deprecated. Use {ns}.{name}() instead.")
        return f(*args, **kwargs)

    return wrapper


_YAML_DICT_ATTRS = frozenset(dir(YamlDict))


def _getattr(obj: Any, name: str) -> Any:
    if obj.__class__ is YamlDict and name not in _YAML_DICT_ATTRS:
        return YamlDict.__getattr__(obj, name)  # what getattr() ends in, without the detour
    return guarded_getattr(obj, name, (NameSpace,), (YamlDict, YamlList))


@lru_cache(maxsize=1)
def _tables() -> tuple[dict[str, Any], dict[str, Any], dict[str, Any]]:
    """The fixed parts of the root table (never modified: every expansion copies them)."""
    b = vars(builtins)
    python = {k: b[k] for k in _PYTHON}
    python["type"] = safe_type
    public = {k: v for k, v in vars(math).items() if not k.startswith("_")}
    return {k: b[k] for k in _DIRECT}, python, public


def make_root(ctx: Any) -> dict[str, Any]:
    """Build the root symbol table for one expansion.

    Args:
        ctx: The expansion, which receives messages and resolves files and args.

    Returns:
        A plain dict: the parent of every top-level scope.
    """
    direct, python_items, public = _tables()
    b = vars(builtins)
    root: dict[str, Any] = direct.copy()
    python = NameSpace()
    dict.update(python, python_items)
    for k in ("sorted", "range"):
        root[k] = _deprecated(ctx, b[k], k, "python")
    root["python"] = python
    mathns = NameSpace()
    dict.update(mathns, public)
    root["math"] = mathns
    root.update(public)

    def message_fn(kind: str) -> Callable[..., str]:
        def f(*args: Any, **kwargs: Any) -> str:
            location = kwargs.pop("print_location", kind in ("warning", "error"))
            ctx.message(kind, " ".join(str(a) for a in args), bool(location))
            return ""

        return f

    def fatal(*args: Any) -> None:
        from urdftk.errors import XacroError

        raise XacroError(" ".join(map(str, args)))

    def print_location(*args: Any, **kwargs: Any) -> str:
        ctx.print_location()
        return ""

    xacro = NameSpace()
    funcs = {
        "load_yaml": ctx.load_yaml,
        "abs_filename": ctx.abs_filename,
        "dotify": YamlDict,
    }
    dict.update(xacro, funcs)
    dict.update(
        xacro,
        {
            "arg": ctx.arg,
            "message": message_fn("message"),
            "warning": message_fn("warning"),
            "error": message_fn("error"),
            "print_location": print_location,
            "fatal": fatal,
            "tokenize": tokenize,
        },
    )
    for k, f in funcs.items():
        root[k] = _deprecated(ctx, f, k, "xacro")
    root["xacro"] = xacro
    root[GETATTR] = _getattr
    root[POW] = guarded_pow
    root[LSHIFT] = guarded_lshift
    return root
