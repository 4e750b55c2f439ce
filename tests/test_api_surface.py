"""Public API hygiene: an explicit ``__all__`` everywhere, and ``tf`` stays a leaf package."""

from __future__ import annotations

import ast
import importlib
import pkgutil
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]


def _modules(package: str) -> list[str]:
    pkg = importlib.import_module(package)
    names = [package]
    for info in pkgutil.walk_packages(pkg.__path__, prefix=f"{package}."):
        names.append(info.name)
    return names


ALL_MODULES = [m for p in ("urdftk", "tf") for m in _modules(p) if not m.endswith("__main__")]


def test_modules_were_found():
    assert "urdftk.resources" in ALL_MODULES
    assert "tf.messages" in ALL_MODULES


@pytest.mark.parametrize("name", ALL_MODULES)
def test_all_is_explicit_and_importable(name):
    """Every module declares ``__all__`` (its order is enforced by ruff's RUF022)."""
    module = importlib.import_module(name)
    exported = getattr(module, "__all__", None)
    assert exported is not None, f"{name} has no __all__"
    assert len(set(exported)) == len(exported), f"{name}.__all__ has duplicates"
    for attr in exported:
        assert hasattr(module, attr), f"{name}.__all__ names {attr!r}, which is not importable"


def test_tf_never_imports_urdftk():
    offenders = []
    for path in sorted((REPO / "tf").rglob("*.py")):
        tree = ast.parse(path.read_text(encoding="utf-8"))
        for node in ast.walk(tree):
            mods = []
            if isinstance(node, ast.Import):
                mods = [a.name for a in node.names]
            elif isinstance(node, ast.ImportFrom) and node.module:
                mods = [node.module]
            offenders += [
                f"{path.relative_to(REPO)}:{node.lineno}" for m in mods if m.split(".")[0] == "urdftk"
            ]
    assert offenders == []


def test_top_level_import_is_light():
    """``import urdftk`` must not pull Pinocchio or yourdfpy (the xacro command starts fast)."""
    import subprocess
    import sys

    code = (
        "import sys, urdftk, urdftk.cli; "
        "print(sorted(m for m in ('pinocchio','yourdfpy','numpy','trimesh') if m in sys.modules))"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.strip() == "[]"
