"""``urdftk check``: what check_urdf prints (robot, root, link tree), then a lint with severities.

The check works on the XML tree with line numbers, not on a loaded model, so it reports every
problem, with its line, even in a file that would not load.

Example:
    >>> from urdftk.check import check
    >>> report = check("examples/robots/robot0_description/urdf/robot0.urdf")  # doctest: +SKIP
    >>> report.root, report.counts  # doctest: +SKIP
    ('world', {'error': 0, 'warning': 0})
"""

from __future__ import annotations

import os
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field

from urdftk._read import read_source
from urdftk.description import MAX_TREE_DEPTH
from urdftk.errors import format_location
from urdftk.lint import Context, Finding, run_rules
from urdftk.tree import TreeInfo, read_tree

__all__ = ["SCHEMA", "STRUCTURAL_CODES", "Finding", "Report", "TreeEntry", "check", "format_text"]

SCHEMA = "urdftk-check/1"
"""Identifier of the JSON layout of :meth:`Report.to_dict`; changes only with a new number."""

STRUCTURAL_CODES = frozenset(
    {
        "not-robot",
        "empty-robot",
        "missing-name",
        "duplicate-name",
        "missing-parent",
        "missing-child",
        "dangling-parent",
        "dangling-child",
        "two-parents",
        "two-roots",
        "cycle",
        "too-deep",
        "unknown-joint-type",
    }
)
"""Finding codes that leave no single valid link tree (check_urdf would refuse the file)."""


@dataclass(frozen=True)
class TreeEntry:
    """One link of the printed tree, in check_urdf order (children sorted by joint name).

    Attributes:
        link: The link name.
        parent: Its parent link (None for a root).
        joint: The joint from the parent (None for a root).
        depth: 0 for a root, 1 for its children, ...
    """

    link: str
    parent: str | None
    joint: str | None
    depth: int


@dataclass
class Report:
    """The result of :func:`check`.

    Attributes:
        filename: The file checked (None for text).
        robot: The robot name.
        roots: Root links (one in a valid robot).
        tree: Every link reachable from the roots, depth first (empty when too deep to print).
        findings: Problems, sorted by line.
        expanded: True when xacro expanded the file (lines refer to the expanded text).
    """

    filename: str | None
    robot: str
    roots: list[str] = field(default_factory=list)
    tree: list[TreeEntry] = field(default_factory=list)
    findings: list[Finding] = field(default_factory=list)
    expanded: bool = False

    @property
    def root(self) -> str | None:
        """The root link, when there is exactly one."""
        return self.roots[0] if len(self.roots) == 1 else None

    @property
    def counts(self) -> dict[str, int]:
        """Number of findings per severity."""
        return {
            "error": sum(f.severity == "error" for f in self.findings),
            "warning": sum(f.severity == "warning" for f in self.findings),
        }

    @property
    def ok(self) -> bool:
        """True when there is no error-level finding (warnings allowed)."""
        return self.counts["error"] == 0

    @property
    def well_formed(self) -> bool:
        """True when the link tree is valid (what check_urdf needs to print it)."""
        return not any(f.code in STRUCTURAL_CODES and f.severity == "error" for f in self.findings)

    def codes(self) -> list[str]:
        """Return the finding codes, in order (handy in tests and scripts)."""
        return [f.code for f in self.findings]

    def to_dict(self) -> dict[str, object]:
        """Return the report as JSON-ready data (layout :data:`SCHEMA`)."""
        return {
            "schema": SCHEMA,
            "file": self.filename,
            "expanded": self.expanded,
            "robot": self.robot,
            "root": self.root,
            "roots": list(self.roots),
            "tree": [
                {"link": e.link, "parent": e.parent, "joint": e.joint, "depth": e.depth} for e in self.tree
            ],
            "findings": [f.to_dict() for f in self.findings],
            "counts": self.counts,
            "ok": self.ok,
        }


def _tree_entries(tree: TreeInfo) -> list[TreeEntry]:
    out: list[TreeEntry] = []
    seen: set[str] = set()
    for root in tree.roots:
        stack: list[TreeEntry] = [TreeEntry(root, None, None, 0)]
        while stack:
            entry = stack.pop()
            if entry.link in seen:
                continue
            seen.add(entry.link)
            out.append(entry)
            kids = sorted(tree.children.get(entry.link, ()), key=lambda j: j.name)
            stack.extend(TreeEntry(j.child, entry.link, j.name, entry.depth + 1) for j in reversed(kids))
    return out


def check(
    path_or_text: str | os.PathLike[str],
    *,
    args: Mapping[str, str] | None = None,
    package_paths: Iterable[str | os.PathLike[str]] | None = None,
    load_meshes: bool = True,
) -> Report:
    """Check a robot description and report every problem with its line.

    Args:
        path_or_text: A .urdf/.xacro file, or URDF text.
        args: xacro arguments (``{"name": "value"}``).
        package_paths: Extra folders searched first for ROS packages.
        load_meshes: Also load every mesh with trimesh (otherwise only check that files exist).

    Returns:
        The report; ``report.ok`` is False when any finding is an error.

    Raises:
        UrdftkError: When the document cannot be read at all: missing file, malformed XML, a
            DOCTYPE/ENTITY, or a xacro failure.
    """
    source = read_source(path_or_text, args=args, package_paths=package_paths)
    root = source.root
    if not isinstance(root.tag, str) or root.tag != "robot":
        finding = Finding(
            "error",
            "not-robot",
            f"<{root.tag}>",
            root.sourceline,
            f"the root element is <{root.tag}>; a URDF document is a <robot>",
        )
        return Report(source.filename, "", findings=[finding], expanded=source.expanded)
    tree = read_tree(root)
    ctx = Context(root, tree, source.filename, source.resolver, load_meshes)
    entries = _tree_entries(tree) if not tree.cycle and tree.depth <= MAX_TREE_DEPTH else []
    return Report(
        source.filename,
        tree.name,
        roots=list(tree.roots),
        tree=entries,
        findings=run_rules(ctx),
        expanded=source.expanded,
    )


def _plural(n: int, word: str) -> str:
    return f"{n} {word}" + ("" if n == 1 else "s")


def format_text(report: Report, display_name: str | None = None) -> str:
    """Render a report as check_urdf's output followed by one line per finding and a summary.

    Args:
        report: The report.
        display_name: The file name to print (defaults to ``report.filename``).

    Returns:
        The text, ending with a newline.
    """
    name = display_name or report.filename or "<string>"
    lines = [f"robot name is: {report.robot}"]
    if report.well_formed:
        lines.append("---------- Successfully Parsed XML ---------------")
    else:
        lines.append("---------- Parsed XML, but it is not a valid robot (errors below) ---------------")
    children: dict[str, int] = {}
    for entry in report.tree:
        if entry.parent is not None:
            children[entry.parent] = children.get(entry.parent, 0) + 1
    for entry in report.tree:
        if entry.parent is None:
            lines.append(f"root Link: {entry.link} has {children.get(entry.link, 0)} child(ren)")
            counters = [0]
        else:
            del counters[entry.depth :]
            counters[-1] += 1
            counters.append(0)
            lines.append("    " * entry.depth + f"child({counters[-2]}):  {entry.link}")
    if report.roots and not report.tree:
        lines.append(f"(link tree not printed: deeper than {MAX_TREE_DEPTH} joints or cyclic)")
    if report.expanded and report.findings:
        lines.append(f"note: {name} was expanded by xacro; line numbers refer to the expanded URDF")
    for f in report.findings:
        lines.append(f"{format_location(name, f.line)}: {f.severity}: [{f.code}] {f.element}: {f.message}")
    counts = report.counts
    if report.findings:
        lines.append(f"{name}: {_plural(counts['error'], 'error')}, {_plural(counts['warning'], 'warning')}")
    else:
        lines.append(f"{name}: no problems found")
    return "\n".join(lines) + "\n"
