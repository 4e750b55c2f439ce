"""urdftk.load: one text, two libraries, safe parsing, clear errors with file:line."""

from __future__ import annotations

import time
from pathlib import Path

import pinocchio as pin
import pytest
import yourdfpy

import urdftk
from urdftk.errors import DescriptionError, ResourceError, UrdftkError

ROBOT0 = Path(__file__).resolve().parents[1] / "examples/robots/robot0_description/urdf/robot0.urdf"


def _chain(n: int) -> str:
    parts = ['<robot name="chain"><link name="l0"/>']
    for i in range(1, n + 1):
        parts.append(
            f'<link name="l{i}"/><joint name="j{i}" type="revolute"><parent link="l{i - 1}"/>'
            f'<child link="l{i}"/><origin xyz="0 0 0.1"/><axis xyz="0 0 1"/>'
            '<limit lower="-1" upper="1" effort="1" velocity="1"/></joint>'
        )
    return "".join(parts) + "</robot>"


def test_load_file_gives_description_and_model_from_the_same_text():
    robot = urdftk.load(ROBOT0)
    ref = yourdfpy.URDF.load(str(ROBOT0), load_meshes=False, build_scene_graph=False)
    assert robot.name == ref.robot.name
    assert set(robot.link_names) == set(ref.link_map)
    model = pin.buildModelFromXML(ROBOT0.read_text())
    pin_joints = [n for n in model.names if n != "universe"]
    assert set(pin_joints) == {j.name for j in ref.robot.joints if j.type != "fixed"}
    assert robot.urdf_text == ROBOT0.read_text()


def test_load_text_equals_load_file():
    a = urdftk.load(ROBOT0)
    b = urdftk.load(ROBOT0.read_text())
    assert a.link_names == b.link_names
    assert a.joint_names == b.joint_names


def test_doctype_and_entities_are_rejected_without_reading(tmp_path):
    secret = tmp_path / "secret.txt"
    secret.write_text("TOP-SECRET-MARKER")
    text = (
        f'<?xml version="1.0"?>\n<!DOCTYPE robot [<!ENTITY x SYSTEM "file://{secret}">]>\n'
        '<robot name="&x;"><link name="a"/></robot>'
    )
    f = tmp_path / "xxe.urdf"
    f.write_text(text)
    before = secret.stat().st_atime_ns
    with pytest.raises(DescriptionError) as err:
        urdftk.load(f)
    assert f"{f}:2" in str(err.value)
    assert "TOP-SECRET-MARKER" not in str(err.value)
    assert secret.stat().st_atime_ns == before


def test_billion_laughs_is_rejected_fast():
    lol = ['<?xml version="1.0"?>\n<!DOCTYPE lolz [\n <!ENTITY lol "lol">']
    for i in range(1, 10):
        prev = "lol" if i == 1 else f"lol{i - 1}"
        lol.append(f' <!ENTITY lol{i} "{("&" + prev + ";") * 10}">')
    lol.append(']>\n<robot name="&lol9;"><link name="a"/></robot>')
    start = time.monotonic()
    with pytest.raises(DescriptionError, match="DOCTYPE"):
        urdftk.load("\n".join(lol))
    assert time.monotonic() - start < 1.0


def test_deep_chain_is_rejected_quickly_and_moderate_chain_loads():
    start = time.monotonic()
    with pytest.raises(DescriptionError, match="deep"):
        urdftk.load(_chain(10_000))
    assert time.monotonic() - start < 5.0
    robot = urdftk.load(_chain(1000))
    assert len(robot.joint_names) == 1000


@pytest.mark.parametrize(
    ("body", "line", "fragment"),
    [
        ('<robot name="r">\n<link name="a"/>\n<link name="a"/>\n</robot>', 3, "duplicate link name 'a'"),
        (
            '<robot name="r">\n<link name="a"/>\n<joint name="j" type="fixed">\n'
            '<parent link="a"/><child link="zz"/></joint>\n</robot>',
            3,
            "child link 'zz' does not exist",
        ),
        ('<robot name="r">\n<link name="a"/>\n<link name="b"/>\n</robot>', 3, "2 root links"),
        ('<robot name="r">\n</robot>', 1, "no <link>"),
        ('<robot name="r">\n<link name="a">\n</robot>', 3, "malformed XML"),
        ('<model name="r"><link name="a"/></model>', 1, "expected <robot>"),
    ],
)
def test_structural_errors_name_file_and_line(tmp_path, body, line, fragment):
    f = tmp_path / "bad.urdf"
    f.write_text(body)
    with pytest.raises(DescriptionError) as err:
        urdftk.load(f)
    assert f"{f}:{line}:" in str(err.value)
    assert fragment in str(err.value)


def test_missing_file_is_a_resource_error(tmp_path):
    with pytest.raises(ResourceError, match="no such file"):
        urdftk.load(tmp_path / "nope.urdf")


def test_every_error_is_an_urdftk_error():
    assert issubclass(DescriptionError, UrdftkError)
    assert issubclass(ResourceError, UrdftkError)
