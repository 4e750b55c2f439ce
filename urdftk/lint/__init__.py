"""The rules behind ``urdftk check``, one module per family, each a ``lint(ctx) -> list[Finding]``.

Families: :mod:`~urdftk.lint.structure`, :mod:`~urdftk.lint.numbers`, :mod:`~urdftk.lint.limits`,
:mod:`~urdftk.lint.mimic`, :mod:`~urdftk.lint.physics`, :mod:`~urdftk.lint.geometry`,
:mod:`~urdftk.lint.materials` and :mod:`~urdftk.lint.meshes`. Every rule works on the XML tree
with line numbers, so it reports every problem even in a file that would not load.
"""

from __future__ import annotations

from urdftk.lint import geometry, limits, materials, meshes, mimic, numbers, physics, structure
from urdftk.lint._base import Context, Finding, Severity

__all__ = ["RULES", "Context", "Finding", "Severity", "run_rules"]

RULES = (
    structure.lint,
    numbers.lint,
    limits.lint,
    mimic.lint,
    physics.lint,
    geometry.lint,
    materials.lint,
    meshes.lint,
)
"""Every rule family, in the order their findings are listed for one line."""


def run_rules(ctx: Context) -> list[Finding]:
    """Run every rule on a ``<robot>`` document.

    Args:
        ctx: The document.

    Returns:
        The findings, sorted by line (findings without a line last), duplicates removed.
    """
    found: list[Finding] = []
    for rule in RULES:
        found.extend(rule(ctx))
    unique = list(dict.fromkeys(found))
    return sorted(unique, key=lambda f: (f.line is None, f.line or 0))
