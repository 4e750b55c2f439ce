"""``urdftk check`` on real robots: every URDF shipped in example-robot-data, and meshes in other packages.

The files are found by iterating the installed package (never a hard-coded list). urdfdom's tree
order, as Pinocchio (which bundles urdfdom) builds its frames, is the oracle for the printed tree.
"""

from __future__ import annotations

import os
import subprocess
import sys
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import pinocchio as pin
import pytest
import trimesh

from urdftk.check import check, format_text
from urdftk.cli import main
from urdftk.resources import PackageResolver

ROBOT0 = (
    Path(__file__).resolve().parents[1]
    / "examples"
    / "robots"
    / "robot0_description"
    / "urdf"
    / "robot0.urdf"
)


def _erd_urdfs() -> list[Path]:
    robots = PackageResolver().find("example-robot-data") / "robots"
    return sorted(robots.glob("**/*.urdf"))


ERD = _erd_urdfs()


def test_example_robot_data_is_installed_with_its_urdfs():
    assert len(ERD) >= 60
    assert any(p.name == "ur3.urdf" for p in ERD)


@pytest.mark.parametrize("path", ERD, ids=lambda p: p.name)
def test_check_runs_on_every_example_robot_data_urdf(path, capsys):
    status = main(["check", str(path), "--no-meshes"])
    out, err = capsys.readouterr()
    assert "internal error" not in err and "Traceback" not in err + out
    assert status in (0, 1), err
    assert out.startswith("robot name is: ")
    assert out.splitlines()[-1].startswith(f"{path}: ")
    # every package:// mesh of example-robot-data resolves through the installed package
    assert "[package-not-found]" not in out


def test_ur3_gives_a_clear_error(capsys):
    (ur3,) = [p for p in ERD if p.name == "ur3.urdf"]
    assert main(["check", str(ur3)]) == 1
    out = capsys.readouterr().out
    assert f"{ur3}:6: error: [empty-robot] <robot>: the robot has no <link> elements" in out
    assert f"{ur3}:6: error: [missing-name] <robot>: the robot has no name attribute" in out


@pytest.mark.parametrize("path", ERD, ids=lambda p: p.name)
def test_tree_order_matches_urdfdom(path):
    report = check(path, load_meshes=False)
    if not report.well_formed:
        with pytest.raises(ValueError):
            pin.buildModelFromXML(path.read_text(encoding="utf-8"))
        return
    model = pin.buildModelFromXML(path.read_text(encoding="utf-8"))
    bodies = [f for f in model.frames if f.type == pin.FrameType.BODY]
    assert [e.link for e in report.tree] == [f.name for f in bodies]
    for entry, frame in zip(report.tree[1:], bodies[1:], strict=True):
        assert entry.joint == model.frames[frame.parentFrame].name


def _load_all(path: str) -> tuple[str, list[str]]:
    report = check(path, load_meshes=True)
    return path, [f.code for f in report.findings]


@pytest.mark.timeout(300)
def test_meshes_load_with_trimesh_on_a_sample():
    sample = [str(p) for p in ERD[::4]]
    with ProcessPoolExecutor(max_workers=2) as pool:
        results = dict(pool.map(_load_all, sample))
    assert len(results) == len(sample)
    for path, codes in results.items():
        assert "mesh-load-failed" not in codes, path
        assert "package-not-found" not in codes, path


def test_robot0_prints_exactly_what_check_urdf_prints():
    report = check(ROBOT0)
    assert report.findings == []
    assert format_text(report, "robot0.urdf") == (
        "robot name is: robot0\n"
        "---------- Successfully Parsed XML ---------------\n"
        "root Link: world has 1 child(ren)\n"
        "    child(1):  link_0\n"
        "        child(1):  link_1\n"
        "            child(1):  end_effector\n"
        "robot0.urdf: no problems found\n"
    )


def test_children_are_numbered_per_parent_in_joint_name_order():
    text = """<robot name="r"><link name="b"/><link name="x"/><link name="y"/><link name="z"/>
    <joint name="j2" type="fixed"><parent link="b"/><child link="x"/></joint>
    <joint name="j1" type="fixed"><parent link="b"/><child link="y"/></joint>
    <joint name="j3" type="fixed"><parent link="y"/><child link="z"/></joint></robot>"""
    lines = format_text(check(text)).splitlines()
    assert lines[2:6] == [
        "root Link: b has 2 child(ren)",
        "    child(1):  y",
        "        child(1):  z",
        "    child(2):  x",
    ]


# --- meshes in another package -------------------------------------------------------------------


def _package(folder: Path, name: str) -> Path:
    folder.mkdir(parents=True)
    (folder / "package.xml").write_text(
        f'<?xml version="1.0"?>\n<package format="3"><name>{name}</name></package>\n'
    )
    return folder


def _two_packages(root: Path, *, siblings: bool) -> Path:
    """Robot in pkg_a referencing a mesh in pkg_b; return the robot file."""
    pkg_a = _package(root / "ws" / "src" / "pkg_a_description", "pkg_a_description")
    pkg_b_parent = root / "ws" / "src" if siblings else root / "elsewhere"
    pkg_b = _package(pkg_b_parent / "folder_b", "pkg_b_meshes")
    (pkg_b / "meshes").mkdir()
    trimesh.creation.box((0.1, 0.2, 0.3)).export(pkg_b / "meshes" / "body.stl")
    urdf = pkg_a / "urdf" / "robot.urdf"
    urdf.parent.mkdir()
    urdf.write_text(
        '<robot name="two_pkgs"><link name="base"><visual><geometry>'
        '<mesh filename="package://pkg_b_meshes/meshes/body.stl"/></geometry></visual></link></robot>\n'
    )
    return urdf


def test_mesh_in_other_package_found_with_package_path(tmp_path):
    urdf = _two_packages(tmp_path, siblings=False)
    assert check(urdf).codes() == ["package-not-found"]
    assert check(urdf, package_paths=[tmp_path / "elsewhere"]).findings == []


def test_mesh_in_other_package_found_with_ros_package_path(tmp_path):
    urdf = _two_packages(tmp_path, siblings=False)
    env = {**os.environ, "ROS_PACKAGE_PATH": f"/nonexistent{os.pathsep}{tmp_path / 'elsewhere'}"}
    proc = subprocess.run(
        [sys.executable, "-m", "urdftk", "check", str(urdf)],
        capture_output=True,
        text=True,
        env=env,
        timeout=60,
    )
    assert proc.returncode == 0, proc.stdout + proc.stderr
    assert proc.stdout.endswith(f"{urdf}: no problems found\n")


def test_mesh_in_other_package_found_in_enclosing_workspace(tmp_path):
    urdf = _two_packages(tmp_path, siblings=True)
    assert check(urdf).findings == []


def test_cli_package_path_option_and_missing_package_message(tmp_path, capsys):
    urdf = _two_packages(tmp_path, siblings=False)
    assert main(["check", str(urdf), "-p", str(tmp_path / "elsewhere")]) == 0
    capsys.readouterr()
    assert main(["check", str(urdf), "-p", str(tmp_path / "nowhere")]) == 1
    out = capsys.readouterr().out
    line = next(ln for ln in out.splitlines() if "[package-not-found]" in ln)
    assert line.startswith(f"{urdf}:1: error: [package-not-found] link 'base' <visual> <geometry> <mesh>: ")
    assert f"-p {(tmp_path / 'nowhere').resolve()}" in line
    assert f"workspace of robot.urdf: {tmp_path / 'ws' / 'src'}" in line
    assert "installed packages in" in line


# --- xacro input ---------------------------------------------------------------------------------

EXAMPLES = ROBOT0.parents[2]


@pytest.mark.parametrize("path", sorted(EXAMPLES.glob("**/*.xacro")), ids=lambda p: p.name)
def test_example_xacro_robots_check_clean(path):
    report = check(path)
    assert report.expanded
    if report.tree:  # a robot, not a file of macros
        assert report.ok, [(f.code, f.message) for f in report.findings]


def test_xacro_arguments_reach_the_expansion(tmp_path, capsys):
    robot = tmp_path / "argued.urdf.xacro"
    robot.write_text(
        '<robot name="argued" xmlns:xacro="http://www.ros.org/wiki/xacro">\n'
        '  <xacro:arg name="base" default="default_base"/>\n'
        '  <link name="$(arg base)"/>\n'
        "</robot>\n"
    )
    assert check(robot).root == "default_base"
    assert main(["check", str(robot), "base:=from_cli"]) == 0
    out = capsys.readouterr().out
    assert "root Link: from_cli has 0 child(ren)\n" in out


def test_xacro_failure_is_one_line_exit_2(tmp_path):
    robot = tmp_path / "broken.xacro"
    robot.write_text('<robot name="${undefined_property}" xmlns:xacro="http://www.ros.org/wiki/xacro"/>\n')
    proc = subprocess.run(
        [sys.executable, "-m", "urdftk", "check", str(robot)], capture_output=True, text=True, timeout=60
    )
    assert proc.returncode == 2 and proc.stdout == ""
    assert len(proc.stderr.strip().splitlines()) == 1 and "Traceback" not in proc.stderr
    assert "undefined_property" in proc.stderr


def test_plain_urdf_keeps_its_own_line_numbers(tmp_path):
    # xmlns:xacro and ${...} inside comments do not send a plain URDF through xacro
    robot = tmp_path / "plain.urdf"
    robot.write_text(
        '<robot name="p" xmlns:xacro="http://www.ros.org/wiki/xacro">\n'
        "  <!-- ${not_a_property} -->\n\n\n"
        '  <link name="a"/>\n'
        '  <link name="b"/>\n'
        "</robot>\n"
    )
    report = check(robot)
    assert not report.expanded
    assert [(f.code, f.line) for f in report.findings] == [("two-roots", 6)]
