"""Text nodes as stock xacro sees them: long runs, entities, CDATA, comments and non-ASCII text.

The parser receives each run of text in one piece however long it is (its buffer is sized to
the document); the oracle is stock xacro's output for the same file.
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

from urdftk.xacro import process_file

NS = 'xmlns:xacro="http://www.ros.org/wiki/xacro"'
STOCK = Path(sys.executable).with_name("xacro")

LONG = "x" * 20_000
WIDE = "é" * 9_000 + "🙂" * 3_000


def stock(path: Path) -> str:
    run = subprocess.run([str(STOCK), str(path)], capture_output=True, text=True, timeout=60)
    assert run.returncode == 0, run.stderr
    return run.stdout


@pytest.mark.parametrize(
    "body",
    [
        f"<a>{LONG}&amp;{LONG}&#233;{LONG}</a>",
        f"<a>{LONG}<!-- split -->{LONG}</a>\n  <b>  {LONG}  </b>",
        f"<a>before<![CDATA[{LONG} <raw> &amp;]]>after&lt;{LONG}</a>",
        f"<a>{WIDE}&gt;{WIDE}</a>\n  <b w='{WIDE}'/>",
        f'<xacro:property name="p" value="{LONG}"/><a>${{p}}\r\n{LONG}</a>',
    ],
    ids=["entities", "comment", "cdata", "non-ascii", "property"],
)
def test_long_text_matches_stock(tmp_path: Path, body: str):
    path = tmp_path / "t.xacro"
    doc = f"<?xml version='1.0'?>\n<!-- top -->\n<r {NS}>\n  {body}\n</r>\n<!-- end -->\n"
    path.write_text(doc, encoding="utf-8")
    assert process_file(path) == stock(path)
