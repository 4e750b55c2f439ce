"""Limit rules: missing <limit>, missing effort/velocity, lower > upper, negative effort/velocity."""

from __future__ import annotations

from urdftk.lint._base import Context, Finding, elements

__all__ = ["lint"]

_NEEDS_LIMIT = frozenset({"revolute", "prismatic"})


def lint(ctx: Context) -> list[Finding]:
    """Check the ``<limit>`` of every joint.

    urdfdom refuses a revolute or prismatic joint without ``<limit>``, and a ``<limit>`` without
    ``effort`` or ``velocity``; so do we.

    Args:
        ctx: The document.

    Returns:
        The findings.
    """
    out: list[Finding] = []
    for j in ctx.tree.joints:
        element = f"joint '{j.name}'"
        limit = next(elements(j.element, "limit"), None)
        if limit is None:
            if j.type in _NEEDS_LIMIT:
                out.append(
                    Finding(
                        "error",
                        "missing-limit",
                        element,
                        j.line,
                        f"{j.type} joint has no <limit>; "
                        "add <limit lower=... upper=... effort=... velocity=.../>",
                    )
                )
            continue
        for attr in ("effort", "velocity"):
            if limit.get(attr) is None:
                out.append(
                    Finding(
                        "error",
                        "missing-limit-attribute",
                        element,
                        limit.sourceline,
                        f"<limit> has no '{attr}' attribute (urdfdom requires it)",
                    )
                )
        for attr in ("effort", "velocity"):
            value = ctx.number(limit, attr)
            if value is not None and value < 0:
                out.append(
                    Finding(
                        "error",
                        f"negative-{attr}",
                        element,
                        limit.sourceline,
                        f"{attr} limit is {value:g}; it must be >= 0",
                    )
                )
        if j.type not in _NEEDS_LIMIT:
            continue
        lower = ctx.number(limit, "lower", 0.0)
        upper = ctx.number(limit, "upper", 0.0)
        if lower is None or upper is None:
            continue
        if lower > upper:
            out.append(
                Finding(
                    "error",
                    "lower-above-upper",
                    element,
                    limit.sourceline,
                    f"lower limit {lower:g} is above upper limit {upper:g}",
                )
            )
        elif lower == upper:
            missing = [a for a in ("lower", "upper") if limit.get(a) is None]
            note = f" ({' and '.join(missing)} missing: defaults to 0)" if missing else ""
            out.append(
                Finding(
                    "warning",
                    "zero-range",
                    element,
                    limit.sourceline,
                    f"lower == upper == {lower:g}{note}: the joint cannot move; "
                    "make it fixed or widen the range",
                )
            )
    return out
