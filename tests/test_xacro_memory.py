"""An expansion leaves nothing for Python's cyclic garbage collector: its trees, macro tables and
parsers are freed by reference counting as soon as it returns (or fails).

Oracle: ``gc.collect()`` with ``DEBUG_SAVEALL``, which keeps every unreachable object it finds.
"""

from __future__ import annotations

import gc
import io
from pathlib import Path

import pytest

from urdftk.errors import XacroError
from urdftk.xacro import expand

CORPUS = Path(__file__).resolve().parents[2] / "shared" / "corpus" / "xacro"
PR2 = CORPUS / "pr2_common" / "pr2_description" / "robots" / "pr2.urdf.xacro"
NS = 'xmlns:xacro="http://www.ros.org/wiki/xacro"'


def _cyclic_garbage(fn) -> list:
    gc.collect()
    flags = gc.get_debug()
    gc.disable()
    try:
        gc.set_debug(gc.DEBUG_SAVEALL)
        fn()
        gc.collect()
        found = list(gc.garbage)
        gc.garbage.clear()
    finally:
        gc.set_debug(flags)
        gc.enable()
    return found


def test_an_expansion_leaves_no_cyclic_garbage(monkeypatch: pytest.MonkeyPatch):
    assert PR2.is_file(), f"the xacro corpus is missing at {CORPUS}"
    monkeypatch.setenv("ROS_PACKAGE_PATH", str(CORPUS / "pr2_common"))
    expand(PR2, stderr=io.StringIO())  # (warm: lazy imports and caches)
    garbage = _cyclic_garbage(lambda: expand(PR2, stderr=io.StringIO()))
    assert garbage == [], sorted({type(o).__name__ for o in garbage})


def test_a_failed_expansion_leaves_no_cyclic_garbage(tmp_path: Path):
    bad = tmp_path / "bad.xacro"
    bad.write_text(
        f'<r {NS}>\n  <xacro:macro name="m"><x v="${{nope}}"/></xacro:macro>\n  <xacro:m/>\n</r>\n'
    )

    def fail() -> None:
        with pytest.raises(XacroError):
            expand(bad, stderr=io.StringIO())

    fail()
    garbage = _cyclic_garbage(fail)
    assert garbage == [], sorted({type(o).__name__ for o in garbage})
