"""Macro bodies expanded many times: every way a body is copied and evaluated, against stock xacro.

The expander shares the unchanging parts of a macro body between calls, expands the parts
without xacro tags in one pass and lets read-only tags (property, arg, include, insert_block,
attribute) work on the body itself; the oracle for all of it is stock xacro's output.
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

from urdftk.errors import XacroError
from urdftk.xacro import process_file

NS = 'xmlns:xacro="http://www.ros.org/wiki/xacro"'
STOCK = Path(sys.executable).with_name("xacro")

PARTS = f"""<r {NS}>
  <!-- a comment kept -->
  <xacro:property name="part_mass" value="${{0.5 * scale}}"/>
  <part m="${{part_mass}}"/>
</r>
"""

MAIN = f"""<robot {NS} name="bodies">
  <xacro:arg name="scale" default="2"/>
  <xacro:property name="scale" value="$(arg scale)"/>
  <xacro:macro name="leg" params="side n:=1 *origin **extras">
    <!-- dropped before a property -->
    <xacro:property name="len" value="${{0.25 * n * scale}}"/>
    <xacro:property name="tmp" value="1"/>
    <xacro:property name="tmp" remove="true"/>
    <xacro:property name="blk">
      <b side="${{side}}">text ${{side}}</b>
    </xacro:property>
    <link name="${{side}}_leg_${{n}}">
      <!-- ${{not evaluated}} -->
      <visual>
        <geometry><box size="${{len}} 0.1 0.1"/></geometry>
        <material name="grey"><color rgba="0.5 0.5 0.5 1"/></material>
      </visual>
      <inertial><mass value="${{len * 3}}"/>mass of ${{side}} <![CDATA[ raw ${{x}} ]]></inertial>
      <xacro:attribute name="kind" value="leg_${{n}}"/>
    </link>
    <joint name="${{side}}_joint_${{n}}" type="revolute">
      <xacro:insert_block name="origin"/>
      <parent link="base"/><child link="${{side}}_leg_${{n}}"/>
      <xacro:if value="${{n > 1}}"><limit effort="${{n}}" velocity="1"/></xacro:if>
      <xacro:unless value="${{n > 1}}"><!-- first --><limit effort="1" velocity="1"/></xacro:unless>
    </joint>
    <xacro:insert_block name="extras"/>
    <xacro:insert_block name="blk"/>
    <xacro:include filename="parts.xacro"/>
    <!-- xacro:eval-comments -->
    <!-- leg ${{side}} ${{n}} -->
    <fixed a="1"><same b="2"/></fixed>
    <xacro:if value="${{n &lt; 3}}">
      <xacro:leg side="${{side}}" n="${{n + 1}}">
        <origin xyz="0 0 ${{-len}}"/>
        <extra n="${{n}}"/>
      </xacro:leg>
    </xacro:if>
  </xacro:macro>
  <link name="base"/>
  <xacro:leg side="left"><origin xyz="0 1 0"/><e/></xacro:leg>
  <xacro:leg side="right" n="2"><origin xyz="0 -1 0"/><e a="${{scale}}"/></xacro:leg>
</robot>
"""


def stock(path: Path, *args: str) -> str:
    run = subprocess.run([str(STOCK), str(path), *args], capture_output=True, text=True, timeout=60)
    assert run.returncode == 0, run.stderr
    return run.stdout


@pytest.mark.parametrize("args", [(), ("scale:=3",)])
def test_repeated_macro_bodies_match_stock(tmp_path: Path, args: tuple[str, ...]):
    (tmp_path / "parts.xacro").write_text(PARTS)
    main = tmp_path / "main.xacro"
    main.write_text(MAIN)
    ours = process_file(main, dict(a.split(":=") for a in args))
    assert ours == stock(main, *args)
    assert ours.count("<part ") == 5  # the included file, once per call


def test_error_in_text_of_a_macro_body_names_its_element(tmp_path: Path):
    main = tmp_path / "main.xacro"
    main.write_text(
        f'<robot {NS} name="e">\n  <xacro:macro name="m" params="a">\n    <link name="${{a}}">\n'
        "      <visual>\n        <t>${a + missing}</t>\n      </visual>\n    </link>\n"
        '  </xacro:macro>\n  <xacro:m a="x"/>\n  <xacro:m a="y"/>\n</robot>\n'
    )
    with pytest.raises(XacroError) as info:
        process_file(main)
    first, *trace = str(info.value).splitlines()
    assert first.startswith(f"{main}:5: name 'missing' is not defined")
    assert trace == [f"  in macro 'm' called at {main}:9"]


def test_parameter_listed_twice_matches_stock(tmp_path: Path):
    # stock takes one occurrence of a name off the list per argument: the other one gets its
    # default (or is reported missing)
    main = tmp_path / "dup.xacro"
    main.write_text(
        f'<robot {NS} name="d">\n  <xacro:macro name="m" params="a a:=5 b">\n'
        '    <x a="${a}" b="${b}"/>\n  </xacro:macro>\n  <xacro:m a="1" b="2"/>\n</robot>\n'
    )
    assert process_file(main) == stock(main)
    missing = tmp_path / "missing.xacro"
    missing.write_text(main.read_text().replace('a="1" b="2"', 'b="2"'))
    assert process_file(missing) == stock(missing)  # the default fills both occurrences


def test_macro_defined_in_an_include_inside_a_macro_lifts_namespaces(tmp_path: Path):
    # an include in a macro body adds the included root's namespaces to the body, and the call
    # hands them on to its parent (stock's test_xml_namespace_lifting, from a file)
    (tmp_path / "ns.xml").write_text('<a xmlns:b="http://www.ros.org/b"/>')
    main = tmp_path / "lift.xacro"
    main.write_text(
        f'<a {NS} xmlns:a="http://www.ros.org/a">\n  <xacro:macro name="test">\n'
        '    <xacro:include filename="ns.xml"/>\n  </xacro:macro>\n  <xacro:test/>\n</a>\n'
    )
    assert process_file(main) == stock(main)
