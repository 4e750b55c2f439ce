"""Pretty-printing byte-identical to stock xacro (minidom ``toprettyxml(indent='  ')`` with its fixes).

The rules, which the output of every ROS tool depends on:

* attributes are sorted by name; ``&``, ``<``, ``"`` and ``>`` are escaped in text and attributes;
* an element whose only child is one text node is printed on one line, text verbatim;
* otherwise whitespace-only text nodes are dropped and every other child goes on its own
  indented line (a text node keeps its own leading and trailing whitespace);
* CDATA sections are printed without indentation or newline.
"""

from __future__ import annotations

from urdftk.errors import XacroError
from urdftk.xacro._tree import PI, CData, Comment, Element, Text

__all__ = ["banner", "write_document"]


def _esc(s: str) -> str:
    if "&" not in s and "<" not in s and '"' not in s and ">" not in s:
        return s
    return s.replace("&", "&amp;").replace("<", "&lt;").replace('"', "&quot;").replace(">", "&gt;")


def _head(tag: str, attrs: dict[str, str]) -> str:
    """'<tag a="1" b="2"' with attributes sorted and escaped."""
    n = len(attrs)
    if n == 1:
        ((k, v),) = attrs.items()
        if "&" in v or "<" in v or '"' in v or ">" in v:
            v = _esc(v)
        return f'<{tag} {k}="{v}"'
    vals = "".join(attrs.values())
    if "&" in vals or "<" in vals or '"' in vals or ">" in vals:
        return "<" + tag + "".join([f' {k}="{_esc(attrs[k])}"' for k in sorted(attrs)])
    if n == 2:
        a, b = attrs
        if b < a:
            a, b = b, a
        return f'<{tag} {a}="{attrs[a]}" {b}="{attrs[b]}"'
    return "<" + tag + "".join([f' {k}="{attrs[k]}"' for k in sorted(attrs)])


def _element(el: Element, indent: str, out: list) -> None:
    tag = el.tag
    attrs = el.attrs
    head = indent + _head(tag, attrs) if attrs else indent + "<" + tag
    children = el.children
    if not children:
        out.append(head + "/>\n")
        return
    if len(children) == 1:
        c = children[0]
        cls = c.__class__
        if cls is str or cls is Text:
            if cls is Text:
                c = c.data
            if "&" in c or "<" in c or '"' in c or ">" in c:
                c = _esc(c)
            out.append(f"{head}>{c}</{tag}>\n")
            return
    out.append(head + ">\n")
    sub = indent + "  "
    for c in children:
        cls = c.__class__
        if cls is Element:
            kids = c.children
            if not kids:  # a leaf, inlined
                a = c.attrs
                n = len(a)
                if n == 1:
                    ((k, v),) = a.items()
                    if "&" in v or "<" in v or '"' in v or ">" in v:
                        v = _esc(v)
                    out.append(f'{sub}<{c.tag} {k}="{v}"/>\n')
                elif n == 2:
                    (k, v), (k2, v2) = a.items()
                    if k2 < k:
                        k, v, k2, v2 = k2, v2, k, v
                    if "&" in v or "<" in v or '"' in v or ">" in v:
                        v = _esc(v)
                    if "&" in v2 or "<" in v2 or '"' in v2 or ">" in v2:
                        v2 = _esc(v2)
                    out.append(f'{sub}<{c.tag} {k}="{v}" {k2}="{v2}"/>\n')
                else:
                    out.append(f"{sub}{_head(c.tag, a) if a else '<' + c.tag}/>\n")
            elif len(kids) == 1 and kids[0].__class__ is str:  # one text child, inlined
                a = c.attrs
                t = kids[0]
                if "&" in t or "<" in t or '"' in t or ">" in t:
                    t = _esc(t)
                ctag = c.tag
                out.append(f"{sub}{_head(ctag, a) if a else '<' + ctag}>{t}</{ctag}>\n")
            else:
                _element(c, sub, out)
        elif cls is str:
            if c and not c.isspace():
                out.append(sub + _esc(c) + "\n")
        elif cls is Text:
            if c.data and not c.data.isspace():
                out.append(sub + _esc(c.data) + "\n")
        else:
            _other(c, sub, out)
    out.append(f"{indent}</{tag}>\n")


def _other(node, indent: str, out: list) -> None:
    cls = node.__class__
    if cls is Comment:
        if "--" in node.data:
            raise XacroError(f"cannot write a comment containing '--': <!--{node.data[:60]}-->")
        out.append(f"{indent}<!--{node.data}-->\n")
    elif cls is CData:
        if "]]>" in node.data:
            raise XacroError("cannot write a CDATA section containing ']]>'")
        out.append(f"<![CDATA[{node.data}]]>")
    elif cls is PI:
        out.append(f"{indent}<?{node.target} {node.data}?>\n")


def banner(source_name: str) -> list[Comment]:
    """Return the four header comments stock xacro puts before the document.

    Args:
        source_name: The input file name as given on the command line.
    """
    shown = source_name
    while "--" in shown:
        shown = shown.replace("--", "-")
    rule = " " + "=" * 83 + " "
    return [
        Comment(rule),
        Comment(f" |    This document was autogenerated by xacro from {shown:<30} | "),
        Comment(f" |    EDITING THIS FILE BY HAND IS NOT RECOMMENDED  {'':<30} | "),
        Comment(rule),
    ]


def write_document(top: list) -> str:
    """Serialise document-level nodes (header comments, comments, the root element) as stock does.

    Args:
        top: The document's child nodes in order.

    Returns:
        The full text, starting with ``<?xml version="1.0" ?>``.
    """
    out = ['<?xml version="1.0" ?>\n']
    for node in top:
        if node.__class__ is Element:
            _element(node, "", out)
        elif node.__class__ is str:
            if node and not node.isspace():
                out.append(_esc(node) + "\n")
        else:
            _other(node, "", out)
    return "".join(out)
