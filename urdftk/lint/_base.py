"""What every lint rule shares: the :class:`Finding` record, the :class:`Context` and number parsing."""

from __future__ import annotations

import math
import re
from collections.abc import Iterator
from dataclasses import dataclass
from functools import cached_property
from typing import Literal

from lxml import etree

from urdftk.resources import PackageResolver
from urdftk.tree import JointInfo, TreeInfo

__all__ = [
    "MOVING_JOINT_TYPES",
    "Context",
    "Finding",
    "Severity",
    "describe",
    "elements",
    "parse_numbers",
]

Severity = Literal["error", "warning"]

MOVING_JOINT_TYPES = frozenset({"revolute", "continuous", "prismatic", "floating", "planar"})
"""Joint types whose child moves."""

_NUMBER_RE = re.compile(r"^[+-]?(?:(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?|nan|inf|infinity)$", re.IGNORECASE)


@dataclass(frozen=True)
class Finding:
    """One problem found in a robot description.

    Attributes:
        severity: ``"error"`` (the description is wrong or will not load) or ``"warning"``.
        code: Stable kebab-case identifier, e.g. ``"two-roots"``.
        element: The element at fault, e.g. ``"joint 'j1'"``.
        line: Its line in the document (None when unknown).
        message: What is wrong and, where useful, what to do.
    """

    severity: Severity
    code: str
    element: str
    line: int | None
    message: str

    def to_dict(self) -> dict[str, object]:
        """Return the finding as a JSON-ready dict."""
        return {
            "severity": self.severity,
            "code": self.code,
            "element": self.element,
            "line": self.line,
            "message": self.message,
        }


def parse_numbers(text: str | None) -> list[float] | None:
    """Parse a whitespace-separated list of numbers as URDF does.

    Args:
        text: The attribute value.

    Returns:
        The numbers (possibly non-finite), or None when a token is not a number.
    """
    if text is None:
        return None
    tokens = text.split()
    if not all(_NUMBER_RE.match(t) for t in tokens):
        return None
    return [float(t) for t in tokens]


def describe(el: etree._Element) -> str:
    """Name the element a finding is about: its top-level owner plus the path below it.

    Args:
        el: Any element of a ``<robot>`` document.

    Returns:
        A label such as ``"joint 'j1'"`` or ``"link 'arm' <visual> <box>"``.
    """
    chain: list[etree._Element] = []
    node: etree._Element | None = el
    while node is not None and node.getparent() is not None:
        chain.append(node)
        node = node.getparent()
    top = chain[-1] if chain else el
    label = f"{top.tag} '{top.get('name')}'" if top.get("name") is not None else f"<{top.tag}>"
    return " ".join([label, *(f"<{c.tag}>" for c in reversed(chain[:-1]))])


def elements(parent: etree._Element, tag: str) -> Iterator[etree._Element]:
    """Yield the direct children of ``parent`` called ``tag`` (comments skipped)."""
    for child in parent:
        if isinstance(child.tag, str) and child.tag == tag:
            yield child


@dataclass
class Context:
    """Everything a lint rule may look at.

    Attributes:
        root: The ``<robot>`` element.
        tree: Its structure.
        filename: The file, if any.
        resolver: Resolves resource references.
        load_meshes: Whether mesh files are loaded with trimesh.
    """

    root: etree._Element
    tree: TreeInfo
    filename: str | None
    resolver: PackageResolver | None
    load_meshes: bool

    def number(self, el: etree._Element | None, attr: str, default: float | None = None) -> float | None:
        """Return a single finite number from an attribute (``default`` when absent, None when bad)."""
        if el is None or el.get(attr) is None:
            return default
        values = parse_numbers(el.get(attr))
        if values is None or len(values) != 1 or not math.isfinite(values[0]):
            return None
        return values[0]

    def vector(self, el: etree._Element | None, attr: str, size: int) -> list[float] | None:
        """Return ``size`` finite numbers from an attribute, or None when absent or bad."""
        if el is None:
            return None
        values = parse_numbers(el.get(attr))
        if values is None or len(values) != size or not all(math.isfinite(v) for v in values):
            return None
        return values

    @cached_property
    def parent_joint(self) -> dict[str, JointInfo]:
        """Child link name -> its (first) parent joint."""
        return {child: js[0] for child, js in self.tree.parent_joint.items() if child}

    @cached_property
    def moving_links(self) -> set[str]:
        """Links that move: children of a non-fixed joint, and links fixed below one."""
        moving: set[str] = set()
        stack = [(r, False) for r in self.tree.roots]
        seen: set[str] = set()
        while stack:
            link, is_moving = stack.pop()
            if link in seen:
                continue
            seen.add(link)
            if is_moving:
                moving.add(link)
            for j in self.tree.children.get(link, ()):
                stack.append((j.child, is_moving or j.type in MOVING_JOINT_TYPES))
        return moving

    @cached_property
    def body_of(self) -> dict[str, str]:
        """Link name -> the link that heads its rigid body (fixed joints lumped, as Pinocchio does)."""
        heads: dict[str, str] = {}
        stack = [(r, r) for r in self.tree.roots]
        while stack:
            link, head = stack.pop()
            if link in heads:
                continue
            heads[link] = head
            for j in self.tree.children.get(link, ()):
                stack.append((j.child, head if j.type == "fixed" else j.child))
        return heads
