"""``urdftk.load``: a .urdf or .xacro file (or text) to a :class:`~urdftk.model.Robot`."""

from __future__ import annotations

import os
import re
from collections.abc import Iterable, Mapping
from pathlib import Path

from lxml import etree

from urdftk.description import parse_description
from urdftk.errors import ResourceError
from urdftk.resources import PackageResolver
from urdftk.xmlsafe import parse_xml

__all__ = ["expand", "load", "uses_xacro"]


_COMMENT = re.compile(r"<!--.*?-->", re.S)
_XACRO_ELEMENT = etree.XPath("boolean(//*[starts-with(name(), 'xacro:')])")
"""As stock xacro, by prefix: files use several namespace URIs."""
_SUBSTITUTION = etree.XPath("boolean(//@*[contains(., '${')] | //text()[contains(., '${')])")
"""``${...}`` in an attribute or text (comments are not text())."""


def uses_xacro(root: etree._Element, text: str | None = None) -> bool:
    """Tell whether a parsed document uses xacro: ``xacro:`` elements, or ``${...}`` in values.

    Comments do not count, and neither does an unused ``xmlns:xacro`` declaration (files written
    by xacro keep it), nor a bare ``$(...)`` (a plain URDF may hold such text; name the file
    ``.xacro`` or pass an argument to have it expanded).

    Args:
        root: The document root.
        text: The document text, if at hand: substring tests then skip most of the tree walks.

    Returns:
        True when the document must be expanded before it is a URDF.
    """
    if text is not None:
        bare = _COMMENT.sub("", text) if "<!--" in text else text
        if ("$" not in bare or "${" not in bare) and "<xacro:" not in bare:  # "$" alone is a fast scan
            return False
    return bool(_XACRO_ELEMENT(root)) or bool(_SUBSTITUTION(root))


def _looks_like_text(value: str) -> bool:
    return value.lstrip().startswith("<")


def expand(
    path_or_text: str | os.PathLike[str],
    *,
    args: Mapping[str, str] | None = None,
    package_paths: Iterable[str | os.PathLike[str]] | None = None,
) -> tuple[str, str | None, PackageResolver, etree._Element | None]:
    """Read a .urdf/.xacro file (or text) and return URDF text, its file name and the resolver.

    A document goes through xacro when it is a ``.xacro`` file, when ``args`` are given, or when
    it uses xacro (see :func:`uses_xacro`); otherwise it is parsed once here and that parse is
    returned for reuse.

    Args:
        path_or_text: A file path, or the XML text itself.
        args: xacro arguments (``name:=value``).
        package_paths: Extra folders to search for ROS packages first.

    Returns:
        ``(urdf_text, filename_or_None, resolver, root)``; ``root`` is the parsed XML when the
        text was not expanded, else None.

    Raises:
        ResourceError: If the file cannot be read.
        XacroError: If xacro expansion fails.
    """
    pkg_paths = list(package_paths or ())
    text: str
    filename: str | None
    if isinstance(path_or_text, str) and _looks_like_text(path_or_text):
        text, filename = path_or_text, None
    else:
        p = Path(path_or_text)
        try:
            with open(p, "rb") as fh:  # as p.read_text(encoding="utf-8"), without a text layer
                text = fh.read().decode("utf-8")
        except FileNotFoundError:
            raise ResourceError(f"{p}: no such file") from None
        except (OSError, UnicodeDecodeError) as exc:
            raise ResourceError(f"{p}: cannot read: {exc}") from None
        if "\r" in text:  # universal newlines, as text mode reads
            text = text.replace("\r\n", "\n").replace("\r", "\n")
        filename = str(p)
    resolver = PackageResolver(pkg_paths, source=filename)
    if not args and not (filename or "").endswith(".xacro"):
        root = parse_xml(text, filename)
        if not uses_xacro(root, text):
            return text, filename, resolver, root
    from urdftk import xacro

    mappings = dict(args or {})
    if filename is not None:
        text = xacro.process_file(filename, mappings, resolver=resolver)
    else:
        text = xacro.process_string(text, mappings, resolver=resolver)
    return text, filename, resolver, None


def load(
    path_or_text: str | os.PathLike[str],
    *,
    args: Mapping[str, str] | None = None,
    package_paths: Iterable[str | os.PathLike[str]] | None = None,
    floating_base: bool = False,
):  # -> Robot (annotation left out to keep Pinocchio out of import time)
    """Load a robot from a .urdf or .xacro file, or from URDF/xacro text.

    The text is expanded (xacro), parsed once safely, checked for structure, then given to
    yourdfpy (the description) and to Pinocchio (the model): both see the same text.

    Args:
        path_or_text: A file path, or the XML text itself.
        args: xacro arguments, as ``{"name": "value"}``.
        package_paths: Extra folders to search for ROS packages (searched first).
        floating_base: Put a free-flyer joint between the world and the root link.

    Returns:
        The :class:`~urdftk.model.Robot`.

    Raises:
        UrdftkError: A subclass naming the file and line for anything that cannot be loaded.

    Example:
        >>> robot = load("examples/robots/robot0_description/urdf/robot0.urdf")  # doctest: +SKIP
        >>> robot.joint_names  # doctest: +SKIP
        ('joint_1',)
    """
    from urdftk.model import Robot

    text, filename, resolver, root = expand(path_or_text, args=args, package_paths=package_paths)
    description = parse_description(text, filename, resolver, root=root)
    return Robot(description, resolver=resolver, floating_base=floating_base)
