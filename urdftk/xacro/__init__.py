"""Our xacro expander: output byte-identical to stock xacro 2.1.1, faster, and safe by default.

Example:
    >>> from urdftk.xacro import process_string
    >>> text = process_string('<r xmlns:xacro="http://www.ros.org/wiki/xacro">'
    ...                       '<xacro:property name="w" value="2"/><b w="${w * 3}"/></r>')
    >>> text.splitlines()[-3]
    '  <b w="6"/>'

``$(find pkg)`` is resolved without ROS by :class:`urdftk.resources.PackageResolver`.
Expressions run in a sandbox (see :mod:`urdftk.xacro._eval`). Errors are
:class:`urdftk.errors.XacroError` naming ``file:line`` and the macro/include trace.
"""

from __future__ import annotations

import os

TYPE_CHECKING = False
if TYPE_CHECKING:
    from collections.abc import Iterable, Mapping
    from pathlib import Path
    from typing import Any, TextIO

__all__ = ["Result", "expand", "process_file", "process_string"]

PathLike = str | os.PathLike


class Result:
    """The outcome of one expansion.

    Attributes:
        text: The document, exactly as stock ``xacro`` prints it.
        includes: Every file read besides the input (xacro includes and yaml), in first-use order,
            as paths (made on first access: most callers only want the text).
        packages: Packages resolved by ``$(find)``: name -> folder.
    """

    __slots__ = ("_includes", "packages", "text")

    def __init__(self, text: str, includes: Iterable[PathLike] = (), packages: dict[str, Path] | None = None):
        self.text = text
        self._includes: tuple = tuple(includes)
        self.packages = dict(packages or {})

    @property
    def includes(self) -> tuple[Path, ...]:
        """Every file read besides the input, in first-use order."""
        found = self._includes
        if any(p.__class__ is str for p in found):
            from pathlib import Path

            found = self._includes = tuple(Path(p) for p in found)
        return found

    def __repr__(self) -> str:
        return (
            f"Result(text=<{len(self.text)} chars>, includes={self.includes!r}, packages={self.packages!r})"
        )


def expand(
    source: PathLike | None = None,
    mappings: Mapping[str, str] | None = None,
    *,
    text: str | None = None,
    filename: str | None = None,
    package_paths: Iterable[PathLike] = (),
    resolver: Any = None,
    stderr: TextIO | None = None,
    verbosity: int = 1,
) -> Result:
    """Expand a xacro file (``source``) or text (``text``), returning text and dependencies.

    Args:
        source: The input file. Relative includes are relative to it.
        mappings: ``name:=value`` arguments.
        text: Document text, instead of ``source``.
        filename: For ``text``: the name shown in the header and errors, and the base of relative
            includes (the current directory when None).
        package_paths: Folders searched first by ``$(find)``.
        resolver: A :class:`urdftk.resources.PackageResolver` to use (one is made otherwise, with
            ``package_paths`` and the input's workspace).
        stderr: Where warnings go (``sys.stderr`` when None).
        verbosity: 0 silences warnings.

    Returns:
        The :class:`Result`.

    Raises:
        urdftk.errors.XacroError: With ``file:line`` and the macro/include trace.
        urdftk.errors.PackageNotFound: A ``$(find)`` package is unknown.
    """
    from urdftk.xacro._output import banner, write_document
    from urdftk.xacro._processor import Expander
    from urdftk.xacro._tree import parse_xml

    if (source is None) == (text is None):
        raise ValueError("give exactly one of source and text")
    ex = Expander(dict(mappings or {}), tuple(package_paths), resolver, stderr, verbosity)
    if source is not None:
        name = os.fspath(source)
        top, root = ex.parse_file(name)
        shown = name
    else:
        name = filename
        top, root = parse_xml(text, filename)  # type: ignore[arg-type]
        shown = filename if filename is not None else "<string>"
    try:
        top = ex.process(top, root, name)
        out = write_document([*banner(str(shown)), *top])
        return Result(out, dict.fromkeys(ex.includes), ex.found_packages())
    finally:
        ex.release()


def process_file(
    path: PathLike,
    mappings: Mapping[str, str] | None = None,
    *,
    package_paths: Iterable[PathLike] = (),
    resolver: Any = None,
) -> str:
    """Expand a xacro file; return the document exactly as stock ``xacro`` prints it.

    Args:
        path: The input file.
        mappings: ``name:=value`` arguments.
        package_paths: Folders searched first by ``$(find)``.
        resolver: A :class:`urdftk.resources.PackageResolver` to use instead of a new one.
    """
    return expand(path, mappings, package_paths=package_paths, resolver=resolver).text


def process_string(
    text: str,
    mappings: Mapping[str, str] | None = None,
    *,
    filename: str | None = None,
    package_paths: Iterable[PathLike] = (),
    resolver: Any = None,
) -> str:
    """Expand xacro text; ``filename`` (if given) names it and anchors relative includes.

    Args:
        text: The document.
        mappings: ``name:=value`` arguments.
        filename: Name for the header, errors and relative includes.
        package_paths: Folders searched first by ``$(find)``.
        resolver: A :class:`urdftk.resources.PackageResolver` to use instead of a new one.
    """
    return expand(
        None, mappings, text=text, filename=filename, package_paths=package_paths, resolver=resolver
    ).text
