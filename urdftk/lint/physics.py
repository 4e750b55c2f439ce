"""Physics rules: masses and inertia tensors of the links that move.

A link *moves* when it is the child of a non-fixed joint, or hangs below one through fixed
joints. Links joined by fixed joints form one rigid body (as Pinocchio lumps them), so a zero-mass
tool frame fixed to a heavy wrist is fine; a moving body whose total mass is zero is not.
"""

from __future__ import annotations

from collections import defaultdict

import numpy as np

from urdftk.lint._base import MOVING_JOINT_TYPES, Context, Finding, elements
from urdftk.tree import LinkInfo

__all__ = ["lint"]

_INERTIA = ("ixx", "ixy", "ixz", "iyy", "iyz", "izz")


def _mass(ctx: Context, link: LinkInfo) -> tuple[float | None, int | None]:
    inertial = next(elements(link.element, "inertial"), None)
    if inertial is None:
        return None, None
    mass_el = next(elements(inertial, "mass"), None)
    if mass_el is None:
        return None, inertial.sourceline
    return ctx.number(mass_el, "value"), mass_el.sourceline


def _inertia_findings(ctx: Context, link: LinkInfo, mass: float | None, moving: bool) -> list[Finding]:
    inertial = next(elements(link.element, "inertial"), None)
    el = next(elements(inertial, "inertia"), None) if inertial is not None else None
    if el is None:
        return []
    values = [ctx.number(el, a) for a in _INERTIA]
    if any(v is None for v in values):
        return []
    ixx, ixy, ixz, iyy, iyz, izz = values
    tensor = np.array([[ixx, ixy, ixz], [ixy, iyy, iyz], [ixz, iyz, izz]], dtype=float)
    if not tensor.any() and not mass:
        return []  # a massless link: nothing to check
    eig = np.linalg.eigvalsh(tensor)
    severity = "error" if moving else "warning"
    element = f"link '{link.name}'"
    shown = ", ".join(f"{v:.6g}" for v in eig)
    if eig[0] <= 0 or eig[0] <= 1e-12 * eig[-1]:
        return [
            Finding(
                severity,
                "inertia-not-positive-definite",
                element,
                el.sourceline,
                f"inertia tensor is not positive definite (principal moments {shown})",
            )
        ]
    a, b, c = eig
    if a + b < c - 1e-6 * (a + b + c):
        return [
            Finding(
                severity,
                "inertia-triangle",
                element,
                el.sourceline,
                f"principal moments {shown} break the triangle inequality ({a:.6g} + {b:.6g} < {c:.6g}); "
                "no rigid body has this inertia",
            )
        ]
    return []


def _required(link: LinkInfo) -> list[Finding]:
    out: list[Finding] = []
    for inertial in elements(link.element, "inertial"):
        for tag in ("mass", "inertia"):
            if next(elements(inertial, tag), None) is None:
                out.append(
                    Finding(
                        "error",
                        f"missing-{tag}",
                        f"link '{link.name}'",
                        inertial.sourceline,
                        f"<inertial> has no <{tag}> (urdfdom requires it)",
                    )
                )
    return out


def lint(ctx: Context) -> list[Finding]:
    """Check masses and inertias.

    Args:
        ctx: The document.

    Returns:
        The findings.
    """
    out: list[Finding] = []
    moving = ctx.moving_links
    body_mass: dict[str, float] = defaultdict(float)
    has_inertial: set[str] = set()
    zero_mass: dict[str, tuple[LinkInfo, int | None]] = {}
    for link in ctx.tree.links:
        mass, line = _mass(ctx, link)
        head = ctx.body_of.get(link.name, link.name)
        if line is not None:
            has_inertial.add(head)
        if mass is not None:
            body_mass[head] += max(mass, 0.0)
            if mass < 0:
                out.append(
                    Finding(
                        "error",
                        "non-positive-mass",
                        f"link '{link.name}'",
                        line,
                        f"mass is {mass:g}; a mass must be positive",
                    )
                )
            elif mass == 0 and link.name in moving:
                zero_mass.setdefault(head, (link, line))
        out.extend(_inertia_findings(ctx, link, mass, link.name in moving))
        out.extend(_required(link))
    for head, (link, line) in zero_mass.items():
        if body_mass[head] <= 0:
            out.append(
                Finding(
                    "error",
                    "non-positive-mass",
                    f"link '{link.name}'",
                    line,
                    "mass is 0 on a moving link (and nothing fixed to it has mass); dynamics will fail",
                )
            )
    for j in ctx.tree.joints:
        if j.type not in MOVING_JOINT_TYPES or j.child not in moving or j.child in has_inertial:
            continue
        if ctx.body_of.get(j.child) != j.child:
            continue
        out.append(
            Finding(
                "warning",
                "missing-inertial",
                f"link '{j.child}'",
                ctx.tree.link_line(j.child),
                f"link moves (child of {j.type} joint '{j.name}') but neither it nor anything fixed to it "
                "has an <inertial>; simulators and dynamics treat it as massless",
            )
        )
    return out
