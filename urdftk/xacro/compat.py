"""Stock xacro's Python API on top of urdftk's expander: switch scripts with one import.

``import urdftk.xacro.compat as xacro`` provides ``process_file`` (returns a minidom document),
``process_doc``, ``parse``, ``process``, ``XacroException``, ``Table``, ``open_output``, ``main``
and the helpers stock exposes. Stock keeps its processing state (``filestack``, ``macrostack``,
``all_includes``, ``verbosity``, ``root_dir``) in module globals that callers read and reset;
this module mirrors them for compatibility, so it is not thread-safe (use
:func:`urdftk.xacro.expand` for that).

Documents returned here print with stock's pretty-printing rules (``toprettyxml(indent='  ')``
gives stock's output) without changing ``xml.dom.minidom`` itself.
"""

from __future__ import annotations

import os
import sys
import xml.dom.minidom
from typing import Any
from xml.parsers.expat import ExpatError

from urdftk.errors import XacroError
from urdftk.xacro import compat_cli as cli
from urdftk.xacro._macros import parse_macro_arg, resolve_macro
from urdftk.xacro._processor import Expander, is_valid_name, standalone_context
from urdftk.xacro._processor import to_bool as get_boolean_value
from urdftk.xacro._scope import NameSpace, Scope
from urdftk.xacro._symbols import tokenize
from urdftk.xacro._tree import PI, CData, Comment, Element, Text, XmlSyntaxError, parse_xml

__all__ = [
    "NameSpace",
    "Table",
    "XacroException",
    "abs_filename_spec",
    "all_includes",
    "cli",
    "eval_text",
    "filestack",
    "get_boolean_value",
    "init_stacks",
    "is_valid_name",
    "load_yaml",
    "macrostack",
    "main",
    "open_output",
    "parse",
    "parse_macro_arg",
    "print_location",
    "process",
    "process_doc",
    "process_file",
    "resolve_macro",
    "root_dir",
    "substitution_args_context",
    "tokenize",
    "verbosity",
]

# Stock xacro's module-level state, mirrored for callers that read or reset it.
filestack: list[str | None] | None = None
macrostack: list[tuple[str, str | None]] | None = None
all_includes: list[str] = []
substitution_args_context: dict[str, Any] = {}
verbosity = 1
root_dir = os.curdir


class XacroException(XacroError):
    """Stock's exception: ``str()`` is ``msg``, then the wrapped exception, then ``suffix``."""

    def __init__(
        self, msg: Any = None, suffix: Any = None, exc: BaseException | None = None, macro: Any = None
    ):
        super().__init__(msg)
        self.suffix = suffix
        self.exc = exc
        self.macros = [] if macro is None else [macro]

    def __str__(self) -> str:
        items = [self.args[0] if self.args else None, self.exc, self.suffix]
        return " ".join(s for s in (str(e) for e in items) if s not in ("", "None"))


class Table(Scope):
    """Stock's property table (a :class:`Scope`); ``_setitem`` keeps stock's spelling."""

    __slots__ = ()

    def _setitem(self, key: str, value: Any, unevaluated: bool) -> None:
        self.setitem(key, value, unevaluated)


def init_stacks(file: str | None) -> None:
    """Reset the file and macro stacks (stock API)."""
    global filestack, macrostack
    filestack = [file]
    macrostack = []


def abs_filename_spec(filename_spec: str) -> str:
    """Prefix a relative name with the folder of the file being processed (stock's rule)."""
    if os.path.isabs(filename_spec):
        return filename_spec
    parent = filestack[-1] if filestack else None
    return os.path.join(os.path.dirname(parent) if parent else ".", filename_spec)


def load_yaml(filename: str) -> Any:
    """``xacro.load_yaml`` outside an expansion (relative to the current file or '.')."""
    ctx = standalone_context()
    ctx.files = [filestack[-1] if filestack else None]
    result = ctx.load_yaml(filename)
    all_includes.extend(ctx.includes)
    return result


def eval_text(text: str, symbols: Any) -> Any:
    """Evaluate ``${}`` and ``$()`` in ``text`` with ``symbols`` (a :class:`Table`)."""
    ctx = symbols.ctx if isinstance(symbols, Scope) and symbols.ctx is not None else standalone_context()
    return ctx.eval_text(text, symbols)


def print_location() -> None:
    """Print the macro and file stack of the last error (stock format) to stderr."""
    msg = "when instantiating macro:"
    for name, file in reversed(macrostack or []):
        print(msg, name, f"({file or '???'})", file=sys.stderr)
        msg = "instantiated from:"
    msg = "in file:" if macrostack else "when processing file:"
    for f in reversed(filestack or []):
        print(msg, "string" if f is None else f, file=sys.stderr)
        msg = "included from:"


# -- minidom <-> urdftk tree -------------------------------------------------------------------
def _from_dom(node: Any, filename: str | None) -> Any:
    t = node.nodeType
    if t == node.ELEMENT_NODE:
        el = Element(node.tagName, dict(node.attributes.items()), 0, filename)
        el.children = [_from_dom(c, filename) for c in node.childNodes]
        return el
    if t == node.TEXT_NODE:
        return node.data
    if t == node.CDATA_SECTION_NODE:
        return CData(node.data)
    if t == node.COMMENT_NODE:
        return Comment(node.data)
    if t == node.PROCESSING_INSTRUCTION_NODE:
        return PI(node.target, node.data)
    return None


def _to_dom(doc: Any, node: Any) -> Any:
    cls = node.__class__
    if cls is str:
        return doc.createTextNode(node)
    if cls is Element:
        el = doc.createElement(node.tag)
        for k, v in node.attrs.items():
            el.setAttribute(k, v)
        for c in node.children:
            el.appendChild(_to_dom(doc, c))
        return el
    if cls is Text:
        return doc.createTextNode(node.data)
    if cls is Comment:
        return doc.createComment(node.data)
    if cls is CData:
        return doc.createCDATASection(node.data)
    return doc.createProcessingInstruction(node.target, node.data)


def _escape(s: str) -> str:
    return s.replace("&", "&amp;").replace("<", "&lt;").replace('"', "&quot;").replace(">", "&gt;")


def _write_element(el: Any, writer: Any, indent: str, addindent: str, newl: str) -> None:
    writer.write(indent + "<" + el.tagName)
    attrs = dict(el.attributes.items())
    for name in sorted(attrs):
        writer.write(f' {name}="{_escape(attrs[name])}"')
    kids = el.childNodes
    if not kids:
        writer.write("/>" + newl)
        return
    if len(kids) == 1 and kids[0].nodeType == el.TEXT_NODE:
        writer.write(">" + _escape(kids[0].data) + f"</{el.tagName}>{newl}")
        return
    writer.write(">" + newl)
    for c in kids:
        if c.nodeType == el.TEXT_NODE and (not c.data or c.data.isspace()):
            continue
        if c.nodeType == el.ELEMENT_NODE:
            _write_element(c, writer, indent + addindent, addindent, newl)
        else:
            c.writexml(writer, indent + addindent, addindent, newl)
    writer.write(f"{indent}</{el.tagName}>{newl}")


class _Document(xml.dom.minidom.Document):
    """A minidom document that serialises elements with stock xacro's pretty-printing rules."""

    def writexml(self, writer, indent="", addindent="", newl="", encoding=None, standalone=None):
        decl = []
        if encoding:
            decl.append(f'encoding="{encoding}"')
        if standalone is not None:
            decl.append(f'standalone="{"yes" if standalone else "no"}"')
        writer.write(f'<?xml version="1.0" {" ".join(decl)}?>{newl}')
        for node in self.childNodes:
            if node.nodeType == node.ELEMENT_NODE:
                _write_element(node, writer, indent, addindent, newl)
            else:
                node.writexml(writer, indent, addindent, newl)


def _fill(doc: Any, top: list) -> Any:
    for c in list(doc.childNodes):
        doc.removeChild(c)
    for node in top:
        doc.appendChild(_to_dom(doc, node))
    return doc


def parse(inp: Any, filename: str | None = None) -> Any:
    """Parse text, a file object, or (``inp`` None) the file ``filename`` into a minidom document.

    Raises:
        XacroException: The file cannot be opened.
        xml.parsers.expat.ExpatError: The text is not well-formed XML (or declares a DOCTYPE).
    """
    if inp is None:
        try:
            with open(os.path.join(root_dir, filename)) as f:  # type: ignore[arg-type]
                inp = f.read()
        except OSError as e:
            if filestack:
                filestack.pop()
            raise XacroException(f"{e.strerror}: {e.filename}", exc=e) from None
    elif hasattr(inp, "read"):
        inp = inp.read()
    if not isinstance(inp, (str, bytes)):
        return inp
    try:
        top, _ = parse_xml(inp, filename)
    except XmlSyntaxError as e:
        raise ExpatError(f"{e.reason}: line {e.line}, column {e.column - 1}") from None
    return _fill(_Document(), top)


def process_doc(doc: Any, mappings: dict[str, str] | None = None, **kwargs: Any) -> None:
    """Expand a minidom document in place (stock API; the options of ``xacro.cli`` are accepted)."""
    global verbosity, filestack, macrostack
    verbosity = kwargs.get("verbosity", verbosity)
    if not filestack:
        init_stacks(None)
    assert filestack is not None
    name = filestack[-1]
    top = [n for n in (_from_dom(c, name) for c in doc.childNodes) if n is not None]
    root = next(n for n in top if n.__class__ is Element)
    ex = Expander(mappings, verbosity=verbosity if verbosity is not None else 1, root_dir=root_dir)
    substitution_args_context["arg"] = ex.args
    try:
        ex.process(top, root, name)
    except XacroError as e:
        filestack = list(getattr(e, "xacro_files", filestack))
        macrostack = list(getattr(e, "xacro_macros", []))
        all_includes.extend(ex.includes)
        if isinstance(e, XmlSyntaxError):
            raise ExpatError(f"{e.reason}: line {e.line}, column {e.column - 1}") from None
        raise XacroException(getattr(e, "message", str(e))) from e
    finally:
        substitution_args_context["arg"] = {}
    all_includes.extend(ex.includes)
    filestack = [name]
    macrostack = []
    _fill(doc, top)


def _banner(doc: Any, input_file_name: Any) -> None:
    from urdftk.xacro._output import banner

    first = doc.firstChild
    for c in banner(str(input_file_name)):
        doc.insertBefore(doc.createComment(c.data), first)


def process_file(input_file_name: Any, **kwargs: Any) -> Any:
    """Parse and expand a file; return the minidom document with stock's header comments."""
    init_stacks(input_file_name)
    doc = parse(None, os.fspath(input_file_name))
    process_doc(doc, **kwargs)
    _banner(doc, input_file_name)
    return doc


def open_output(output_filename: str | None) -> Any:
    """Open the output (stdout for None), creating its folder first (stock API)."""
    if output_filename is None:
        return sys.stdout
    folder = os.path.dirname(output_filename)
    if folder:
        os.makedirs(folder, exist_ok=True)
    try:
        return open(output_filename, "w")
    except OSError as e:
        raise XacroException("Failed to open output:", exc=e) from None


def _result_text(input_file_name: str, opts: dict[str, Any]) -> str:
    global root_dir
    if opts.get("root_dir"):
        root_dir = opts["root_dir"]
    doc = process_file(input_file_name, **opts)
    if opts.get("just_deps"):
        return " ".join(set(all_includes))
    return doc.toprettyxml(indent="  ")


def process(
    input_file_name: str,
    just_deps: bool = False,
    xacro_ns: bool = True,
    verbosity: int = 1,
    mappings: dict[str, str] | None = None,
) -> str:
    """Expand a file and return what stock ``xacro`` would print."""
    opts = {"output": None, "just_deps": just_deps, "xacro_ns": xacro_ns, "verbosity": verbosity}
    return _result_text(input_file_name, {**opts, "mappings": dict(mappings or {})})


def main(argv: list[str] | None = None) -> None:
    """The stock ``xacro`` command line (exit status 2 on errors, no partial output file)."""
    opts, input_file_name = cli.process_args(sys.argv[1:] if argv is None else argv)
    options = vars(opts)
    try:
        text = _result_text(input_file_name, options)  # type: ignore[arg-type]
        if opts.output:
            from urdftk._atomic import write_atomic

            folder = os.path.dirname(opts.output)
            if folder:
                os.makedirs(folder, exist_ok=True)
            write_atomic(opts.output, text)
        else:
            sys.stdout.write(text)
    except ExpatError as e:
        print(f"error: XML parsing error: {e}", file=sys.stderr)
        print_location()
        sys.exit(2)
    except (XacroError, OSError, ValueError) as e:
        print(f"error: {e}", file=sys.stderr)
        print_location()
        sys.exit(2)
