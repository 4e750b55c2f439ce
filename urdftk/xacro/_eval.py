"""The expression sandbox: ``${...}``, ``$(eval ...)`` and yaml unit tags are evaluated here.

Expressions are parsed with :mod:`ast` and checked against a whitelist before they are compiled:

* allowed: literals, arithmetic, comparisons, boolean and conditional expressions, indexing and
  slicing, comprehensions, lambdas, f-strings, calls;
* refused: any name, attribute, keyword or parameter starting with ``_`` (except the name ``_``
  itself), the walrus operator and ``yield``;
* every attribute access is rewritten into a checked lookup that only reaches the public
  attributes of plain values (str, numbers, list, tuple, dict, set, loaded yaml) and the entries
  of xacro namespaces (``math.pi``, ``xacro.load_yaml``, an included file's ``ns``); functions,
  classes, generators, frames and modules expose nothing;
* ``str.format``/``format_map`` refuse attribute access inside the format string
  (``"{0.__class__}"``), and ``**``/``<<`` refuse results that would exhaust memory.

Names resolve through the scope mapping given at evaluation time; its ``__builtins__`` entry is
an empty dict, so nothing outside the exposed symbols is reachable. Compiled code is cached.
"""

from __future__ import annotations

import _string
import ast
from functools import lru_cache
from types import CodeType
from typing import Any

from urdftk.errors import XacroError

__all__ = [
    "GETATTR",
    "POW",
    "REFUSED_NAMES",
    "SandboxError",
    "compile_expr",
    "guarded_getattr",
]

GETATTR = "__xacro_getattr__"
POW = "__xacro_pow__"
LSHIFT = "__xacro_lshift__"

#: Names that give access to the interpreter; never exposed, named in the refusal message.
REFUSED_NAMES = frozenset(
    [
        "getattr",
        "setattr",
        "delattr",
        "hasattr",
        "vars",
        "globals",
        "locals",
        "open",
        "eval",
        "exec",
        "compile",
        "breakpoint",
        "input",
        "dir",
        "help",
        "memoryview",
        "object",
        "super",
        "classmethod",
        "staticmethod",
        "property",
        "exit",
        "quit",
    ]
)

_MAX_POW_BITS = 1 << 16


class SandboxError(XacroError):
    """An expression tried to reach something the sandbox does not expose."""


_ALLOWED = frozenset(
    {
        ast.Expression,
        ast.BoolOp,
        ast.BinOp,
        ast.UnaryOp,
        ast.Lambda,
        ast.IfExp,
        ast.Dict,
        ast.Set,
        ast.ListComp,
        ast.SetComp,
        ast.DictComp,
        ast.GeneratorExp,
        ast.Compare,
        ast.Call,
        ast.keyword,
        ast.FormattedValue,
        ast.JoinedStr,
        ast.Constant,
        ast.Attribute,
        ast.Subscript,
        ast.Starred,
        ast.Name,
        ast.List,
        ast.Tuple,
        ast.Slice,
        ast.comprehension,
        ast.arguments,
        ast.arg,
        ast.Load,
        ast.Store,
        ast.operator,
        ast.unaryop,
        ast.cmpop,
        ast.boolop,
    }
)


def _refuse(what: str) -> SandboxError:
    return SandboxError(f"refused by the xacro sandbox: {what}")


def _check_name(name: str | None, kind: str) -> None:
    if name and name.startswith("_") and name != "_":
        raise _refuse(f"{kind} '{name}' (names starting with '_' are not reachable)")


class _Rewrite(ast.NodeTransformer):
    """Validate every node; route attribute access, ``**`` and ``<<`` through checked helpers."""

    def generic_visit(self, node: ast.AST) -> ast.AST:
        cls = type(node)
        if cls not in _ALLOWED and not isinstance(node, (ast.operator, ast.unaryop, ast.cmpop, ast.boolop)):
            raise _refuse(f"{cls.__name__} expressions are not allowed")
        return super().generic_visit(node)

    def visit_Name(self, node: ast.Name) -> ast.AST:
        _check_name(node.id, "name")
        return node

    def visit_arg(self, node: ast.arg) -> ast.AST:
        _check_name(node.arg, "parameter")
        return node

    def visit_keyword(self, node: ast.keyword) -> ast.AST:
        _check_name(node.arg, "keyword")
        return self.generic_visit(node)

    def visit_Attribute(self, node: ast.Attribute) -> ast.AST:
        value = self.visit(node.value)  # report the first offending name in reading order
        _check_name(node.attr, "attribute")
        if not isinstance(node.ctx, ast.Load):
            raise _refuse(f"assignment to attribute '{node.attr}'")
        call = ast.Call(
            func=ast.Name(id=GETATTR, ctx=ast.Load()),
            args=[value, ast.Constant(value=node.attr)],
            keywords=[],
        )
        return ast.copy_location(call, node)

    def visit_BinOp(self, node: ast.BinOp) -> ast.AST:
        self.generic_visit(node)
        helper = POW if isinstance(node.op, ast.Pow) else LSHIFT if isinstance(node.op, ast.LShift) else None
        if helper is None:
            return node
        call = ast.Call(func=ast.Name(id=helper, ctx=ast.Load()), args=[node.left, node.right], keywords=[])
        return ast.copy_location(call, node)


@lru_cache(maxsize=8192)
def compile_expr(text: str) -> CodeType:
    """Validate and compile one expression (cached).

    Args:
        text: Python expression source, already stripped.

    Returns:
        A code object for ``eval(code, scope)``.

    Raises:
        SyntaxError: The text is not an expression.
        SandboxError: The expression uses something the sandbox refuses.
    """
    tree = ast.parse(text, "<expression>", "eval")
    tree = _Rewrite().visit(tree)
    ast.fix_missing_locations(tree)
    return compile(tree, "<expression>", "eval")


def _check_format(fmt: Any) -> None:
    if not isinstance(fmt, str):
        return
    for _, field, spec, _ in _string.formatter_parser(fmt):
        if field:
            _, rest = _string.formatter_field_name_split(field)
            if any(is_attr for is_attr, _ in rest):
                raise _refuse(f"attribute access inside a format string: '{{{field}}}'")
        if spec:
            _check_format(spec)


class _SafeFormat:
    """``str.format``/``format_map`` that refuse ``{0.attr}`` fields."""

    __slots__ = ("bound", "fmt")

    def __init__(self, fmt: str | None, bound):
        self.fmt = fmt
        self.bound = bound

    def __call__(self, *args, **kwargs):
        if self.fmt is None:  # unbound: str.format(fmt, ...)
            if args:
                _check_format(args[0])
        else:
            _check_format(self.fmt)
        return self.bound(*args, **kwargs)


def _plain_types() -> tuple[type, ...]:
    return (str, int, float, bool, complex, list, tuple, dict, set, frozenset, type(None), range, slice)


_PLAIN = frozenset(_plain_types())


def guarded_getattr(obj: Any, name: str, namespaces: tuple[type, ...], wrappers: tuple[type, ...]) -> Any:
    """Resolve ``obj.name`` inside the sandbox.

    Args:
        obj: The object.
        name: The attribute (never starts with ``_``: the compiler refuses that).
        namespaces: Classes whose attribute access means item lookup (xacro namespaces).
        wrappers: Further value classes whose public attributes are allowed (loaded yaml).

    Raises:
        SandboxError: ``obj`` is not a plain value, or ``name`` is refused.
        NameError: A namespace has no entry ``name``.
    """
    cls = type(obj)
    if isinstance(obj, namespaces):
        if name in REFUSED_NAMES:
            raise _refuse(f"'{name}' is not available")
        try:
            return obj[name]
        except KeyError:
            raise NameError(f"name '{name}' is not defined") from None
    if cls in _PLAIN or isinstance(obj, wrappers):
        if name in ("format", "format_map") and cls is str:
            return _SafeFormat(obj, getattr(obj, name))
        return getattr(obj, name)
    if isinstance(obj, type) and obj in _PLAIN and name in vars(obj):
        if name in ("format", "format_map") and obj is str:
            return _SafeFormat(None, getattr(obj, name))
        return getattr(obj, name)
    raise _refuse(f"attribute '{name}' of {cls.__name__} objects")


def guarded_pow(a: Any, b: Any) -> Any:
    """``a ** b`` refusing integer results too large to compute."""
    if type(a) is int and type(b) is int and b > 0 and abs(a) > 1 and a.bit_length() * b > _MAX_POW_BITS:
        raise _refuse(f"{a} ** {b} is too large")
    return a**b


def guarded_lshift(a: Any, b: Any) -> Any:
    """``a << b`` refusing results too large to compute."""
    if type(b) is int and b > _MAX_POW_BITS:
        raise _refuse(f"<< {b} is too large")
    return a << b


def safe_type(obj: Any) -> type:
    """One-argument ``type()`` that never hands out the metaclass ``type`` itself."""
    t = type(obj)
    if t is type:
        raise _refuse("type() of a class")
    return t
