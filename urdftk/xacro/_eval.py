"""The expression sandbox: ``${...}``, ``$(eval ...)`` and yaml unit tags are evaluated here.

Expressions are parsed to a syntax tree and checked against a whitelist before they are compiled:

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
from functools import lru_cache

from urdftk.errors import XacroError

TYPE_CHECKING = False
if TYPE_CHECKING:
    from types import CodeType
    from typing import Any

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
_ONLY_AST = 0x400  # ast.PyCF_ONLY_AST (the ast module itself is slow to import and not needed)

_ALLOWED_NAMES = [
    "Expression",
    "BoolOp",
    "BinOp",
    "UnaryOp",
    "Lambda",
    "IfExp",
    "Dict",
    "Set",
    "ListComp",
    "SetComp",
    "DictComp",
    "GeneratorExp",
    "Compare",
    "Call",
    "keyword",
    "FormattedValue",
    "JoinedStr",
    "Constant",
    "Attribute",
    "Subscript",
    "Starred",
    "Name",
    "List",
    "Tuple",
    "Slice",
    "comprehension",
    "arguments",
    "arg",
    "Load",
    "Store",
]

# The tokens of expressions that need no rewriting: names not starting with '_', decimal numbers,
# one-line strings without prefix or escapes, and the operators other than '.'.
_SIMPLE_TOKEN = (
    r"\s+|[A-Za-z][A-Za-z0-9_]*|\d+(?:\.\d*)?(?:[eE][+-]?\d+)?[jJ]?|\.\d+(?:[eE][+-]?\d+)?[jJ]?"
    r"""|(?<![A-Za-z0-9_])(?:'[^'\n\r]*'|"[^"\n\r]*")|[-+*/%@&|^~<>=!()\[\]{},:]"""
)
_NOT_SIMPLE = frozenset({"yield", "await", "async"})


class SandboxError(XacroError):
    """An expression tried to reach something the sandbox does not expose."""


def _refuse(what: str) -> SandboxError:
    return SandboxError(f"refused by the xacro sandbox: {what}")


def _check_name(name: str | None, kind: str) -> None:
    if name and name.startswith("_") and name != "_":
        raise _refuse(f"{kind} '{name}' (names starting with '_' are not reachable)")


@lru_cache(maxsize=1)
def _simple_tokens() -> Any:
    import re

    return re.compile(_SIMPLE_TOKEN).findall


def is_simple(text: str) -> bool:
    """Whether ``text`` surely has no attribute access, ``**``, ``<<``, f-string, or '_' name.

    Such an expression compiles to exactly the code the checked rewrite would give, so it needs
    no syntax tree. Whatever is doubtful answers False and takes the checked path.

    Args:
        text: Python expression source.
    """
    if not text.isascii() or "\\" in text or "**" in text or "<<" in text or ":=" in text:
        return False
    if "'''" in text or '"""' in text:
        return False
    tokens = _simple_tokens()(text)  # non-overlapping, left to right: a gap means an unknown character
    if sum(map(len, tokens)) != len(text):
        return False
    return _NOT_SIMPLE.isdisjoint(tokens)


class _Rewriter:
    """Validate every node; route attribute access, ``**`` and ``<<`` through checked helpers.

    Args:
        A: The ``_ast`` module.
    """

    def __init__(self, A: Any) -> None:
        self.A = A
        self.allowed = frozenset(getattr(A, n) for n in _ALLOWED_NAMES)
        self.ops = (A.operator, A.unaryop, A.cmpop, A.boolop)

    def _call(self, helper: str, args: list, like: Any) -> Any:
        A = self.A
        call = A.Call(func=A.Name(id=helper, ctx=A.Load()), args=args, keywords=[])
        for n in (call, call.func, *[a for a in args if not hasattr(a, "lineno")]):
            n.lineno, n.col_offset = like.lineno, like.col_offset
            n.end_lineno, n.end_col_offset = like.end_lineno, like.end_col_offset
        return call

    def visit(self, node: Any) -> Any:
        """Check ``node`` and its children (in reading order); return its replacement."""
        A = self.A
        cls = type(node)
        if cls is A.Name:
            _check_name(node.id, "name")
            return node
        if cls is A.arg:
            _check_name(node.arg, "parameter")
            return node
        if cls is A.keyword:
            _check_name(node.arg, "keyword")
        elif cls is A.Attribute:
            value = self.visit(node.value)  # report the first offending name in reading order
            _check_name(node.attr, "attribute")
            if not isinstance(node.ctx, A.Load):
                raise _refuse(f"assignment to attribute '{node.attr}'")
            return self._call(GETATTR, [value, A.Constant(value=node.attr)], node)
        if cls not in self.allowed and not isinstance(node, self.ops):
            raise _refuse(f"{cls.__name__} expressions are not allowed")
        AST = A.AST
        for field in node._fields:
            old = getattr(node, field, None)
            if isinstance(old, list):
                old[:] = [self.visit(v) if isinstance(v, AST) else v for v in old]
            elif isinstance(old, AST):
                setattr(node, field, self.visit(old))
        if cls is A.BinOp:
            op = type(node.op)
            helper = POW if op is A.Pow else LSHIFT if op is A.LShift else None
            if helper is not None:
                return self._call(helper, [node.left, node.right], node)
        return node


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
    if is_simple(text):
        return compile(text, "<expression>", "eval")
    import _ast

    tree = compile(text, "<expression>", "eval", _ONLY_AST)
    return compile(_Rewriter(_ast).visit(tree), "<expression>", "eval")


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
