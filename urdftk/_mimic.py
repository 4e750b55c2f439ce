"""Mimic joints: read ``<mimic>`` elements and resolve each follower to an independent master.

A follower's value is ``multiplier * master + offset``. Chains (a mimic of a mimic) are folded into
one affine map onto the root master, so the rest of urdftk sees only independent joints.

Rules, chosen so that every real robot description loads:

* ``<mimic>`` inside a ``fixed`` joint is ignored (the joint cannot move; talos_reduced has these).
* A target that names no joint is looked up inside the follower's own name prefix, the usual xacro
  slip where ``prefix`` was applied to the joint but not to its ``<mimic joint=...>``:
  ``Left_index_q2`` mimicking ``index_q1`` resolves to ``Left_index_q1`` (alex_psyonic_hands).
  This emits a :class:`MimicWarning`; if no such joint exists it is an error.
* A follower that mimics itself, a cycle, a target that cannot move (fixed), or a multi-coordinate
  joint (floating, planar) on either side is a :class:`~urdftk.errors.DescriptionError` naming the line.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Sequence
from dataclasses import dataclass

from urdftk.errors import DescriptionError, MimicWarning, close_names
from urdftk.tree import JointInfo

__all__ = ["ONE_DOF_TYPES", "Mimic", "resolve_mimics"]

ONE_DOF_TYPES = ("revolute", "continuous", "prismatic")
"""Joint types with a single coordinate, the only ones a mimic may link."""

_SEPARATORS = ("_", "/", "-", ":", ".")


@dataclass(frozen=True)
class Mimic:
    """A resolved mimic relation ``follower = multiplier * master + offset``.

    Attributes:
        master: The independent joint the follower follows (the root of any mimic chain).
        multiplier: The composed multiplier.
        offset: The composed offset (radians or metres, as the joint).
    """

    master: str
    multiplier: float
    offset: float


def _float_attr(el, attr: str, default: float, joint: JointInfo, filename: str | None) -> float:
    raw = el.get(attr)
    if raw is None:
        return default
    try:
        value = float(raw)
    except ValueError:
        value = math.nan
    if not math.isfinite(value):
        raise DescriptionError(
            f"joint '{joint.name}': <mimic {attr}=\"{raw}\"> is not a finite number", filename, joint.line
        )
    return value


def _repair_target(follower: str, target: str, joints: dict[str, JointInfo]) -> str | None:
    """Find ``prefix + target`` where ``prefix`` is a separator-terminated prefix of ``follower``."""
    for k in range(len(follower) - 1, 0, -1):
        if follower[k - 1] in _SEPARATORS:
            candidate = follower[:k] + target
            if candidate in joints:
                return candidate
    return None


def resolve_mimics(joints: Sequence[JointInfo], filename: str | None = None) -> dict[str, Mimic]:
    """Resolve every ``<mimic>`` of movable joints to its root master.

    Args:
        joints: The joints of the description (from :class:`urdftk.tree.TreeInfo`).
        filename: For error messages.

    Returns:
        Follower name -> :class:`Mimic`, in document order.

    Raises:
        DescriptionError: Self-mimic, cycles, missing or immovable targets, with the follower's line.
    """
    by_name = {j.name: j for j in joints}
    direct: dict[str, tuple[str, float, float]] = {}
    for j in joints:
        el = j.element.find("mimic")
        if el is None or j.type == "fixed":
            continue
        if j.type not in ONE_DOF_TYPES:
            raise DescriptionError(
                f"joint '{j.name}' of type {j.type} has a <mimic>; "
                f"only {', '.join(ONE_DOF_TYPES)} joints can mimic",
                filename,
                j.line,
            )
        target = el.get("joint") or ""
        if target == j.name:
            raise DescriptionError(f"joint '{j.name}' mimics itself", filename, j.line)
        if target not in by_name:
            repaired = _repair_target(j.name, target, by_name) if target else None
            if repaired is None:
                hint = close_names(target, by_name)
                did = f" (did you mean {', '.join(repr(h) for h in hint)}?)" if hint else ""
                raise DescriptionError(
                    f"joint '{j.name}' mimics '{target}', which is not a joint of this robot{did}",
                    filename,
                    j.line,
                )
            warnings.warn(
                f"{filename or '<string>'}:{j.line}: joint '{j.name}' mimics '{target}', "
                "which does not exist; "
                f"using '{repaired}' (same name prefix as the follower)",
                MimicWarning,
                stacklevel=3,
            )
            target = repaired
        master = by_name[target]
        if master.type not in ONE_DOF_TYPES:
            raise DescriptionError(
                f"joint '{j.name}' mimics '{target}', a {master.type} joint; a mimic target must be "
                f"one of {', '.join(ONE_DOF_TYPES)}",
                filename,
                j.line,
            )
        mult = _float_attr(el, "multiplier", 1.0, j, filename)
        off = _float_attr(el, "offset", 0.0, j, filename)
        direct[j.name] = (target, mult, off)

    resolved: dict[str, Mimic] = {}
    for follower in direct:
        mult, off = 1.0, 0.0
        seen = [follower]
        name = follower
        while name in direct:
            target, m, o = direct[name]
            # value(name) = m * value(target) + o, and value(follower) = mult * value(name) + off
            off = mult * o + off
            mult = mult * m
            if target in seen:
                cycle = " -> ".join([*seen[seen.index(target) :], target])
                raise DescriptionError(f"mimic cycle: {cycle}", filename, by_name[follower].line)
            seen.append(target)
            name = target
        resolved[follower] = Mimic(master=name, multiplier=mult, offset=off)
    return resolved
