"""Shared fixtures: repository paths and the oracles' locations.

Nothing here skips: a missing prerequisite makes the tests that need it fail with a message
saying how to install it (``bash tests/run.sh`` installs everything).
"""

from __future__ import annotations

import sys
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]
SHARED = REPO.parent / "shared"
EXAMPLES = REPO / "examples" / "robots"
VENV_BIN = Path(sys.executable).parent


@pytest.fixture(scope="session")
def repo_root() -> Path:
    """The repository root."""
    return REPO


@pytest.fixture(scope="session")
def shared_dir() -> Path:
    """The read-only shared folder beside the repository (corpus, oracle tools)."""
    if not SHARED.is_dir():
        pytest.fail(f"{SHARED} is missing: the steering repo's shared/ must sit beside this repository")
    return SHARED


@pytest.fixture(scope="session")
def examples_dir() -> Path:
    """examples/robots."""
    return EXAMPLES


@pytest.fixture(scope="session")
def erd_robots() -> Path:
    """The robots folder of the installed example-robot-data package."""
    from urdftk.resources import PackageResolver

    return PackageResolver(environ={}).find("example-robot-data") / "robots"


@pytest.fixture(scope="session")
def urdftk_cli() -> list[str]:
    """The command that runs the installed ``urdftk`` console script."""
    exe = VENV_BIN / "urdftk"
    if not exe.exists():
        pytest.fail(f"{exe} not found: install the package (pip install -e .)")
    return [str(exe)]
