"""Error messages of urdftk's xacro expander: where (file:line), a short trace, and what to do."""

from __future__ import annotations

from pathlib import Path

import pytest

from urdftk.errors import PackageNotFound, XacroError
from urdftk.xacro import process_file, process_string
from urdftk.xacro._processor import MAX_DEPTH

NS = 'xmlns:xacro="http://www.ros.org/wiki/xacro"'


def error_of(fn, *args, **kwargs) -> str:
    with pytest.raises(XacroError) as info:
        fn(*args, **kwargs)
    return str(info.value)


def test_undefined_property_in_macro_from_included_file(tmp_path: Path):
    (tmp_path / "inc.xacro").write_text(
        f'<r {NS}>\n  <xacro:macro name="wheel" params="side radius">\n'
        '    <link name="${side}_wheel">\n      <radius r="${radus}"/>\n    </link>\n'
        "  </xacro:macro>\n</r>"
    )
    (tmp_path / "main.xacro").write_text(
        f'<robot {NS} name="x">\n  <xacro:include filename="inc.xacro"/>\n'
        '  <xacro:property name="wheel_radius" value="0.1"/>\n'
        '  <xacro:wheel side="left" radius="${wheel_radius}"/>\n</robot>'
    )
    msg = error_of(process_file, tmp_path / "main.xacro")
    first, *trace = msg.splitlines()
    assert first.startswith(f"{tmp_path / 'inc.xacro'}:4: name 'radus' is not defined")
    assert "did you mean 'radius'" in first
    assert trace == [f"  in macro 'wheel' called at {tmp_path / 'main.xacro'}:4"]


def test_undefined_property_did_you_mean():
    msg = error_of(
        process_string,
        f'<r {NS}>\n<xacro:property name="wheel_radius" value="1"/>\n<a v="${{wheel_radis * 2}}"/></r>',
        filename="p.xacro",
    )
    assert msg.startswith("p.xacro:3: name 'wheel_radis' is not defined (did you mean 'wheel_radius'?)")


def test_undefined_macro_did_you_mean():
    msg = error_of(
        process_string, f'<r {NS}><xacro:macro name="wheel"/>\n<xacro:wheell/></r>', filename="m.xacro"
    )
    assert msg == "m.xacro:2: unknown macro name: xacro:wheell (did you mean xacro:wheel?)"


def test_undefined_arg_did_you_mean():
    msg = error_of(
        process_string,
        f'<r {NS}><xacro:arg name="use_gpu" default="1"/>\n\n<a v="$(arg use_gpus)"/></r>',
        filename="g.xacro",
    )
    assert msg.startswith("g.xacro:3: Undefined substitution argument use_gpus (did you mean 'use_gpu'?)")
    assert "use_gpus:=VALUE" in msg


def test_invalid_macro_parameter_did_you_mean():
    msg = error_of(
        process_string,
        f'<r {NS}><xacro:macro name="m" params="radius"/>\n<xacro:m radus="1"/></r>',
        filename="q.xacro",
    )
    assert msg.startswith("q.xacro:2: Invalid parameter \"radus\" of macro m (did you mean 'radius'?)")


def test_xml_syntax_error_has_line_and_column(tmp_path: Path):
    (tmp_path / "bad.xacro").write_text(f"<r {NS}>\n  <a>\n</r>\n")
    (tmp_path / "main.xacro").write_text(f'<r {NS}>\n\n<xacro:include filename="bad.xacro"/></r>')
    msg = error_of(process_file, tmp_path / "main.xacro")
    first, *trace = msg.splitlines()
    assert first == f"{tmp_path / 'bad.xacro'}:3:3: XML syntax error: mismatched tag"
    assert trace == [f"  included from {tmp_path / 'main.xacro'}:3"]


def test_include_cycle_is_short(tmp_path: Path):
    (tmp_path / "a.xacro").write_text(f'<r {NS}><xacro:include filename="b.xacro"/></r>')
    (tmp_path / "b.xacro").write_text(f'<r {NS}>\n<xacro:include filename="a.xacro"/></r>')
    msg = error_of(process_file, tmp_path / "a.xacro")
    lines = msg.splitlines()
    assert len(lines) <= 10
    a, b = tmp_path / "a.xacro", tmp_path / "b.xacro"
    assert lines[0] == f"{b}:2: include cycle: {a} -> {b} -> {a}"


def test_macro_recursion_cycle_is_short():
    text = (
        f'<r {NS}>\n<xacro:macro name="a" params="n"><xacro:b n="${{n}}"/></xacro:macro>\n'
        '<xacro:macro name="b" params="n"><xacro:a n="${n}"/></xacro:macro>\n<xacro:a n="1"/></r>'
    )
    msg = error_of(process_string, text, filename="rec.xacro")
    lines = msg.splitlines()
    assert len(lines) <= 10, msg
    assert lines[0].startswith("rec.xacro:3: macro recursion cycle: a -> b -> a")
    assert "in macro 'b' called at rec.xacro:2" in lines[1]


def test_terminating_recursion_is_fine():
    text = (
        f'<r {NS}><xacro:macro name="chain" params="n">'
        '<l i="${n}"/><xacro:if value="${n > 0}"><xacro:chain n="${n - 1}"/></xacro:if></xacro:macro>'
        f'<xacro:chain n="{MAX_DEPTH // 2}"/></r>'
    )
    assert process_string(text).count("<l i=") == MAX_DEPTH // 2 + 1


def test_unknown_package_names_file_and_search_places():
    with pytest.raises(PackageNotFound) as info:
        process_string(f'<r {NS}>\n<a v="$(find no_such_pkg_xyz)"/></r>', filename="f.xacro")
    msg = str(info.value)
    assert msg.startswith("f.xacro:2: package 'no_such_pkg_xyz' not found. Searched:")
    assert isinstance(info.value, XacroError)


def test_missing_include_suggests_files(tmp_path: Path):
    (tmp_path / "wheel.xacro").write_text(f"<r {NS}/>")
    msg = error_of(
        process_string,
        f'<r {NS}><xacro:include filename="wheeel.xacro"/></r>',
        filename=str(tmp_path / "m.xacro"),
    )
    assert msg.startswith(f"{tmp_path / 'm.xacro'}:1: No such file or directory")
    assert "did you mean 'wheel.xacro'" in msg


def test_optional_include_missing_is_fine():
    out = process_string(f'<r {NS}><xacro:include filename="nope.xacro" optional="true"/><a/></r>')
    assert out.endswith("<r>\n  <a/>\n</r>\n")


def test_line_numbers_count_lines_not_bytes(tmp_path: Path):
    # files are parsed with byte positions and lines are worked out for the message: multi-byte
    # text before the error must not shift the line
    inc = tmp_path / "inc.xacro"
    inc.write_text(
        f'<?xml version="1.0"?>\n<r {NS}>\n  <!-- ünïcödé ✓ ✓ ✓ -->\n'
        '  <xacro:macro name="m" params="a">\n    <link name="${a}">\n'
        "      <visual>ßß ${undefined_thing}</visual>\n    </link>\n  </xacro:macro>\n</r>\n",
        encoding="utf-8",
    )
    main = tmp_path / "main.xacro"
    main.write_text(
        f'<robot {NS} name="x">\n  <!-- é -->\n  <xacro:include filename="inc.xacro"/>\n\n'
        '  <xacro:m a="x"/>\n</robot>\n',
        encoding="utf-8",
    )
    msg = error_of(process_file, main)
    first, *trace = msg.splitlines()
    want = next(i for i, line in enumerate(inc.read_text().splitlines(), 1) if "undefined_thing" in line)
    assert first.startswith(f"{inc}:{want}: name 'undefined_thing' is not defined"), first
    assert trace == [f"  in macro 'm' called at {main}:5"]
