"""Parse and validate URDF text into a :class:`Description` (yourdfpy), owning error locations.

The same text feeds yourdfpy here and Pinocchio in :mod:`urdftk.model`. Entity declarations are
rejected (see :mod:`urdftk.xmlsafe`), so both libraries see identical link and joint names.
Structural faults that would make either library crash or disagree are raised here as
:class:`~urdftk.errors.DescriptionError` with ``file:line``.
"""

from __future__ import annotations

import functools
import io
from collections import Counter
from dataclasses import dataclass
from pathlib import Path

from lxml import etree

from urdftk.errors import DescriptionError
from urdftk.resources import PackageResolver
from urdftk.tree import TreeInfo, read_tree
from urdftk.xmlsafe import parse_xml

__all__ = ["JOINT_TYPES", "MAX_TREE_DEPTH", "Description", "parse_description", "structure_errors"]

JOINT_TYPES = ("revolute", "continuous", "prismatic", "fixed", "floating", "planar")
"""The joint types URDF defines."""

MAX_TREE_DEPTH = 2000
"""Deepest kinematic chain accepted. Pinocchio's URDF parser recurses per joint and overflows the
C stack past a few thousand; deeper files are rejected before any library sees them."""


@dataclass(frozen=True)
class Description:
    """A parsed, structurally valid robot description.

    Attributes:
        text: The URDF text (after xacro expansion).
        filename: The file it came from (the .xacro for expanded files), if any.
        root: The XML root element, with source lines.
        tree: Links, joints and structure read from the XML.
        resolver: Resolves ``package://`` and relative mesh references.
    """

    text: str
    filename: str | None
    root: etree._Element
    tree: TreeInfo
    resolver: PackageResolver

    @functools.cached_property
    def urdf(self) -> object:  # yourdfpy.URDF; typed loosely to keep yourdfpy out of import time
        """The yourdfpy model, parsed from the same text on first use (meshes not loaded).

        yourdfpy's parse costs several times Pinocchio's model build, so it is deferred until a
        consumer (a viewer, a mesh loader) needs it.

        Raises:
            DescriptionError: If yourdfpy cannot parse the text.
        """
        return _parse_yourdfpy(self.text, self.filename, self.resolver)

    @property
    def name(self) -> str:
        """The robot name."""
        return self.tree.name

    def line_of(self, kind: str, name: str) -> int | None:
        """Return the line of the ``<link>`` or ``<joint>`` (``kind``) called ``name``."""
        items = self.tree.links if kind == "link" else self.tree.joints
        return next((i.line for i in items if i.name == name), None)


def structure_errors(root: etree._Element, tree: TreeInfo) -> list[tuple[int | None, str]]:
    """List the structural faults that make a description unloadable.

    Args:
        root: The document root.
        tree: Its structure, from :func:`urdftk.tree.read_tree`.

    Returns:
        ``(line, message)`` pairs, in document order of discovery; empty when loadable.
    """
    errors: list[tuple[int | None, str]] = []
    if not isinstance(root.tag, str) or root.tag != "robot":
        return [(root.sourceline, f"root element is <{root.tag}>, expected <robot>")]
    if not tree.links:
        return [(root.sourceline, "robot has no <link> elements (empty robot)")]
    for kind, items in (("link", tree.links), ("joint", tree.joints)):
        for item in items:
            if not item.name:
                errors.append((item.line, f"<{kind}> has no name"))
        names = [i.name for i in items if i.name]
        if len(set(names)) == len(names):  # no duplicates: skip the count
            continue
        for name, count in Counter(names).items():
            if count > 1:
                lines = [i.line for i in items if i.name == name]
                errors.append((lines[1], f"duplicate {kind} name '{name}' (also on line {lines[0]})"))
    links = {link.name for link in tree.links}
    for j in tree.joints:
        if j.type not in JOINT_TYPES:
            errors.append(
                (j.line, f"joint '{j.name}' has unknown type '{j.type}' (expected one of {JOINT_TYPES})")
            )
        for role, link in (("parent", j.parent), ("child", j.child)):
            if not link:
                errors.append((j.line, f"joint '{j.name}' has no <{role} link=...>"))
            elif link not in links:
                errors.append((j.line, f"joint '{j.name}' {role} link '{link}' does not exist"))
        if j.parent and j.parent == j.child:
            errors.append((j.line, f"joint '{j.name}' connects link '{j.parent}' to itself"))
    for child, js in tree.parent_joint.items():
        if len(js) > 1 and child in links:
            names = ", ".join(f"'{j.name}'" for j in js)
            errors.append((js[1].line, f"link '{child}' has {len(js)} parent joints ({names})"))
    if tree.cycle:
        errors.append(
            (tree.link_line(tree.cycle[0]), "kinematic loop through links " + " -> ".join(tree.cycle))
        )
    elif len(tree.roots) > 1:
        errors.append(
            (
                tree.link_line(tree.roots[1]),
                f"robot has {len(tree.roots)} root links: {', '.join(tree.roots)}",
            )
        )
    elif not tree.roots:
        errors.append((root.sourceline, "robot has no root link"))
    if tree.depth > MAX_TREE_DEPTH:
        errors.append(
            (
                root.sourceline,
                f"kinematic chain is {tree.depth} joints deep; at most {MAX_TREE_DEPTH} are supported",
            )
        )
    return errors


def parse_description(
    text: str,
    filename: str | None = None,
    resolver: PackageResolver | None = None,
    *,
    root: etree._Element | None = None,
) -> Description:
    """Parse URDF text safely and check its structure (yourdfpy parses it on first use).

    Args:
        text: URDF text.
        filename: Where it came from, for messages and relative paths.
        resolver: Resolves ``package://`` mesh references for yourdfpy.
        root: ``text`` already parsed with :func:`urdftk.xmlsafe.parse_xml`, to skip a second parse.

    Returns:
        The description.

    Raises:
        DescriptionError: For unsafe or malformed XML, or an unloadable structure.
    """
    if root is None:
        root = parse_xml(text, filename)
    tree = read_tree(root)
    errors = structure_errors(root, tree)
    if errors:
        line, msg = errors[0]
        more = (
            f" (and {len(errors) - 1} more problem(s); run `urdftk check` for all)" if len(errors) > 1 else ""
        )
        raise DescriptionError(msg + more, filename, line)
    res = resolver or PackageResolver(source=filename)
    return Description(text=text, filename=filename, root=root, tree=tree, resolver=res)


def _parse_yourdfpy(text: str, filename: str | None, resolver: PackageResolver) -> object:
    import yourdfpy

    base = Path(filename).parent if filename else Path.cwd()

    def handler(fname: str) -> str:
        return str(resolver.resolve(fname, relative_to=base))

    try:
        return yourdfpy.URDF.load(
            io.BytesIO(text.encode("utf-8")),
            build_scene_graph=False,
            load_meshes=False,
            load_collision_meshes=False,
            filename_handler=handler,
            mesh_dir=str(base),
        )
    except Exception as exc:  # yourdfpy raises bare ValueError/AttributeError on bad values
        raise DescriptionError(f"yourdfpy cannot parse the description: {exc}", filename) from None
