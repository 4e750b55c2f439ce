"""Language features where ours differs from stock on purpose, checked against stock otherwise."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

from urdftk.xacro import process_file, process_string

NS = 'xmlns:xacro="http://www.ros.org/wiki/xacro"'
STOCK = Path(sys.executable).with_name("xacro")


def stock(path: Path, *args: str) -> str:
    run = subprocess.run([str(STOCK), str(path), *args], capture_output=True, text=True, timeout=60)
    assert run.returncode == 0, run.stderr
    return run.stdout


def test_dirname_gives_the_folder_of_the_current_file(tmp_path: Path):
    sub = tmp_path / "sub"
    sub.mkdir()
    (sub / "inc.xacro").write_text(f'<r {NS}><d v="$(dirname)"/></r>')
    main = tmp_path / "main.xacro"
    main.write_text(f'<r {NS}><m v="$(dirname)"/><xacro:include filename="sub/inc.xacro"/></r>')
    out = process_file(main)
    assert f'<m v="{tmp_path}"/>' in out
    assert f'<d v="{sub}"/>' in out
    # stock's $(dirname) never receives the file name: it fails
    run = subprocess.run([str(STOCK), str(main)], capture_output=True, text=True, timeout=60)
    assert run.returncode != 0 and "dirname" in run.stderr


def test_eval_cwd_env_optenv_match_stock(tmp_path: Path, monkeypatch):
    monkeypatch.setenv("URDFTK_TEST_VAR", "hello")
    path = tmp_path / "e.xacro"
    path.write_text(
        f'<r {NS}><xacro:arg name="n" default="3"/>'
        '<a e="$(eval n * 2 + 0.5)" b="$(eval n == 3)" c="$(eval pi / 2)" '
        'd="$(env URDFTK_TEST_VAR)" o="$(optenv URDFTK_NOT_SET fall back)" w="$(cwd)" '
        'x="$$(escaped) $${also}"/></r>'
    )
    monkeypatch.chdir(tmp_path)
    assert process_file(path, {"n": "4"}) == stock(path, "n:=4")
    assert '<a b="False" c="1.5707963267948966" d="hello" e="8.5"' in process_file(path, {"n": "4"})


def test_target_namespace_eval_comments_and_unicode(tmp_path: Path):
    path = tmp_path / "t.xacro"
    path.write_text(
        f'<r {NS} xacro:targetNamespace="http://example.org/r">\n'
        '  <xacro:property name="burger" value="🍔"/>\n'
        "  <!-- xacro:eval-comments -->\n  <!-- ${burger} x ${2 * 3} -->\n  <t>${burger * 2}</t>\n"
        "  <![CDATA[ raw ${x} ]]>\n</r>\n",
        encoding="utf-8",
    )
    assert process_file(path) == stock(path)


def test_process_string_matches_process_file(tmp_path: Path):
    path = tmp_path / "s.xacro"
    text = f'<r {NS}><xacro:property name="a" value="2"/><b v="${{a ** 3}}"/></r>'
    path.write_text(text)
    assert process_string(text, filename=str(path)) == process_file(path)
