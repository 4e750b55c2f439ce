"""The sandbox's no-syntax-tree fast path must only accept expressions the checked rewrite leaves alone.

Oracle: Python's own parser (``ast``). An expression the fast path accepts must contain no
attribute access, f-string, walrus, yield/await, ``**``/``<<`` or name starting with '_', and
``compile_expr`` must give the same code as the checked path for every expression.
"""

from __future__ import annotations

import ast
import random
import warnings

import pytest

from urdftk.xacro._eval import SandboxError, _Rewriter, compile_expr, is_simple

ALPHABET = [
    "a", "b1", "x_y", "_", "__c", "1", "0", "1.", "5", ".5", "e", "e5", "j", "f", "b", "r", "rb",
    "'", '"', "'''", "(", ")", "[", "]", "{", "}", ",", ":", "=", "*", "**", "<", "<<", ".", "..",
    "+", "-", " ", "\n", "#", "\\", "lambda", "yield", "await", "if", "else", "for", "in", "not",
    "0x", "1e", "_1", "@", "~", "&", "|", "^", "/", "%", ";", "é", "'s'", "x.y",
]  # fmt: skip

FORBIDDEN = (ast.Attribute, ast.JoinedStr, ast.NamedExpr, ast.Yield, ast.YieldFrom, ast.Await)


def _bad_nodes(tree: ast.AST) -> list[ast.AST]:
    bad = []
    for n in ast.walk(tree):
        if isinstance(n, FORBIDDEN) or (isinstance(n, ast.BinOp) and isinstance(n.op, (ast.Pow, ast.LShift))):
            bad.append(n)
        name = n.id if isinstance(n, ast.Name) else n.arg if isinstance(n, (ast.arg, ast.keyword)) else None
        if name and name.startswith("_"):
            bad.append(n)
    return bad


def _checked(text: str):
    import _ast

    tree = compile(text, "<expression>", "eval", ast.PyCF_ONLY_AST)
    return compile(_Rewriter(_ast).visit(tree), "<expression>", "eval")


def _signature(code) -> list:
    out = [code.co_code, code.co_names, code.co_varnames]
    for c in code.co_consts:
        out.append(_signature(c) if hasattr(c, "co_code") else (type(c), c))
    return out


def test_fast_path_accepts_only_harmless_expressions():
    rng = random.Random(4)
    accepted = parsed = 0
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        for _ in range(60_000):
            text = "".join(rng.choice(ALPHABET) for _ in range(rng.randint(1, 8)))
            if not is_simple(text):
                continue
            accepted += 1
            try:
                tree = ast.parse(text, mode="eval")
            except (SyntaxError, ValueError):
                continue
            parsed += 1
            assert not _bad_nodes(tree), text
    assert accepted > 1000 and parsed > 200  # the sample exercised the fast path


@pytest.mark.parametrize(
    "text",
    [
        "a*2", "-pi/2", "x if y else z", "[i for i in range(3)]", "lambda x: x+1", "d['k'][0]",
        "1.5e-3+.5", "'a.b'", "f(*a)", "{1: 2}", "a.b", "x**2", "x<<3", "f'{x}'", "'x'.join(l)",
        "1 .real", "a1.b", "{**d}", "(lambda: 1)()", "x[1:2]",
    ],
)  # fmt: skip
def test_same_code_as_checked_path(text):
    assert _signature(compile_expr(text)) == _signature(_checked(text))


@pytest.mark.parametrize(
    "text", ["x.__class__", "_x", "a1.__dict__", "(y:=2)", "f(_k=1)", "lambda _a: 1", "1 .__class__"]
)
def test_refused_either_way(text):
    assert not is_simple(text)
    with pytest.raises(SandboxError):
        compile_expr(text)
