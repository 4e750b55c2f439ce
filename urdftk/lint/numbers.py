"""Number rules: joint types, unparsable or non-finite numbers, missing numeric attributes, axes."""

from __future__ import annotations

import math

from urdftk.description import JOINT_TYPES
from urdftk.lint._base import Context, Finding, describe, elements, parse_numbers
from urdftk.lint.geometry import GEOMETRY_DIMENSIONS

__all__ = ["NUMERIC_ATTRIBUTES", "REQUIRED_ATTRIBUTES", "lint"]

_INERTIA = ("ixx", "ixy", "ixz", "iyy", "iyz", "izz")

NUMERIC_ATTRIBUTES: dict[tuple[str, str], int] = {
    ("origin", "xyz"): 3,
    ("origin", "rpy"): 3,
    ("axis", "xyz"): 3,
    ("limit", "lower"): 1,
    ("limit", "upper"): 1,
    ("limit", "effort"): 1,
    ("limit", "velocity"): 1,
    ("safety_controller", "soft_lower_limit"): 1,
    ("safety_controller", "soft_upper_limit"): 1,
    ("safety_controller", "k_position"): 1,
    ("safety_controller", "k_velocity"): 1,
    ("dynamics", "damping"): 1,
    ("dynamics", "friction"): 1,
    ("calibration", "rising"): 1,
    ("calibration", "falling"): 1,
    ("mimic", "multiplier"): 1,
    ("mimic", "offset"): 1,
    ("mass", "value"): 1,
    **{("inertia", a): 1 for a in _INERTIA},
    ("box", "size"): 3,
    ("cylinder", "radius"): 1,
    ("cylinder", "length"): 1,
    ("capsule", "radius"): 1,
    ("capsule", "length"): 1,
    ("sphere", "radius"): 1,
    ("mesh", "scale"): 3,
    ("color", "rgba"): 4,
}
"""(element, attribute) -> how many numbers URDF expects there (inside <link>, <joint>, <material>)."""

REQUIRED_ATTRIBUTES: dict[str, tuple[str, ...]] = {
    "mass": ("value",),
    "inertia": _INERTIA,
    "box": ("size",),
    "cylinder": ("radius", "length"),
    "capsule": ("radius", "length"),
    "sphere": ("radius",),
    "color": ("rgba",),
}
"""Elements whose numeric attributes urdfdom requires."""

_TYPED_OWNERS = frozenset({"link", "joint", "material"})
_PARENTS: dict[str, frozenset[str]] = {
    "origin": frozenset({"joint", "inertial", "visual", "collision"}),
    "mass": frozenset({"inertial"}),
    "inertia": frozenset({"inertial"}),
    "color": frozenset({"material"}),
    **{
        tag: frozenset({"joint"})
        for tag in ("axis", "limit", "safety_controller", "dynamics", "calibration", "mimic")
    },
    **{tag: frozenset({"geometry"}) for tag in ("box", "cylinder", "capsule", "sphere", "mesh")},
}
_TEXT_ATTRIBUTES = frozenset({"name", "link", "joint", "type", "filename", "reference", "xmlns"})
_AXIS_TYPES = frozenset({"revolute", "continuous", "prismatic", "planar"})


def _standard_place(el) -> bool:
    """Whether ``el`` sits where URDF defines it (extensions elsewhere are only checked for NaN/inf)."""
    parents = _PARENTS.get(el.tag)
    parent = el.getparent()
    return parents is not None and parent is not None and parent.tag in parents


def _typed(ctx: Context) -> list[Finding]:
    out: list[Finding] = []
    for owner in ctx.root:
        if not isinstance(owner.tag, str) or owner.tag not in _TYPED_OWNERS:
            continue
        for el in owner.iter():
            if not isinstance(el.tag, str) or not _standard_place(el):
                continue
            for attr in REQUIRED_ATTRIBUTES.get(el.tag, ()):
                if el.get(attr) is None:
                    out.append(
                        Finding(
                            "error",
                            "missing-attribute",
                            describe(el),
                            el.sourceline,
                            f"<{el.tag}> needs a '{attr}' attribute",
                        )
                    )
            for attr, text in el.attrib.items():
                size = NUMERIC_ATTRIBUTES.get((el.tag, attr))
                if size is not None:
                    out.extend(_check_value(el, attr, text, size))
    return out


def _check_value(el, attr: str, text: str, size: int) -> list[Finding]:
    values = parse_numbers(text)
    where = describe(el)
    if values is not None and len(values) != size and (el.tag, attr) in GEOMETRY_DIMENSIONS:
        return []  # a count error in a shape is reported by the geometry rules
    if values is None or len(values) != size:
        want = "a number" if size == 1 else f"{size} numbers"
        return [Finding("error", "bad-number", where, el.sourceline, f'{attr}="{text}" must be {want}')]
    if not all(math.isfinite(v) for v in values):
        return [Finding("error", "not-finite", where, el.sourceline, f'{attr}="{text}" is not finite')]
    return []


def _untyped(ctx: Context) -> list[Finding]:
    """NaN or infinity in any other attribute of the document (extensions included)."""
    out: list[Finding] = []
    for el in ctx.root.iter():
        if not isinstance(el.tag, str):
            continue
        top = el
        while top.getparent() is not None and top.getparent() is not ctx.root:
            top = top.getparent()
        typed = top is not ctx.root and top.tag in _TYPED_OWNERS and _standard_place(el)
        for attr, text in el.attrib.items():
            if attr in _TEXT_ATTRIBUTES or (typed and (el.tag, attr) in NUMERIC_ATTRIBUTES):
                continue
            values = parse_numbers(text)
            if values and not all(math.isfinite(v) for v in values):
                out.append(
                    Finding(
                        "error", "not-finite", describe(el), el.sourceline, f'{attr}="{text}" is not finite'
                    )
                )
    return out


def _joints(ctx: Context) -> list[Finding]:
    out: list[Finding] = []
    for j in ctx.tree.joints:
        element = f"joint '{j.name}'"
        if j.type not in JOINT_TYPES:
            what = f"unknown type '{j.type}'" if j.type else "no type"
            out.append(
                Finding(
                    "error",
                    "unknown-joint-type",
                    element,
                    j.line,
                    f"joint has {what}; use one of {', '.join(JOINT_TYPES)}",
                )
            )
        if j.type not in _AXIS_TYPES:
            continue
        for axis in elements(j.element, "axis"):
            xyz = ctx.vector(axis, "xyz", 3)
            if xyz is None:
                continue
            norm = math.sqrt(sum(v * v for v in xyz))
            if norm < 1e-12:
                out.append(
                    Finding(
                        "error",
                        "zero-axis",
                        element,
                        axis.sourceline,
                        "axis xyz is zero; the joint has no direction",
                    )
                )
            elif abs(norm - 1.0) > 1e-6:
                out.append(
                    Finding(
                        "warning",
                        "non-unit-axis",
                        element,
                        axis.sourceline,
                        f'axis xyz="{axis.get("xyz")}" has length {norm:.6g}; '
                        "tools may or may not normalize it",
                    )
                )
    return out


def lint(ctx: Context) -> list[Finding]:
    """Check joint types, every number in the document, and joint axes.

    Args:
        ctx: The document.

    Returns:
        The findings.
    """
    return [*_joints(ctx), *_typed(ctx), *_untyped(ctx)]
