"""Per-expansion services: text and expression evaluation, files, packages, args and messages."""

from __future__ import annotations

import os
import sys
from functools import lru_cache
from keyword import iskeyword
from pathlib import Path

from urdftk.errors import PackageNotFound, XacroError, close_names
from urdftk.xacro._eval import REFUSED_NAMES, SandboxError, compile_expr
from urdftk.xacro._lexer import EXPR, SUBST, TEXT, tokenize
from urdftk.xacro._scope import Scope

TYPE_CHECKING = False
if TYPE_CHECKING:
    from typing import Any, TextIO

    from urdftk.xacro._subst import EvalScope

__all__ = ["MAX_TEXT", "Context", "IncludeIOError", "XacroPackageNotFound"]

MAX_TEXT = 20_000_000  # characters in one evaluated value


_NAME = 3  # a ${...} that is one name: (kind, name, source)
_CODE = 4  # a ${...} compiled to code: (kind, code, source)


@lru_cache(maxsize=16384)
def _text_plan(text: str) -> tuple[tuple[int, Any, str], ...]:
    """``text``'s tokens as ``(kind, payload, source)``: TEXT, SUBST, _NAME, _CODE, or EXPR.

    An expression that contains ``$`` or that fails to compile stays EXPR: :meth:`eval_expr`
    evaluates it in turn, so its error comes after the effects of the tokens before it.
    """
    out: list[tuple[int, Any, str]] = []
    for kind, s in tokenize(text):
        if kind == EXPR and "$" not in s:
            try:
                name, code = _plan(s)
            except Exception:
                out.append((EXPR, None, s))
                continue
            out.append((_NAME, name, s) if name is not None else (_CODE, code, s))
        else:
            out.append((kind, s, s))
    return tuple(out)


@lru_cache(maxsize=16384)
def _plan(expr: str) -> tuple[str | None, Any]:
    """(name, None) for a bare name, else (None, compiled code); sandbox refusals raise."""
    e = expr.strip()
    if e.isidentifier() and not iskeyword(e) and (e[0] != "_" or e == "_"):
        return e, None
    return None, compile_expr(e)


def _read_bytes(path: str) -> bytes:
    """A file's bytes (plain os calls: much cheaper than ``open()`` for many small files)."""
    fd = os.open(path, os.O_RDONLY)
    try:
        chunks = []
        while True:
            chunk = os.read(fd, 1 << 20)
            if not chunk:
                return b"".join(chunks)
            chunks.append(chunk)
    finally:
        os.close(fd)


class IncludeIOError(XacroError):
    """A file could not be read (an optional include skips it)."""


class XacroPackageNotFound(XacroError, PackageNotFound):
    """``$(find pkg)`` names an unknown package (both a XacroError and a PackageNotFound)."""


def _expr_error(exc: Exception, expr: str, scope: Any) -> XacroError:
    if isinstance(exc, NameError):
        name = getattr(exc, "name", None)
        if name in REFUSED_NAMES:
            return SandboxError(
                f"refused by the xacro sandbox: '{name}' is not available (in expression '{expr}')"
            )
        msg = str(exc)
        if name and isinstance(scope, Scope):
            hint = close_names(name, scope.visible_names())
            if hint:
                msg += f" (did you mean {', '.join(map(repr, hint))}?)"
        return XacroError(f"{msg} when evaluating expression '{expr}'")
    if isinstance(exc, SyntaxError):
        return XacroError(f"invalid syntax ({exc.msg}) when evaluating expression '{expr}'")
    return XacroError(f"{type(exc).__name__}: {exc} when evaluating expression '{expr}'")


class Context:
    """State and services of one expansion.

    Args:
        mappings: ``name:=value`` args (copied).
        package_paths: Extra folders for ``$(find)``.
        resolver: A :class:`urdftk.resources.PackageResolver` to use instead of a new one.
        stderr: Where warnings go (``sys.stderr`` when None).
        verbosity: 0 silences warnings.
        root_dir: Folder that relative file names are opened from (stock's ``--root-dir``).
    """

    def __init__(
        self,
        mappings: dict[str, str] | None = None,
        package_paths: Any = (),
        resolver: Any = None,
        stderr: TextIO | None = None,
        verbosity: int = 1,
        root_dir: str | None = None,
    ):
        self.args: dict[str, str] = dict(mappings or {})
        self.package_paths = tuple(package_paths or ())
        self.resolver = resolver
        self.stderr = stderr
        self.verbosity = verbosity
        self.root_dir = root_dir
        self.files: list[str | None] = []  # stock's file stack (names as stock forms them)
        self.include_sites: list[Any] = []  # the include element of each file after the first
        self.macro_stack: list[tuple[Any, Any]] = []  # (Macro, call element)
        self.includes: list[str] = []  # every file read after the input, in order
        self._eval_scope: EvalScope | None = None
        self._yaml: dict[str, Any] = {}  # yaml text -> loaded data (files without unit tags)
        self._found_text: dict[str, str] = {}  # "find pkg" -> the folder
        self.root: dict[str, Any] = {}

    # -- messages ---------------------------------------------------------------------------
    def _err(self) -> TextIO:
        return self.stderr if self.stderr is not None else sys.stderr

    def warn(self, message: str) -> None:
        """Print a warning and where it happened (unless verbosity is 0)."""
        if self.verbosity > 0:
            print(f"warning: {message}", file=self._err())
            self.print_location()

    def message(self, kind: str, text: str, location: bool) -> None:
        """``xacro.message/warning/error`` from an expression."""
        prefix = "" if kind == "message" else f"{kind}: "
        print(prefix + text, file=self._err())
        if location:
            self.print_location()

    def print_location(self) -> None:
        """Print the macro and include stack as stock xacro does."""
        out = self._err()
        msg = "when instantiating macro:"
        for m, _ in reversed(self.macro_stack):
            print(msg, m.body.attrs.get("name", m.name), f"({m.def_file or '???'})", file=out)
            msg = "instantiated from:"
        msg = "in file:" if self.macro_stack else "when processing file:"
        for f in reversed(self.files):
            print(msg, "string" if f is None else f, file=out)
            msg = "included from:"

    # -- files and packages -----------------------------------------------------------------
    def abs_filename(self, spec: str) -> str:
        """Make ``spec`` relative to the folder of the file being processed (stock's rule)."""
        if os.path.isabs(spec):
            return spec
        parent = self.files[-1] if self.files else None
        return os.path.join(os.path.dirname(parent) if parent else ".", spec)

    def open_path(self, name: str) -> str:
        """The path a file name is opened at (``root_dir`` applied)."""
        return os.path.join(self.root_dir, name) if self.root_dir else name

    def read_text(self, name: str) -> str:
        """Read a file as UTF-8 text; IncludeIOError when it cannot be read."""
        path = self.open_path(name)
        try:
            data = _read_bytes(path)
        except OSError as e:
            msg = f"{e.strerror or e}: {name}"
            folder = os.path.dirname(path) or "."
            try:
                hint = close_names(os.path.basename(path), os.listdir(folder))
            except OSError:
                hint = []
            if hint:
                msg += f" (did you mean {', '.join(map(repr, hint))} in {folder}?)"
            raise IncludeIOError(msg) from e
        try:
            return data.decode("utf-8")
        except UnicodeDecodeError as e:
            raise XacroError(f"{name}: not UTF-8 text ({e.reason} at byte {e.start})") from None

    def find(self, package: str) -> str:
        """``$(find pkg)``: the package folder, through urdftk's resolver."""
        if self.resolver is None:
            from urdftk.resources import PackageResolver

            first = next((f for f in self.files if f), None)
            self.resolver = PackageResolver(self.package_paths, source=first)
        try:
            return str(self.resolver.find(package))
        except PackageNotFound as e:
            raise XacroPackageNotFound(e.package, e.searched) from None

    def found_packages(self) -> dict[str, Path]:
        """Packages resolved during the expansion."""
        return self.resolver.found_packages() if self.resolver is not None else {}

    def dirname(self) -> str:
        """``$(dirname)``: absolute folder of the file being processed."""
        current = self.files[-1] if self.files else None
        if not current:
            raise XacroError(
                "Cannot substitute $(dirname): no file/directory information available (input is a string)"
            )
        return os.path.abspath(os.path.dirname(self.open_path(current)))

    def arg(self, name: str) -> str:
        """``xacro.arg(name)``."""
        try:
            return self.args[name]
        except KeyError:
            hint = close_names(name, self.args)
            extra = f" (did you mean {', '.join(map(repr, hint))}?)" if hint else ""
            raise XacroError(f"undefined xacro arg '{name}'{extra}") from None

    def load_yaml(self, filename: str) -> Any:
        """``xacro.load_yaml(file)``, relative to the file being processed."""
        from urdftk.xacro._yaml import UNITS, copy_data, load_yaml_text

        name = self.abs_filename(filename)
        text = self.read_text(name)
        self.files.append(name)
        try:
            if any(tag in text for tag in UNITS):  # unit tags evaluate expressions: load every time
                return load_yaml_text(text, self.eval_global, name)
            data = self._yaml.get(text)
            if data is None:  # plain data: parse once per expansion, hand out copies
                data = self._yaml[text] = load_yaml_text(text, self.eval_global, name)
            return copy_data(data)
        finally:
            self.files.pop()
            self.includes.append(name)

    # -- evaluation -------------------------------------------------------------------------
    def eval_text(self, text: str, scope: Any) -> Any:
        """Evaluate ``${}``/``$()`` in ``text``; one token gives a typed value, several give text."""
        if "$" not in text:
            return text
        steps = _text_plan(text)
        if len(steps) == 1:
            kind, x, s = steps[0]
            if kind >= _NAME:  # _NAME or _CODE: eval_expr, inlined
                try:
                    if kind == _NAME:
                        try:
                            value = scope[x]
                        except KeyError:
                            raise NameError(f"name '{x}' is not defined", name=x) from None
                    else:
                        value = eval(x, scope)
                except (XacroError, RecursionError):
                    raise
                except Exception as exc:
                    raise _expr_error(exc, s, scope) from None
                if value.__class__ is str and len(value) > MAX_TEXT:
                    raise XacroError(f"expression '{s}' gives text longer than {MAX_TEXT} characters")
                return value
            if kind == EXPR:
                return self.eval_expr(s, scope)
            if kind == SUBST:
                return self.eval_subst_text(s, scope)
            return s
        out = []
        s = ""
        try:
            for kind, x, s in steps:
                if kind == TEXT:
                    out.append(x)
                    continue
                if kind == _NAME:
                    try:
                        value = scope[x]
                    except KeyError:
                        raise NameError(f"name '{x}' is not defined", name=x) from None
                elif kind == _CODE:
                    value = eval(x, scope)
                elif kind == EXPR:
                    value = self.eval_expr(s, scope)
                else:
                    out.append(self.eval_subst_text(s, scope))
                    continue
                if value.__class__ is not str:
                    value = str(value)
                elif len(value) > MAX_TEXT:
                    raise XacroError(f"expression '{s}' gives text longer than {MAX_TEXT} characters")
                out.append(value)
        except (XacroError, RecursionError):
            raise
        except Exception as exc:
            raise _expr_error(exc, s, scope) from None
        result = "".join(out)
        if len(result) > MAX_TEXT:
            raise XacroError(f"evaluated text longer than {MAX_TEXT} characters (exponential expansion?)")
        return result

    def eval_expr(self, source: str, scope: Any) -> Any:
        """Evaluate the inside of ``${...}`` in ``scope``."""
        expr = source if "$" not in source else self.eval_text(source, scope)
        try:
            name, code = _plan(expr)
            if name is not None:
                try:
                    value = scope[name]
                except KeyError:
                    raise NameError(f"name '{name}' is not defined", name=name) from None
            else:
                value = eval(code, scope)
        except XacroError:
            raise
        except RecursionError:
            raise
        except Exception as exc:
            raise _expr_error(exc, source, scope) from None
        if value.__class__ is str and len(value) > MAX_TEXT:
            raise XacroError(f"expression '{source}' gives text longer than {MAX_TEXT} characters")
        return value

    def eval_global(self, text: str) -> Any:
        """Evaluate an expression with only the global symbols (yaml unit tags)."""
        scope = Scope(self.root, ctx=self)
        try:
            return self.eval_expr(text, scope)
        except XacroError as e:
            if "invalid syntax" in str(e):
                raise SyntaxError(str(e)) from None
            raise

    def eval_subst_text(self, inner: str, scope: Any) -> str:
        """Evaluate ``$(inner)``: ``$(cwd)`` or a substitution command."""
        if "$" not in inner:
            if inner[:5] == "find ":  # a package's folder is fixed for the expansion
                hit = self._found_text.get(inner)
                if hit is None:
                    from urdftk.xacro._subst import resolve

                    hit = self._found_text[inner] = resolve(self, "$(" + inner + ")")
                return hit
            if inner[:4] == "arg " and " " not in inner[4:]:
                value = self.args.get(inner[4:])
                if value.__class__ is str and "$(" not in value:  # (else: its $(find) is resolved below)
                    return value
        text = "$(" + str(self.eval_text(inner, scope)) + ")"
        if text == "$(cwd)":
            return os.path.abspath(self.root_dir or os.curdir)
        from urdftk.xacro._subst import resolve

        return resolve(self, text)

    def eval_subst(self, expr: str) -> Any:
        """``$(eval expr)`` in the sandbox, names being helper functions and the args."""
        if self._eval_scope is None:
            base = {
                k: self.root[k]
                for k in ("list", "dict", "map", "str", "float", "int", "len", "bool", "min", "max", "round")
            }
            base.update(
                {
                    k: self.root["python"][k]
                    for k in (
                        "abs",
                        "all",
                        "any",
                        "sum",
                        "sorted",
                        "range",
                        "zip",
                        "tuple",
                        "set",
                        "enumerate",
                        "reversed",
                    )
                }
            )
            for k in ("__xacro_getattr__", "__xacro_pow__", "__xacro_lshift__"):
                base[k] = self.root[k]
            from urdftk.xacro._subst import EvalScope

            self._eval_scope = EvalScope(self, base)
        scope = self._eval_scope
        try:
            code = compile_expr(expr.strip())
            if not dict.__contains__(scope, "__builtins__"):
                dict.__setitem__(scope, "__builtins__", {})
            return eval(code, scope)
        except XacroError:
            raise
        except Exception as exc:
            raise _expr_error(exc, f"$(eval {expr})", None) from None
