"""A small mutable XML tree with the node structure of ``xml.dom.minidom``, built with expat.

Stock xacro's output depends on exactly which text nodes exist (adjacent text is never merged
after parsing) and on attribute order, so the tree keeps both. Children are plain lists, which
makes splicing a macro expansion into its parent one C-level slice assignment.

Parsing never expands entities: a DOCTYPE or ENTITY declaration is an error.
"""

from __future__ import annotations

from pyexpat import ExpatError, ParserCreate, errors

from urdftk.errors import XacroError

__all__ = [
    "CData",
    "Comment",
    "Element",
    "PI",
    "Text",
    "XmlSyntaxError",
    "clone",
    "parse_xml",
]


class XmlSyntaxError(XacroError):
    """The text is not well-formed XML (or declares a DOCTYPE).

    Attributes:
        filename: The file that failed to parse (None for a string).
        line: 1-based line of the error.
        column: 1-based column of the error.
        reason: The parser's message without the location.
    """

    def __init__(self, reason: str, filename: str | None, line: int, column: int):
        self.reason = reason
        self.filename = filename
        self.line = line
        self.column = column
        where = f"{filename or '<string>'}:{line}:{column}"
        super().__init__(f"{where}: XML syntax error: {reason}")


class Element:
    """An element: qualified tag name, attributes in document order, child nodes."""

    __slots__ = ("attrs", "children", "file", "line", "tag")

    def __init__(self, tag: str, attrs: dict[str, str], line: int = 0, file: str | None = None):
        self.tag = tag
        self.attrs = attrs
        self.children: list = []
        self.line = line
        self.file = file

    def __repr__(self) -> str:
        return f"<Element {self.tag} at line {self.line}>"


class Text:
    """A text node; ``parent`` is only kept for the shared blank-line marker node."""

    __slots__ = ("data", "line", "parent")

    def __init__(self, data: str, line: int = 0):
        self.data = data
        self.line = line
        self.parent = None


class Comment:
    """A comment node."""

    __slots__ = ("data", "line")

    def __init__(self, data: str, line: int = 0):
        self.data = data
        self.line = line


class CData:
    """A CDATA section (kept as is; never evaluated)."""

    __slots__ = ("data",)

    def __init__(self, data: str):
        self.data = data


class PI:
    """A processing instruction."""

    __slots__ = ("data", "target")

    def __init__(self, target: str, data: str):
        self.target = target
        self.data = data


def clone(el: Element) -> Element:
    """Deep-copy an element (attribute dicts are shared: they are never mutated in place).

    Args:
        el: The element to copy.

    Returns:
        A new element whose subtree holds new node objects.
    """
    new = Element(el.tag, el.attrs, el.line, el.file)
    out = new.children
    for c in el.children:
        cls = c.__class__
        if cls is Text:
            out.append(Text(c.data, c.line))
        elif cls is Element:
            out.append(clone(c))
        elif cls is Comment:
            out.append(Comment(c.data, c.line))
        elif cls is CData:
            out.append(CData(c.data))
        else:
            out.append(PI(c.target, c.data))
    return new


class _Builder:
    """Expat callbacks that build the tree (text runs merged as minidom's builder does)."""

    def __init__(self, parser, filename: str | None):
        self.p = parser
        self.file = filename
        self.top: list = []  # document-level nodes
        self.stack: list = []
        self.cur = self.top
        self.cdata = False
        self.cdata_node: CData | None = None

    def start(self, name, attributes):
        attrs = {}
        if attributes:
            it = iter(attributes)
            for k in it:
                attrs[k] = next(it)
            if any(k.startswith("xmlns") for k in attrs):  # minidom lists namespace declarations first
                ns = {k: v for k, v in attrs.items() if k == "xmlns" or k.startswith("xmlns:")}
                ns.update((k, v) for k, v in attrs.items() if k not in ns)
                attrs = ns
        el = Element(name, attrs, self.p.CurrentLineNumber, self.file)
        self.cur.append(el)
        self.stack.append(self.cur)
        self.cur = el.children

    def end(self, name):
        self.cur = self.stack.pop()

    def chars(self, data):
        cur = self.cur
        if self.cdata:
            node = self.cdata_node
            if node is not None and cur and cur[-1] is node:
                node.data += data
            else:
                node = self.cdata_node = CData(data)
                cur.append(node)
            return
        if cur and cur[-1].__class__ is Text:
            cur[-1].data += data
        elif cur is not self.top:
            cur.append(Text(data, self.p.CurrentLineNumber))

    def comment(self, data):
        self.cur.append(Comment(data, self.p.CurrentLineNumber))

    def pi(self, target, data):
        self.cur.append(PI(target, data))

    def start_cdata(self):
        self.cdata = True
        self.cdata_node = None

    def end_cdata(self):
        self.cdata = False
        self.cdata_node = None

    def doctype(self, *args):
        raise XmlSyntaxError(
            "DOCTYPE declarations are not allowed (entities could read files or expand without bound)",
            self.file,
            self.p.CurrentLineNumber,
            self.p.CurrentColumnNumber + 1,
        )


def parse_xml(text: str | bytes, filename: str | None = None) -> tuple[list, Element]:
    """Parse a document.

    Args:
        text: The document (str, or bytes in the encoding it declares).
        filename: Recorded on every element, for error messages.

    Returns:
        The document-level nodes (comments, processing instructions, the root element) and the
        root element.

    Raises:
        XmlSyntaxError: The text is not well-formed, or declares a DOCTYPE/ENTITY.
    """
    p = ParserCreate()
    b = _Builder(p, filename)
    p.buffer_text = True
    p.ordered_attributes = True
    p.StartElementHandler = b.start
    p.EndElementHandler = b.end
    p.CharacterDataHandler = b.chars
    p.CommentHandler = b.comment
    p.ProcessingInstructionHandler = b.pi
    p.StartCdataSectionHandler = b.start_cdata
    p.EndCdataSectionHandler = b.end_cdata
    p.StartDoctypeDeclHandler = b.doctype
    p.EntityDeclHandler = b.doctype
    try:
        p.Parse(text, True)
    except ExpatError as e:
        raise XmlSyntaxError(errors.messages[e.code], filename, e.lineno, e.offset + 1) from None
    root = next((n for n in b.top if n.__class__ is Element), None)
    if root is None:  # pragma: no cover - expat reports "no element found" first
        raise XmlSyntaxError("no element found", filename, 1, 1)
    return b.top, root
