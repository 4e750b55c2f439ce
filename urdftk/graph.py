"""``urdftk graph``: urdf_to_graphviz's picture of a robot, safely.

Links are boxes, joints are blue ellipses, and each parent-link -> joint edge is labelled with the
joint origin (``xyz`` and ``rpy``), as urdf_to_graphviz draws it. Unlike urdf_to_graphviz, no robot
text ever reaches a shell: node identifiers are generated (``link0``, ``joint0``), names only
appear inside escaped DOT strings, and ``dot`` runs from an argument list with the DOT text on
its standard input.

Example:
    >>> from urdftk.graph import write_graph
    >>> write_graph("examples/robots/robot0_description/urdf/robot0.urdf", "robot0.svg")  # doctest: +SKIP
"""

from __future__ import annotations

import os
import shutil
import subprocess
from collections.abc import Iterable, Mapping
from pathlib import Path

from lxml import etree

from urdftk._atomic import write_atomic
from urdftk._read import read_source
from urdftk.errors import DescriptionError, UrdftkError
from urdftk.lint._base import elements, parse_numbers
from urdftk.tree import JointInfo, TreeInfo, read_tree

__all__ = [
    "DOT_TIMEOUT_S",
    "FORMATS",
    "dot_string",
    "output_format",
    "read_robot",
    "render",
    "to_dot",
    "write_dot",
    "write_graph",
]

FORMATS = {".gv": None, ".dot": None, ".svg": "svg", ".png": "png", ".pdf": "pdf"}
"""Output suffix -> Graphviz ``-T`` format (None: the DOT text itself)."""

DOT_TIMEOUT_S = 300.0
"""Longest a ``dot`` run may take, in seconds."""


def dot_string(text: str) -> str:
    r"""Quote ``text`` as a DOT string whose label shows exactly ``text``.

    Backslashes and quotes are escaped (so ``\\N`` and friends show literally), and line breaks
    become DOT's ``\\n`` (centred line break).

    Args:
        text: Any text (a robot, link or joint name).

    Returns:
        A double-quoted DOT string.
    """
    body = text.replace("\\", "\\\\").replace('"', '\\"')
    body = body.replace("\r\n", "\n").replace("\r", "\n").replace("\n", "\\n")
    return f'"{body}"'


def _fmt(values: list[float] | None, raw: str | None) -> str:
    if values is None:
        return raw if raw is not None else "0 0 0"
    return " ".join(f"{v:g}" for v in values)


def _origin_label(joint: JointInfo) -> str:
    origin = next(elements(joint.element, "origin"), None)
    xyz_raw = origin.get("xyz") if origin is not None else None
    rpy_raw = origin.get("rpy") if origin is not None else None
    xyz = parse_numbers(xyz_raw) if xyz_raw is not None else [0.0, 0.0, 0.0]
    rpy = parse_numbers(rpy_raw) if rpy_raw is not None else [0.0, 0.0, 0.0]
    return f"xyz: {_fmt(xyz, xyz_raw)} \nrpy: {_fmt(rpy, rpy_raw)}"


def _ordered(tree: TreeInfo) -> tuple[list[str], list[JointInfo]]:
    """Links and joints in urdf_to_graphviz order (depth first, children by joint name), then the rest."""
    links: list[str] = []
    joints: list[JointInfo] = []
    seen: set[str] = set()
    defined = {lk.name for lk in tree.links}
    for root in tree.roots:
        stack = [root]
        while stack:
            link = stack.pop()
            if link in seen or link not in defined:
                continue
            seen.add(link)
            links.append(link)
            kids = sorted(tree.children.get(link, ()), key=lambda j: j.name)
            joints.extend(kids)
            stack.extend(j.child for j in reversed(kids))
    links.extend(dict.fromkeys(lk.name for lk in tree.links if lk.name not in seen))
    listed = {id(j) for j in joints}
    joints.extend(j for j in tree.joints if id(j) not in listed)
    return links, joints


def to_dot(tree: TreeInfo) -> str:
    """Draw a robot's structure as Graphviz DOT text.

    Args:
        tree: The structure, from :func:`urdftk.tree.read_tree`.

    Returns:
        The DOT text: links as boxes, joints as blue ellipses, edges labelled with xyz/rpy.
        Links that joints name but that are not defined are drawn as dashed red boxes.
    """
    links, joints = _ordered(tree)
    ids = {name: f"link{i}" for i, name in enumerate(links)}
    undefined = [n for j in joints for n in (j.parent, j.child) if n not in ids]
    for name in dict.fromkeys(undefined):
        ids[name] = f"link{len(ids)}"
    out = ["digraph G {", f"graph [label={dot_string(tree.name)}, labelloc=t];", "node [shape=box];"]
    out.extend(f"{ids[name]} [label={dot_string(name)}];" for name in links)
    out.extend(
        f"{ids[name]} [label={dot_string(name + ' (undefined)')}, style=dashed, color=red];"
        for name in dict.fromkeys(undefined)
    )
    out.append("node [shape=ellipse, color=blue, fontcolor=blue];")
    for i, j in enumerate(joints):
        out.append(f"joint{i} [label={dot_string(j.name)}];")
        out.append(f"{ids[j.parent]} -> joint{i} [label={dot_string(_origin_label(j))}];")
        out.append(f"joint{i} -> {ids[j.child]};")
    out.append("}")
    return "\n".join(out) + "\n"


def render(dot_text: str, fmt: str, *, dot: str = "dot") -> bytes:
    """Run Graphviz ``dot`` on DOT text (argument list, no shell; the text goes to its stdin).

    Args:
        dot_text: The graph.
        fmt: A ``dot -T`` format such as ``svg``, ``png`` or ``pdf``.
        dot: The ``dot`` program (looked up on PATH).

    Returns:
        The rendered file's bytes.

    Raises:
        UrdftkError: If ``dot`` is missing, fails or takes longer than :data:`DOT_TIMEOUT_S`.
    """
    exe = shutil.which(dot)
    if exe is None:
        raise UrdftkError(
            f"Graphviz '{dot}' not found on PATH; install it "
            "(Debian/Ubuntu: `sudo apt-get install graphviz`) "
            "or write a .gv file instead"
        )
    try:
        proc = subprocess.run(
            [exe, f"-T{fmt}"],
            input=dot_text.encode("utf-8"),
            capture_output=True,
            timeout=DOT_TIMEOUT_S,
            check=False,
            shell=False,
        )
    except subprocess.TimeoutExpired:
        raise UrdftkError(f"'{exe} -T{fmt}' took longer than {DOT_TIMEOUT_S:g} s") from None
    if proc.returncode != 0 or not proc.stdout:
        detail = " ".join(proc.stderr.decode("utf-8", "replace").split())[:300]
        raise UrdftkError(f"'{exe} -T{fmt}' failed (exit {proc.returncode}): {detail}")
    return proc.stdout


def read_robot(
    path_or_text: str | os.PathLike[str],
    *,
    args: Mapping[str, str] | None = None,
    package_paths: Iterable[str | os.PathLike[str]] | None = None,
) -> tuple[etree._Element, TreeInfo]:
    """Read a robot file (xacro expanded when needed) and return its ``<robot>`` element and structure.

    Args:
        path_or_text: A .urdf/.xacro file or URDF text.
        args: xacro arguments.
        package_paths: Extra folders searched first for ROS packages.

    Returns:
        ``(root, tree)``.

    Raises:
        UrdftkError: If the file cannot be read or its root is not ``<robot>``.
    """
    source = read_source(path_or_text, args=args, package_paths=package_paths)
    root: etree._Element = source.root
    if not isinstance(root.tag, str) or root.tag != "robot":
        raise DescriptionError(
            f"root element is <{root.tag}>, expected <robot>", source.filename, root.sourceline
        )
    return root, read_tree(root)


def output_format(output: str | os.PathLike[str]) -> str | None:
    """Return the ``dot -T`` format for an output file (None for DOT text).

    Raises:
        UrdftkError: For a suffix other than those in :data:`FORMATS`.
    """
    suffix = Path(output).suffix.lower()
    if suffix not in FORMATS:
        raise UrdftkError(f"{output}: unknown output format '{suffix}'; use one of {', '.join(FORMATS)}")
    return FORMATS[suffix]


def write_dot(dot_text: str, output: str | os.PathLike[str]) -> Path:
    """Write DOT text to ``output`` as DOT or rendered by ``dot``, chosen by suffix, atomically.

    Args:
        dot_text: The graph.
        output: .gv/.dot, .svg, .png or .pdf file.

    Returns:
        The path written.

    Raises:
        UrdftkError: For an unknown suffix or a ``dot`` failure (nothing is written then).
    """
    fmt = output_format(output)
    write_atomic(output, dot_text if fmt is None else render(dot_text, fmt))
    return Path(output)


def write_graph(
    path_or_text: str | os.PathLike[str],
    output: str | os.PathLike[str],
    *,
    args: Mapping[str, str] | None = None,
    package_paths: Iterable[str | os.PathLike[str]] | None = None,
) -> Path:
    """Draw a robot to ``output`` (.gv/.dot text, or .svg/.png/.pdf through ``dot``), atomically.

    Args:
        path_or_text: A .urdf/.xacro file or URDF text.
        output: The file to write; its suffix chooses the format.
        args: xacro arguments.
        package_paths: Extra folders searched first for ROS packages.

    Returns:
        The path written.

    Raises:
        UrdftkError: For an unreadable robot, an unknown suffix, or a ``dot`` failure.
    """
    output_format(output)
    _, tree = read_robot(path_or_text, args=args, package_paths=package_paths)
    return write_dot(to_dot(tree), output)
