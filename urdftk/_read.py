"""Read a robot file for ``urdftk check`` and ``urdftk graph``, keeping its line numbers when possible.

A plain URDF is parsed as it is on disk, so every line a finding names is a line of that file. Only
a document that needs xacro (a ``.xacro`` file, xacro elements or ``${}``/``$()`` outside comments,
or xacro arguments given) goes through :func:`urdftk.loading.expand`; its lines are then those of
the expanded text.
"""

from __future__ import annotations

import os
from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from pathlib import Path

from lxml import etree

from urdftk.errors import ResourceError
from urdftk.loading import uses_xacro
from urdftk.resources import PackageResolver
from urdftk.xmlsafe import parse_xml

__all__ = ["Source", "read_source"]


@dataclass(frozen=True)
class Source:
    """A parsed robot document.

    Attributes:
        root: The XML root element (with source lines).
        filename: The file it came from, or None for text.
        resolver: Resolves ``package://`` and relative references for this document.
        expanded: True when the text went through xacro (lines refer to the expanded text).
    """

    root: etree._Element
    filename: str | None
    resolver: PackageResolver
    expanded: bool


def _looks_like_text(value: object) -> bool:
    return isinstance(value, str) and value.lstrip().startswith("<")


def read_source(
    path_or_text: str | os.PathLike[str],
    *,
    args: Mapping[str, str] | None = None,
    package_paths: Iterable[str | os.PathLike[str]] | None = None,
) -> Source:
    """Read and safely parse a .urdf/.xacro file or URDF text.

    Args:
        path_or_text: A file path, or the XML text itself (text starts with ``<``).
        args: xacro arguments (``name:=value``).
        package_paths: Extra folders searched first for ROS packages.

    Returns:
        The parsed document.

    Raises:
        ResourceError: If the file cannot be read.
        DescriptionError: For malformed XML or a DOCTYPE/ENTITY declaration.
        XacroError: If xacro expansion fails.
    """
    paths = list(package_paths or ())
    filename: str | None
    if _looks_like_text(path_or_text):
        data = str(path_or_text).encode("utf-8")
        filename = None
    else:
        path = Path(path_or_text)
        try:
            data = path.read_bytes()
        except FileNotFoundError:
            raise ResourceError(f"{path}: no such file") from None
        except OSError as exc:
            raise ResourceError(f"{path}: cannot read: {exc.strerror or exc}") from None
        filename = str(path)
    is_xacro_file = filename is not None and filename.endswith(".xacro")
    if not args and not is_xacro_file:
        root = parse_xml(data, filename)
        if not uses_xacro(root):
            return Source(root, filename, PackageResolver(paths, source=filename), expanded=False)
    from urdftk.loading import expand

    text, _, resolver, _root = expand(path_or_text, args=args, package_paths=paths)
    return Source(parse_xml(text, filename), filename, resolver, expanded=True)
