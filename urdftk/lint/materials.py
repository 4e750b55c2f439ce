"""Material rules: unique top-level names (as urdfdom), and every material used defined somewhere."""

from __future__ import annotations

from urdftk.lint._base import Context, Finding, describe, elements

__all__ = ["lint"]


def _has_look(material) -> bool:
    return any(True for _ in elements(material, "color")) or any(True for _ in elements(material, "texture"))


def lint(ctx: Context) -> list[Finding]:
    """Check top-level and per-visual materials.

    urdfdom refuses a duplicate top-level material (an error here). A visual naming a material that
    is defined nowhere, or a material with neither colour nor texture, gets a warning: urdfdom
    loads them, but the visual has no colour.

    Args:
        ctx: The document.

    Returns:
        The findings.
    """
    out: list[Finding] = []
    defined: dict[str, int | None] = {}
    for mat in elements(ctx.root, "material"):
        name = mat.get("name") or ""
        if not name:
            out.append(
                Finding("error", "missing-name", "<material>", mat.sourceline, "a <material> has no name")
            )
            continue
        if name in defined:
            out.append(
                Finding(
                    "error",
                    "duplicate-material",
                    f"material '{name}'",
                    mat.sourceline,
                    f"material '{name}' is already defined on line {defined[name]} "
                    "(urdfdom refuses duplicates)",
                )
            )
            continue
        defined[name] = mat.sourceline
        if not _has_look(mat):
            out.append(
                Finding(
                    "warning",
                    "empty-material",
                    f"material '{name}'",
                    mat.sourceline,
                    "material has no <color> or <texture>",
                )
            )
    for link in ctx.tree.links:
        for visual in elements(link.element, "visual"):
            for mat in elements(visual, "material"):
                name = mat.get("name")
                if name is None:
                    out.append(
                        Finding(
                            "error",
                            "missing-name",
                            describe(mat),
                            mat.sourceline,
                            "a visual <material> needs a name",
                        )
                    )
                elif not _has_look(mat) and name not in defined:
                    out.append(
                        Finding(
                            "warning",
                            "undefined-material",
                            describe(mat),
                            mat.sourceline,
                            f"material '{name}' is not defined; add a top-level <material name=\"{name}\"> "
                            "with a <color> or give this one a <color>",
                        )
                    )
    return out
