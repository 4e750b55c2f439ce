"""Macro definitions: parameter parsing and name resolution through namespaces."""

from __future__ import annotations

import re
from functools import lru_cache

from urdftk.xacro._share import mark_static
from urdftk.xacro._tree import Element

TYPE_CHECKING = False
if TYPE_CHECKING:
    from typing import Any

__all__ = ["Macro", "first_element", "parse_macro_arg", "parse_params", "resolve_macro", "tree_size"]


@lru_cache(maxsize=1)
def _arg_re() -> re.Pattern[str]:
    # param, optional ':=' or '=', optional '^' or '^|', default: ${...}, $(...), quoted or bare words
    return re.compile(
        r"^\s*([^\s:=]+?)\s*:?=\s*(\^\|?)?"
        r"(\$\{.*?\}|\$\(.*?\)|(?:'.*?'|\".*?\"|[^\s'\"]+)+|)"
        r"(?:\s+|$)(.*)"
    )


def parse_macro_arg(s: str) -> tuple[str, tuple[str | None, str | None] | None, str]:
    """Parse the first parameter spec of a ``params`` string.

    Args:
        s: E.g. ``"prefix:=^|'' *origin"``.

    Returns:
        ``(name, (forward, default) or None, rest)``: ``forward`` is the name itself after ``^``,
        ``default`` the default text (None when empty); the middle item is None when the spec
        has no ``=`` at all.
    """
    m = _arg_re().match(s) if "=" in s else None
    if m:
        name, forward, default, rest = m.groups()
        return name, (name if forward else None, default or None), rest
    words = s.lstrip().split(None, 1)
    return words[0], None, words[1] if len(words) > 1 else ""


@lru_cache(maxsize=4096)
def parse_params(params: str) -> tuple[tuple[str, ...], dict[str, tuple[str | None, str | None]]]:
    """Parse a whole ``params`` attribute into the ordered names and their defaults."""
    names: list[str] = []
    defaults: dict[str, tuple[str | None, str | None]] = {}
    while params:
        name, value, params = parse_macro_arg(params)
        names.append(name)
        if value is not None:
            defaults[name] = value
    return tuple(names), defaults


@lru_cache(maxsize=4096)
def _signature(params: str) -> tuple[Any, ...]:
    """What a call needs of ``params``: names, defaults, their set, block and other names, dups."""
    names, defaults = parse_params(params)
    blocks = tuple([p for p in names if p[0] == "*"])
    plain = tuple([p for p in names if p[0] != "*"])
    return names, defaults, frozenset(names), blocks, plain, len(set(names)) != len(names)


def tree_size(el: Element) -> int:
    """Count the nodes below and including ``el`` (the cost of one copy)."""
    n = 1
    for c in el.children:
        n += tree_size(c) if c.__class__ is Element else 1
    return n


class Macro:
    """A macro definition.

    Attributes:
        name: The name as written in the ``name`` attribute.
        body: The ``xacro:macro`` element (copied at every call).
        params: Parameter names in order (``*block`` and ``**block`` included).
        defaults: name -> (forward, default).
        param_set: The parameter names as a set.
        blocks: The block parameters (``*name``, ``**name``) in order.
        plain: The other parameters in order.
        dups: Whether a parameter name is listed more than once.
        has_ns: Whether the ``xacro:macro`` element declares namespaces (imported at each call).
        def_file: The file being processed when the macro was defined (None for a string).
        size: Node count of the body.
    """

    __slots__ = (
        "_size",
        "blocks",
        "body",
        "def_file",
        "defaults",
        "dups",
        "has_ns",
        "name",
        "param_set",
        "params",
        "plain",
    )

    def __init__(self, name: str, body: Element, params: str, def_file: str | None):
        self.name = name
        self.body = body
        self.params, self.defaults, self.param_set, self.blocks, self.plain, self.dups = _signature(params)
        self.has_ns = "xmlns:" in " ".join(body.attrs)  # namespaces to import at each call
        self.def_file = def_file
        self._size: int | None = None

    @property
    def size(self) -> int:
        """Node count of the body; the body is marked for sharing on first use (many are never called)."""
        if self._size is None:
            self._size = mark_static(self.body)
        return self._size


def resolve_macro(fullname: str, macros: Any, symbols: Any) -> tuple[Any, Any, Any]:
    """Find a macro by name, or by ``ns.name`` through included namespaces.

    Returns:
        The macro table and symbol table it lives in, and the macro.

    Raises:
        KeyError: No such macro.
    """
    try:
        return macros, symbols, macros[fullname]
    except KeyError:
        parts = fullname.split(".")
        name = parts.pop()
        if not parts:
            raise
        for ns in parts:
            macros = macros[ns]
            symbols = symbols[ns]
        return macros, symbols, macros[name]


def first_element(children: list, start: int = 0) -> tuple[int, Element | None]:
    """Return the index and element of the first element child at or after ``start``."""
    for i in range(start, len(children)):
        if children[i].__class__ is Element:
            return i, children[i]
    return len(children), None
