"""Geometry rules: every <visual>/<collision> has one known shape with sane dimensions."""

from __future__ import annotations

from urdftk.lint._base import Context, Finding, describe, elements, parse_numbers

__all__ = ["GEOMETRY_DIMENSIONS", "SHAPES", "lint"]

SHAPES = ("box", "cylinder", "sphere", "mesh", "capsule")
"""Shapes URDF knows (``capsule`` is a common extension)."""

GEOMETRY_DIMENSIONS: dict[tuple[str, str], int] = {
    ("box", "size"): 3,
    ("cylinder", "radius"): 1,
    ("cylinder", "length"): 1,
    ("capsule", "radius"): 1,
    ("capsule", "length"): 1,
    ("sphere", "radius"): 1,
    ("mesh", "scale"): 3,
}
"""Shape attributes this module judges (count and sign), with how many numbers each takes."""


def _shape(shape) -> list[Finding]:
    out: list[Finding] = []
    for (tag, attr), size in GEOMETRY_DIMENSIONS.items():
        if tag != shape.tag or shape.get(attr) is None:
            continue
        text = shape.get(attr)
        values = parse_numbers(text)
        if values is None or any(v != v or abs(v) == float("inf") for v in values):
            continue  # reported by the number rules
        problem = ""
        if len(values) != size:
            problem = f'{attr}="{text}" has {len(values)} value(s); {size} expected'
        elif tag == "mesh" and all(v != 0 for v in values) and any(v < 0 for v in values):
            out.append(
                Finding(
                    "warning",
                    "mirrored-mesh",
                    describe(shape),
                    shape.sourceline,
                    f'scale="{text}" mirrors the mesh (its faces turn inside out); '
                    "make sure this is intended",
                )
            )
        elif any(v <= 0 for v in values):
            problem = f'{attr}="{text}" must be positive' + (" in every direction" if size > 1 else "")
        if problem:
            out.append(Finding("error", "bad-geometry", describe(shape), shape.sourceline, problem))
    if shape.tag == "mesh" and not (shape.get("filename") or "").strip():
        out.append(
            Finding(
                "error", "missing-attribute", describe(shape), shape.sourceline, "<mesh> needs a 'filename'"
            )
        )
    return out


def lint(ctx: Context) -> list[Finding]:
    """Check the geometry of every visual and collision.

    Args:
        ctx: The document.

    Returns:
        The findings.
    """
    out: list[Finding] = []
    for link in ctx.tree.links:
        for kind in ("visual", "collision"):
            for item in elements(link.element, kind):
                geometry = next(elements(item, "geometry"), None)
                if geometry is None:
                    out.append(
                        Finding(
                            "error",
                            "missing-geometry",
                            describe(item),
                            item.sourceline,
                            f"<{kind}> has no <geometry>",
                        )
                    )
                    continue
                shapes = [c for c in geometry if isinstance(c.tag, str)]
                if not shapes:
                    out.append(
                        Finding(
                            "error",
                            "missing-geometry",
                            describe(geometry),
                            geometry.sourceline,
                            f"<geometry> is empty; add one of {', '.join(f'<{s}>' for s in SHAPES)}",
                        )
                    )
                    continue
                shape = shapes[0]
                if shape.tag not in SHAPES:
                    out.append(
                        Finding(
                            "error",
                            "unknown-geometry",
                            describe(shape),
                            shape.sourceline,
                            f"unknown shape <{shape.tag}>; use one of {', '.join(f'<{s}>' for s in SHAPES)}",
                        )
                    )
                    continue
                out.extend(_shape(shape))
    return out
