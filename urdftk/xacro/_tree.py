"""A small mutable XML tree with the node structure of ``xml.dom.minidom``, built with expat.

Stock xacro's output depends on exactly which text nodes exist (adjacent text is never merged
after parsing) and on attribute order, so the tree keeps both. Children are plain lists, which
makes splicing a macro expansion into its parent one C-level slice assignment. A text node is a
plain ``str`` in its parent's list (cheap to copy); :class:`Text` objects are only used for the
one node that must keep its identity (stock's shared blank node).

Parsing never expands entities: a DOCTYPE or ENTITY declaration is an error.
"""

from __future__ import annotations

from pyexpat import ExpatError, ParserCreate, errors

from urdftk.errors import XacroError

__all__ = [
    "PI",
    "CData",
    "Comment",
    "Element",
    "SourceName",
    "Text",
    "XmlSyntaxError",
    "line_of",
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
    """An element: qualified tag name, attributes in document order, child nodes.

    ``static`` marks a subtree of a macro body that evaluation cannot change (no ``$``, no xacro
    tag or attribute, no comment that could be evaluated): it is shared, not copied, and skipped.
    ``pure`` marks a subtree of a macro body without xacro tags or ``xacro:eval-comments``: its
    expansion only evaluates attributes and text, so it is copied in one go.
    ``fixed`` marks an element of a macro body whose children are all static (its attributes may
    not be): copies share its child list, and evaluation skips the children. ``shared`` marks
    every element of a macro body: the walk never edits one, it copies it first (one level at a
    time, as it descends: see :func:`urdftk.xacro._share.copy_shallow`).
    ``plan`` is set on the ``pure`` elements that are not static (and only there): whether the
    attributes need evaluating, and the indices of the children that do.

    ``line`` is a 1-based line number, or, when ``file`` is a :class:`SourceName` (files parsed
    with positions), 1 + the byte offset of the start tag: see :func:`line_of`.

    Args:
        tag: The qualified name.
        attrs: The attributes (never edited in place: edits replace the dict).
        line: See above.
        file: The file name, for messages.
        children: The child list to take (a copy passes its source's list, or a copy of it);
            a new empty list when None.
    """

    __slots__ = (
        "attrs",
        "children",
        "file",
        "fixed",
        "line",
        "plan",
        "pure",
        "shared",
        "static",
        "tag",
    )

    def __init__(
        self,
        tag: str,
        attrs: dict[str, str],
        line: int = 0,
        file: str | None = None,
        children: list | None = None,
    ):
        self.tag = tag
        self.attrs = attrs
        self.children: list = [] if children is None else children
        self.line = line
        self.file = file
        self.static = False
        self.fixed = False
        self.shared = False
        self.pure = False

    def __repr__(self) -> str:
        return f"<Element {self.tag} at line {line_of(self.file, self.line)}>"


class SourceName(str):
    """A file name that also holds the file's text (``text``).

    Elements parsed with positions record byte offsets instead of line numbers (expat counts
    lines by rescanning the text at each request); the line is only worked out for a message.
    """

    text: str

    def line_at(self, pos: int) -> int:
        """The 1-based line of ``pos`` (1 + a byte offset into the UTF-8 text; 0 for unknown)."""
        if pos <= 0:
            return 0
        text = self.text
        if text.isascii():
            return text.count("\n", 0, pos - 1) + 1
        return text.encode().count(b"\n", 0, pos - 1) + 1


def line_of(file: str | None, line: int) -> int:
    """The line number of a node's ``line`` (see :class:`Element`)."""
    if file.__class__ is SourceName:
        return file.line_at(line)  # type: ignore[union-attr]
    return line


class Text:
    """A text node with an identity and a parent (only used for stock's shared blank node)."""

    __slots__ = ("data", "parent")

    def __init__(self, data: str):
        self.data = data
        self.parent: Element | None = None


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


def _reorder_at(text: str | bytes) -> set[int]:
    """Byte offsets of the start tags where a namespace declaration follows another attribute.

    minidom lists namespace declarations first; only these tags need their attributes reordered.
    (A false positive is harmless: reordering is a no-op on a tag without declarations.)
    """
    if text.__class__ is str and not text.isascii():
        text = text.encode()  # expat reports offsets into the UTF-8 encoding
    if text.__class__ is str:
        xmlns, lt, eq = "xmlns", "<", "="
    else:
        xmlns, lt, eq = b"xmlns", b"<", b"="
    out = set()
    i = text.find(xmlns)  # type: ignore[arg-type]
    while i >= 0:
        start = text.rfind(lt, 0, i)  # type: ignore[arg-type]
        if start >= 0 and eq in text[start:i]:  # type: ignore[operator]
            out.add(start)
        i = text.find(xmlns, i + 5)  # type: ignore[arg-type]
    return out


def parse_xml(
    text: str | bytes, filename: str | None = None, positions: bool = False
) -> tuple[list, Element]:
    """Parse a document.

    Args:
        text: The document (str, or bytes in the encoding it declares).
        filename: Recorded on every element, for error messages.
        positions: Record byte offsets instead of line numbers, which are worked out only for
            a message (expat finds a line by rescanning the text since the last request: a
            tenth of an expansion's time); only for str text with a file name (``file`` is
            then a :class:`SourceName`).

    Returns:
        The document-level nodes (comments, processing instructions, the root element) and the
        root element.

    Raises:
        XmlSyntaxError: The text is not well-formed, or declares a DOCTYPE/ENTITY.
    """
    p = ParserCreate(intern=None)  # (interning names costs more per element than it saves)
    top: list = []
    stack: list = []  # the child lists of the open elements' parents
    push = stack.append
    pop = stack.pop
    cur = top  # the child list of the innermost open element
    cdata = None
    reorder = _reorder_at(text)

    src: str | None = filename
    if positions and filename is not None and text.__class__ is str:
        src = SourceName(filename)
        src.text = text  # type: ignore[attr-defined]
    else:
        positions = False

    def start(name, attrs):
        nonlocal cur
        el = Element(name, attrs, p.CurrentLineNumber, filename)
        cur.append(el)
        push(cur)
        cur = el.children

    def start_at(name, attrs):  # with positions
        nonlocal cur
        el = Element(name, attrs, p.CurrentByteIndex + 1, src)
        cur.append(el)
        push(cur)
        cur = el.children

    begin = start_at if positions else start

    def start_reordered(name, attrs):
        if p.CurrentByteIndex in reorder:
            ns = {k: v for k, v in attrs.items() if k == "xmlns" or k.startswith("xmlns:")}
            ns.update(attrs)
            attrs = ns
        begin(name, attrs)

    def end(name):
        nonlocal cur
        cur = pop()

    def chars(data):  # text outside the root element is dropped at the end
        cur.append(data)

    def chars_merging(data):  # for a buffer smaller than the text: a run may come in pieces
        if cur:
            last = cur[-1]
            if last.__class__ is str:
                cur[-1] = last + data
                return
        cur.append(data)

    def cdata_chars(data):
        nonlocal cdata
        if cdata is not None and cur and cur[-1] is cdata:
            cdata.data += data
        else:
            cdata = CData(data)
            cur.append(cdata)

    def comment(data):
        cur.append(Comment(data, p.CurrentLineNumber))

    def comment_at(data):  # with positions
        cur.append(Comment(data, p.CurrentByteIndex + 1))

    def pi(target, data):
        cur.append(PI(target, data))

    def start_cdata():
        nonlocal cdata
        cdata = None
        p.CharacterDataHandler = cdata_chars

    def end_cdata():
        nonlocal cdata
        cdata = None
        p.CharacterDataHandler = text_handler

    def doctype(*args):
        raise XmlSyntaxError(
            "DOCTYPE and ENTITY declarations are not allowed "
            "(entities could read files or expand without bound)",
            filename,
            p.CurrentLineNumber,
            p.CurrentColumnNumber + 1,
        )

    p.buffer_text = True
    # a buffer as large as the document: each run of text arrives in one piece, never split
    size = len(text) if text.__class__ is str and text.isascii() else 4 * len(text)  # UTF-8 bytes, at most
    text_handler = chars_merging
    if size < 1 << 30:
        p.buffer_size = max(size, 8192)
        text_handler = chars
    p.StartElementHandler = start_reordered if reorder else begin
    p.EndElementHandler = end
    p.CharacterDataHandler = text_handler
    p.CommentHandler = comment_at if positions else comment
    p.ProcessingInstructionHandler = pi
    p.StartCdataSectionHandler = start_cdata
    p.EndCdataSectionHandler = end_cdata
    p.StartDoctypeDeclHandler = doctype
    p.EntityDeclHandler = doctype
    try:
        p.Parse(text, True)
    except ExpatError as e:
        raise XmlSyntaxError(errors.messages[e.code], filename, e.lineno, e.offset + 1) from None
    finally:
        # the handlers refer to the parser (a cycle): break it, so that the parser and its
        # buffer go now, and the tree is freed by reference counting, not by the cyclic GC
        p = None
    top = [n for n in top if n.__class__ is not str]
    for n in top:
        if n.__class__ is Element:
            return top, n
    raise XmlSyntaxError("no element found", filename, 1, 1)  # pragma: no cover - expat says so first
