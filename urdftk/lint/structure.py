"""Structure rules: names, duplicates, dangling references, parents, roots, cycles and depth."""

from __future__ import annotations

from collections import Counter

from urdftk.description import MAX_TREE_DEPTH
from urdftk.lint._base import Context, Finding

__all__ = ["KNOWN_TOP_LEVEL", "lint"]

KNOWN_TOP_LEVEL = frozenset(
    {"link", "joint", "material", "transmission", "gazebo", "ros2_control", "sensor", "plugin", "frame"}
)
"""Top-level elements that URDF or its common extensions define; anything else gets a warning."""


def _robot_label(ctx: Context) -> str:
    return f"robot '{ctx.tree.name}'" if ctx.tree.name else "<robot>"


def _names(ctx: Context) -> list[Finding]:
    out: list[Finding] = []
    robot = ctx.root
    if not (robot.get("name") or "").strip():
        out.append(
            Finding("error", "missing-name", "<robot>", robot.sourceline, "the robot has no name attribute")
        )
    for kind, items in (("link", ctx.tree.links), ("joint", ctx.tree.joints)):
        for item in items:
            if not item.name:
                out.append(
                    Finding("error", "missing-name", f"<{kind}>", item.line, f"a <{kind}> has no name")
                )
        counts = Counter(i.name for i in items if i.name)
        for name, count in counts.items():
            if count < 2:
                continue
            lines = [i.line for i in items if i.name == name]
            for line in lines[1:]:
                out.append(
                    Finding(
                        "error",
                        "duplicate-name",
                        f"{kind} '{name}'",
                        line,
                        f"{kind} name '{name}' is used {count} times (first on line {lines[0]}); "
                        "names must be unique",
                    )
                )
    return out


def _joint_links(ctx: Context) -> list[Finding]:
    out: list[Finding] = []
    links = {link.name for link in ctx.tree.links}
    for j in ctx.tree.joints:
        element = f"joint '{j.name}'"
        for role, link in (("parent", j.parent), ("child", j.child)):
            if not link:
                out.append(
                    Finding("error", f"missing-{role}", element, j.line, f'joint has no <{role} link="..."/>')
                )
            elif link not in links:
                out.append(
                    Finding(
                        "error",
                        f"dangling-{role}",
                        element,
                        j.line,
                        f"{role} link '{link}' is not defined; add <link name=\"{link}\"/> or fix the name",
                    )
                )
        if j.parent and j.parent == j.child:
            out.append(
                Finding("error", "cycle", element, j.line, f"joint connects link '{j.parent}' to itself")
            )
    for child, joints in ctx.tree.parent_joint.items():
        if len(joints) > 1 and child in links:
            names = ", ".join(f"'{j.name}'" for j in joints)
            for j in joints[1:]:
                out.append(
                    Finding(
                        "error",
                        "two-parents",
                        f"joint '{j.name}'",
                        j.line,
                        f"link '{child}' is the child of {len(joints)} joints ({names}); "
                        "a link has one parent "
                        "(closed chains are not URDF)",
                    )
                )
    return out


def _tree_shape(ctx: Context) -> list[Finding]:
    out: list[Finding] = []
    tree = ctx.tree
    cycle = tree.cycle
    if len(cycle) > 1:
        path = " -> ".join([*cycle, cycle[0]])
        out.append(
            Finding(
                "error",
                "cycle",
                f"link '{cycle[0]}'",
                tree.link_line(cycle[0]),
                f"kinematic loop: {path} (each link is the child of the next)",
            )
        )
    if len(tree.roots) > 1:
        shown = ", ".join(tree.roots[:10]) + (", ..." if len(tree.roots) > 10 else "")
        for name in tree.roots[1:]:
            out.append(
                Finding(
                    "error",
                    "two-roots",
                    f"link '{name}'",
                    tree.link_line(name),
                    f"link '{name}' has no parent joint; "
                    f"the robot has {len(tree.roots)} root links ({shown}). "
                    "Connect them with joints so that one root remains",
                )
            )
    elif not tree.roots and not cycle:
        out.append(
            Finding("error", "cycle", "<robot>", ctx.root.sourceline, "no root link: every link has a parent")
        )
    if tree.depth > MAX_TREE_DEPTH:
        out.append(
            Finding(
                "error",
                "too-deep",
                _robot_label(ctx),
                ctx.root.sourceline,
                f"the kinematic chain is {tree.depth} joints deep; at most {MAX_TREE_DEPTH} are supported",
            )
        )
    return out


def _unknown_elements(ctx: Context) -> list[Finding]:
    out: list[Finding] = []
    for el in ctx.root:
        if isinstance(el.tag, str) and "}" not in el.tag and el.tag not in KNOWN_TOP_LEVEL:
            out.append(
                Finding(
                    "warning",
                    "unknown-element",
                    f"<{el.tag}>",
                    el.sourceline,
                    f"<{el.tag}> is not a URDF element and is ignored (typo of <link> or <joint>?)",
                )
            )
    return out


def lint(ctx: Context) -> list[Finding]:
    """Check names, references and the shape of the link tree.

    Args:
        ctx: The document.

    Returns:
        The findings.
    """
    if not ctx.tree.links:
        return [
            *_names(ctx),
            Finding(
                "error",
                "empty-robot",
                _robot_label(ctx),
                ctx.root.sourceline,
                "the robot has no <link> elements",
            ),
            *_unknown_elements(ctx),
        ]
    return [*_names(ctx), *_joint_links(ctx), *_tree_shape(ctx), *_unknown_elements(ctx)]
