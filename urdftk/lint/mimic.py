"""Mimic rules: missing target, self-mimic, mimic cycles, chains of mimics, mimic on a fixed joint."""

from __future__ import annotations

from urdftk.lint._base import Context, Finding, elements

__all__ = ["lint"]


def lint(ctx: Context) -> list[Finding]:
    """Check every ``<mimic>``.

    Args:
        ctx: The document.

    Returns:
        The findings.
    """
    out: list[Finding] = []
    joints = {j.name: j for j in ctx.tree.joints if j.name}
    target: dict[str, str] = {}
    lines: dict[str, int | None] = {}
    for j in ctx.tree.joints:
        mimic = next(elements(j.element, "mimic"), None)
        if mimic is None:
            continue
        element = f"joint '{j.name}'"
        name = mimic.get("joint") or ""
        if not name:
            out.append(
                Finding(
                    "error",
                    "mimic-missing-joint",
                    element,
                    mimic.sourceline,
                    "<mimic> has no joint attribute",
                )
            )
        elif name == j.name:
            out.append(Finding("error", "mimic-self", element, mimic.sourceline, "joint mimics itself"))
        elif name not in joints:
            out.append(
                Finding(
                    "error",
                    "mimic-missing-joint",
                    element,
                    mimic.sourceline,
                    f"mimics joint '{name}', which is not defined",
                )
            )
        else:
            target[j.name] = name
            lines[j.name] = mimic.sourceline
            if j.type == "fixed" or joints[name].type == "fixed":
                which = "joint" if j.type == "fixed" else f"its target '{name}'"
                out.append(
                    Finding(
                        "warning",
                        "mimic-fixed",
                        element,
                        mimic.sourceline,
                        f"{which} is fixed; the mimic does nothing",
                    )
                )
    reported: set[str] = set()
    for start in target:
        path = [start]
        node = target[start]
        while node in target and node not in path:
            path.append(node)
            node = target[node]
        if node in path:
            loop = path[path.index(node) :]
            if not reported.intersection(loop):
                reported.update(loop)
                shown = " -> ".join([*loop, loop[0]])
                out.append(
                    Finding(
                        "error", "mimic-cycle", f"joint '{loop[0]}'", lines[loop[0]], f"mimic loop: {shown}"
                    )
                )
        elif len(path) > 1 and not reported.intersection(path):
            master = target[start]
            out.append(
                Finding(
                    "warning",
                    "mimic-chain",
                    f"joint '{start}'",
                    lines[start],
                    f"mimics '{master}', which itself mimics '{target[master]}'; "
                    "Pinocchio and some tools only "
                    f"support one level: mimic '{node}' directly",
                )
            )
    return out
