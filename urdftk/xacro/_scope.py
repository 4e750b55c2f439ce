"""Property scopes: nested tables with lazy evaluation, as in stock xacro.

A :class:`Scope` is a dict (so it can be the globals of ``eval``) whose lookups walk up to the
parent scopes and finally to the root: the read-only dict of global symbols. A property whose
value is text is stored unevaluated and evaluated at its first use, in the scope that defined it.
"""

from __future__ import annotations

from functools import lru_cache

from urdftk.errors import XacroError

TYPE_CHECKING = False
if TYPE_CHECKING:
    from typing import Any

__all__ = ["NameSpace", "Scope", "literal"]

_NO_BUILTINS: dict[str, Any] = {}  # eval() finds no builtins through a scope
_MISSING = object()
_FLOAT_WORDS = frozenset({"inf", "infinity", "nan"})
_WS = (" ", "\t", "\n", "\r")


def literal(value: Any) -> Any:
    """Convert a property value the way stock xacro does: quoted text, int, float, bool, or as is.

    ``'text'`` loses its quotes; text containing ``_`` stays text (Python would drop the
    underscores of ``1_000``).
    """
    if value.__class__ is not str:
        return value
    if len(value) <= 200:
        return _literal_text(value)
    return _convert(value)


@lru_cache(maxsize=8192)
def _literal_text(value: str) -> Any:
    return _convert(value)


def _convert(value: str) -> Any:
    n = len(value)
    if n >= 2 and value[0] == "'" and value[-1] == "'":
        return value[1:-1]
    if "_" in value:
        return value
    s = value.strip()
    if s and not any(w in s for w in _WS) and not (s.isalpha() and s.lower() not in _FLOAT_WORDS):
        try:
            return int(value)
        except ValueError:
            pass
        try:
            return float(value)
        except ValueError:
            pass
    if value == "true" or value == "True":
        return True
    if value == "false" or value == "False":
        return False
    return value


class Scope(dict):
    """A table of properties (or macros) chained to a parent table.

    Evaluated entries live in the dict itself, so hits are C-speed lookups (also from ``eval``);
    a miss goes through :meth:`__missing__` to the lazy entries, then to the parent.

    Args:
        parent: The enclosing scope, or a plain dict acting as the root (global symbols).
        ctx: Evaluates lazy values and reports warnings; inherited from the parent.
    """

    __slots__ = ("ctx", "lazy", "parent", "recursive", "root")

    def __init__(self, parent: dict | None = None, ctx: Any | None = None):
        dict.__setitem__(self, "__builtins__", _NO_BUILTINS)  # (dict.__new__ made it empty)
        if parent is None:
            parent = {}
        self.parent = parent
        if isinstance(parent, Scope):
            self.root = parent.root
            self.ctx = ctx if ctx is not None else parent.ctx
        else:
            self.root = parent
            self.ctx = ctx
        self.lazy: dict[str, str] = {}
        self.recursive: list[str] | tuple = ()  # names being evaluated (a list once there is one)

    def __missing__(self, key: str) -> Any:
        t = self
        root = self.root  # every chain ends at its root, the one parent that is not a Scope
        get = dict.get
        while True:  # up the chain in one call (deep macro nesting makes long chains)
            if t.lazy and key in t.lazy:
                return t._resolve(key)
            t = t.parent
            if t is root:
                return t[key]
            value = get(t, key, _MISSING)
            if value is not _MISSING:
                return value

    def _resolve(self, key: str) -> Any:
        if key in self.recursive:
            chain = " -> ".join([*self.recursive, key])
            raise XacroError(
                f"circular variable definition: {chain}\n"
                'Consider disabling lazy evaluation via lazy_eval="false"'
            )
        if not self.recursive:
            self.recursive = []
        self.recursive.append(key)  # type: ignore[union-attr]
        try:
            value = literal(self._ctx().eval_text(self.lazy[key], self))
        finally:
            self.recursive.remove(key)  # type: ignore[union-attr]
        self.lazy.pop(key, None)
        dict.__setitem__(self, key, value)
        return value

    def _ctx(self) -> Any:
        if self.ctx is None:
            from urdftk.xacro._processor import standalone_context

            self.ctx = standalone_context()
        return self.ctx

    def get(self, key: str, default: Any = None) -> Any:
        """Look ``key`` up through the parents; ``default`` when no scope has it."""
        try:
            return self[key]
        except KeyError:
            return default

    def setitem(self, key: str, value: Any, unevaluated: bool) -> None:
        """Store a property; text stays unevaluated (lazy) when ``unevaluated`` is true."""
        if key in self.root:
            self._ctx().warn(f"redefining global symbol: {key}")
        value = literal(value)
        if unevaluated and value.__class__ is str:
            self.lazy[key] = value
            dict.pop(self, key, None)
        else:
            dict.__setitem__(self, key, value)
            if self.lazy:
                self.lazy.pop(key, None)

    def __setitem__(self, key: str, value: Any) -> None:
        self.setitem(key, value, unevaluated=True)

    def __delitem__(self, key: str) -> None:
        p = self
        while p is not self.root:
            dict.pop(p, key, None)
            p.lazy.pop(key, None)
            p = p.parent
        if key in self.root:
            self._ctx().warn(f"Cannot remove global symbol: {key}")

    def __contains__(self, key: object) -> bool:
        t = self
        while isinstance(t, Scope):
            if dict.__contains__(t, key) or key in t.lazy:
                return True
            t = t.parent
        return key in t

    def top(self) -> Scope:
        """The outermost scope below the root (where ``scope="global"`` stores)."""
        p = self
        while p.parent is not p.root:
            p = p.parent
        return p

    def visible_names(self, blocks: bool = False) -> list[str]:
        """Every name visible from here (for "did you mean"), without internal names.

        Args:
            blocks: List block parameters (``*name``, ``**name``) instead of the other names.
        """
        names: dict[str, None] = {}
        t: Any = self
        while isinstance(t, Scope):
            names.update(dict.fromkeys(k for k in dict.keys(t) if isinstance(k, str)))
            names.update(dict.fromkeys(t.lazy))
            t = t.parent
        names.update(dict.fromkeys(k for k in t if isinstance(k, str)))
        if blocks:
            return [n for n in names if n.startswith("*")]
        return [n for n in names if not n.startswith("_") and not n.startswith("*")]

    def __repr__(self) -> str:
        return repr({k: v for k, v in dict.items(self) if k != "__builtins__"})


class NameSpace(Scope):
    """A scope reached by name (``math``, ``xacro``, an included file's ``ns``): ``ns.item``."""

    __slots__ = ()
