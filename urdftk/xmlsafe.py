"""Safe XML parsing: no DOCTYPE, no entities, no network, line numbers kept.

URDF and xacro never need a DTD. Rejecting every ``<!DOCTYPE``/``<!ENTITY`` before parsing
rules out external entities (file or network reads) and entity bombs ("billion laughs"), and
guarantees that every consumer of the same text (yourdfpy, Pinocchio, our lint) sees the same
names.
"""

from __future__ import annotations

import re

from lxml import etree

from urdftk.errors import DescriptionError

__all__ = ["line_of_offset", "parse_xml", "reject_doctype", "safe_parser"]

_DTD_RE = re.compile(rb"<!(DOCTYPE|ENTITY)", re.IGNORECASE)


def safe_parser() -> etree.XMLParser:
    """Return an lxml parser that never loads a DTD, resolves entities, or reads the network."""
    return etree.XMLParser(
        resolve_entities=False,
        no_network=True,
        load_dtd=False,
        dtd_validation=False,
        huge_tree=False,
        remove_blank_text=False,
    )


def line_of_offset(data: bytes, offset: int) -> int:
    """Return the 1-based line number of byte ``offset`` in ``data``."""
    return data.count(b"\n", 0, offset) + 1


def reject_doctype(data: bytes, filename: str | None = None) -> None:
    """Raise if ``data`` declares a DOCTYPE or an ENTITY.

    Args:
        data: The document bytes.
        filename: Used in the error message.

    Raises:
        DescriptionError: Naming the line of the declaration.
    """
    match = _DTD_RE.search(data)
    if match:
        kind = match.group(1).decode().upper()
        raise DescriptionError(
            f"<!{kind}> declarations are not allowed (entities could read files or expand without bound); "
            "remove the DOCTYPE",
            filename,
            line_of_offset(data, match.start()),
        )


def parse_xml(text: str | bytes, filename: str | None = None) -> etree._Element:
    """Parse XML text safely and return its root element (with ``sourceline`` set).

    Args:
        text: The document.
        filename: Where it came from, for error messages.

    Returns:
        The root element.

    Raises:
        DescriptionError: For a DOCTYPE/ENTITY, or malformed XML (with line and column).
    """
    data = text.encode("utf-8") if isinstance(text, str) else text
    reject_doctype(data, filename)
    if isinstance(text, str) and text.lstrip().startswith("<?xml"):
        # lxml refuses str input with an encoding declaration; parse the UTF-8 bytes instead.
        text = data
    try:
        root = etree.fromstring(data if isinstance(text, bytes) else text, parser=safe_parser())
    except etree.XMLSyntaxError as exc:
        line, col = exc.position if exc.position else (None, None)
        msg = str(exc.msg or exc).split(", line ")[0]
        raise DescriptionError(f"malformed XML: {msg}", filename, line, col) from None
    except ValueError as exc:  # e.g. unsupported encodings
        raise DescriptionError(f"cannot parse XML: {exc}", filename) from None
    if root is None:
        raise DescriptionError("empty document", filename)
    docinfo = root.getroottree().docinfo
    if docinfo.doctype or docinfo.internalDTD is not None:
        # The byte search above cannot see a DOCTYPE in a UTF-16/32 document; the parser can.
        raise DescriptionError("<!DOCTYPE> declarations are not allowed; remove the DOCTYPE", filename, 1)
    return root
