"""The kinematic structure of a URDF document, read from XML with line numbers.

This is the part of a robot description that both loading and ``urdftk check`` need before any
library builds a model: link and joint names, parents and children, roots, cycles and depth.
It never raises on malformed structure; it records what it sees, and callers decide.
"""

from __future__ import annotations

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


def _joint_info(el: etree._Element) -> JointInfo:
    """The :class:`JointInfo` of a ``<joint>``: its first ``<parent>`` and ``<child>``, in one pass."""
    parent = child = None
    for sub in el:
        tag = sub.tag
        if tag == "parent":
            if parent is None:
                parent = sub
        elif tag == "child" and child is None:
            child = sub
    return JointInfo(
        el.get("name") or "",
        el.get("type") or "",
        (parent.get("link") or "") if parent is not None else "",
        (child.get("link") or "") if child is not None else "",
        el.sourceline,
        el,
    )


def read_tree(root: etree._Element) -> TreeInfo:
    """Read the kinematic structure of a ``<robot>`` element.

    Args:
        root: The document root (normally ``<robot>``).

    Returns:
        The structure; validity is judged by the caller.
    """
    links: list[LinkInfo] = []
    joints: list[JointInfo] = []
    parent_joint: dict[str, list[JointInfo]] = {}
    children: dict[str, list[JointInfo]] = {}
    for el in root:  # comments and processing instructions have a non-str tag: never equal
        tag = el.tag
        if tag == "link":
            links.append(LinkInfo(el.get("name") or "", el.sourceline, el))
        elif tag == "joint":
            j = _joint_info(el)
            joints.append(j)
            if j.child in parent_joint:
                parent_joint[j.child].append(j)
            else:
                parent_joint[j.child] = [j]
            if j.parent in children:
                children[j.parent].append(j)
            else:
                children[j.parent] = [j]
    info = TreeInfo(name=root.get("name") or "", links=links, joints=joints)
    info.parent_joint = parent_joint
    info.children = children
    link_names = list(dict.fromkeys(link.name for link in links))
    info.roots = [n for n in link_names if n not in parent_joint]
    info.cycle = _find_cycle(link_names, parent_joint)
    info.depth = _depth(info.roots, children) if not info.cycle else 0
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
        if d > best:
            best = d
        kids = children.get(link)
        if kids:
            d += 1
            stack.extend((j.child, d) for j in kids)
    return best
