"""The kinematic structure of a URDF document, read from XML with line numbers.

This is the part of a robot description that both loading and ``urdftk check`` need before any
library builds a model: link and joint names, parents and children, roots, cycles and depth.
It never raises on malformed structure; it records what it sees, and callers decide.
"""

from __future__ import annotations

from collections import defaultdict
from dataclasses import dataclass, field

from lxml import etree

__all__ = ["JointInfo", "LinkInfo", "TreeInfo", "read_tree"]


@dataclass(frozen=True)
class LinkInfo:
    """A ``<link>`` element.

    Attributes:
        name: The link name ('' when the attribute is missing).
        line: Its line in the document.
        element: The XML element.
    """

    name: str
    line: int | None
    element: etree._Element


@dataclass(frozen=True)
class JointInfo:
    """A ``<joint>`` element.

    Attributes:
        name: The joint name ('' when missing).
        type: The ``type`` attribute ('' when missing).
        parent: The parent link name ('' when missing).
        child: The child link name ('' when missing).
        line: Its line in the document.
        element: The XML element.
    """

    name: str
    type: str
    parent: str
    child: str
    line: int | None
    element: etree._Element


@dataclass
class TreeInfo:
    """The structure read from a ``<robot>`` element.

    Attributes:
        name: The robot name.
        links: Every top-level ``<link>``, in document order.
        joints: Every top-level ``<joint>``, in document order.
        parent_joint: Child link name -> the joints naming it as child (more than one is an error).
        children: Parent link name -> joints whose parent it is, in document order.
        roots: Links that are no joint's child.
        cycle: Link names on a cycle, if any (empty when the graph is a forest).
        depth: Number of joints on the longest root-to-leaf path.
    """

    name: str
    links: list[LinkInfo]
    joints: list[JointInfo]
    parent_joint: dict[str, list[JointInfo]] = field(default_factory=dict)
    children: dict[str, list[JointInfo]] = field(default_factory=dict)
    roots: list[str] = field(default_factory=list)
    cycle: list[str] = field(default_factory=list)
    depth: int = 0

    def link_line(self, name: str) -> int | None:
        """Return the line of the first link called ``name``."""
        return next((link.line for link in self.links if link.name == name), None)


def _child_text(el: etree._Element, tag: str, attr: str) -> str:
    sub = el.find(tag)
    return (sub.get(attr) or "") if sub is not None else ""


def read_tree(root: etree._Element) -> TreeInfo:
    """Read the kinematic structure of a ``<robot>`` element.

    Args:
        root: The document root (normally ``<robot>``).

    Returns:
        The structure; validity is judged by the caller.
    """
    links = [
        LinkInfo(el.get("name") or "", el.sourceline, el)
        for el in root
        if isinstance(el.tag, str) and el.tag == "link"
    ]
    joints = [
        JointInfo(
            el.get("name") or "",
            el.get("type") or "",
            _child_text(el, "parent", "link"),
            _child_text(el, "child", "link"),
            el.sourceline,
            el,
        )
        for el in root
        if isinstance(el.tag, str) and el.tag == "joint"
    ]
    info = TreeInfo(name=root.get("name") or "", links=links, joints=joints)
    parent_joint: dict[str, list[JointInfo]] = defaultdict(list)
    children: dict[str, list[JointInfo]] = defaultdict(list)
    for j in joints:
        parent_joint[j.child].append(j)
        children[j.parent].append(j)
    info.parent_joint = dict(parent_joint)
    info.children = dict(children)
    link_names = list(dict.fromkeys(link.name for link in links))
    info.roots = [n for n in link_names if n not in parent_joint]
    info.cycle = _find_cycle(link_names, info.parent_joint)
    info.depth = _depth(info.roots, info.children) if not info.cycle else 0
    return info


def _find_cycle(links: list[str], parent_joint: dict[str, list[JointInfo]]) -> list[str]:
    state: dict[str, int] = {}
    for start in links:
        path: list[str] = []
        node = start
        while node and state.get(node) is None:
            state[node] = 1
            path.append(node)
            parents = parent_joint.get(node)
            node = parents[0].parent if parents else ""
        if node and state.get(node) == 1 and node in path:
            return path[path.index(node) :]
        for n in path:
            state[n] = 2
    return []


def _depth(roots: list[str], children: dict[str, list[JointInfo]]) -> int:
    best = 0
    stack = [(r, 0) for r in roots]
    seen: set[str] = set()
    while stack:
        link, d = stack.pop()
        if link in seen:
            continue
        seen.add(link)
        best = max(best, d)
        for j in children.get(link, ()):
            stack.append((j.child, d + 1))
    return best
