"""``urdftk.resources.PackageResolver`` on real folders: search order, crawling rules, ament index, URIs.

ament_index_python (the ROS 2 implementation) is the oracle for AMENT_PREFIX_PATH look-ups.
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

from urdftk.errors import PackageNotFound, ResourceError
from urdftk.resources import PackageResolver, crawl_packages


def _pkg(folder: Path, name: str | None = None) -> Path:
    folder.mkdir(parents=True, exist_ok=True)
    (folder / "package.xml").write_text(
        f'<?xml version="1.0"?>\n<package format="3">\n  <name>{name or folder.name}</name>\n</package>\n'
    )
    return folder


def _ament_prefix(prefix: Path, name: str, *, indexed: bool = True) -> Path:
    share = prefix / "share" / name
    share.mkdir(parents=True)
    if indexed:
        index = prefix / "share" / "ament_index" / "resource_index" / "packages"
        index.mkdir(parents=True, exist_ok=True)
        (index / name).write_text("")
    return share


def _layout(tmp: Path) -> dict[str, Path]:
    """The same package 'dup' in every kind of place, plus one unique package in each."""
    places = {
        "explicit": tmp / "explicit",
        "ros": tmp / "ros",
        "ament": tmp / "ament",
        "ws": tmp / "ws" / "src",
    }
    _pkg(places["explicit"] / "dup")
    _pkg(places["explicit"] / "only_explicit")
    _pkg(places["ros"] / "dup")
    _pkg(places["ros"] / "only_ros")
    _ament_prefix(places["ament"], "dup")
    _ament_prefix(places["ament"], "only_ament")
    _pkg(places["ws"] / "dup")
    source_pkg = _pkg(places["ws"] / "robot_description")
    (source_pkg / "urdf").mkdir()
    places["source"] = source_pkg / "urdf" / "robot.urdf"
    places["source"].write_text("<robot name='r'/>")
    return places


def _resolver(
    places: dict[str, Path], *, explicit=True, ros=True, ament=True, source=True
) -> PackageResolver:
    env = {}
    if ros:
        env["ROS_PACKAGE_PATH"] = str(places["ros"])
    if ament:
        env["AMENT_PREFIX_PATH"] = str(places["ament"])
    return PackageResolver(
        [places["explicit"]] if explicit else [],
        source=places["source"] if source else None,
        environ=env,
        use_installed=False,
    )


def test_search_order_precedence(tmp_path):
    places = _layout(tmp_path)
    assert _resolver(places).find("dup") == (places["explicit"] / "dup").resolve()
    assert _resolver(places, explicit=False).find("dup") == places["ros"] / "dup"
    assert _resolver(places, explicit=False, ros=False).find("dup") == places["ament"] / "share" / "dup"
    assert _resolver(places, explicit=False, ros=False, ament=False).find("dup") == places["ws"] / "dup"
    with pytest.raises(PackageNotFound):
        _resolver(places, explicit=False, ros=False, ament=False, source=False).find("dup")
    r = _resolver(places)
    assert r.find("only_ros") == places["ros"] / "only_ros"
    assert r.find("only_ament") == places["ament"] / "share" / "only_ament"
    assert r.find("robot_description") == places["ws"] / "robot_description"
    assert r.found_packages() == {
        "only_ros": places["ros"] / "only_ros",
        "only_ament": places["ament"] / "share" / "only_ament",
        "robot_description": places["ws"] / "robot_description",
    }


def test_missing_package_lists_every_place_in_order(tmp_path):
    places = _layout(tmp_path)
    r = _resolver(places)
    with pytest.raises(PackageNotFound) as info:
        r.find("nope_pkg")
    err = info.value
    assert err.package == "nope_pkg"
    assert err.searched == r.search_places()
    assert [s.split(" ", 1)[0] for s in err.searched] == [
        "-p",
        "ROS_PACKAGE_PATH",
        "AMENT_PREFIX_PATH",
        "workspace",
    ]
    text = str(err)
    for place in err.searched:
        assert place in text
    assert (
        text.index("-p ")
        < text.index("ROS_PACKAGE_PATH")
        < text.index("AMENT_PREFIX_PATH")
        < text.index("workspace")
    )
    assert "-p/--package-path" in text


def test_ros_package_path_crawl_rules(tmp_path):
    root = tmp_path / "ros"
    _pkg(root / "a" / "b" / "c" / "deep_pkg")
    outer = _pkg(root / "outer_pkg")
    _pkg(outer / "inner_pkg")  # a crawl stops at a package: not found
    _pkg(root / ".hidden" / "hidden_pkg")
    for marker in ("CATKIN_IGNORE", "COLCON_IGNORE", "AMENT_IGNORE"):
        folder = root / f"ignored_{marker.lower()}"
        _pkg(folder / f"pkg_{marker.lower()}")
        (folder / marker).write_text("")
    _pkg(root / "folder_name", "declared_name")
    found = crawl_packages(root)
    assert found["deep_pkg"] == root / "a" / "b" / "c" / "deep_pkg"
    assert found["outer_pkg"] == outer
    assert found["declared_name"] == found["folder_name"] == root / "folder_name"
    assert "inner_pkg" not in found and "hidden_pkg" not in found
    assert not any(name.startswith("pkg_") for name in found)
    env = {"ROS_PACKAGE_PATH": os.pathsep.join([str(tmp_path / "missing"), "", str(root)])}
    r = PackageResolver(environ=env, use_installed=False)
    assert r.find("declared_name") == root / "folder_name"
    with pytest.raises(PackageNotFound):
        r.find("pkg_catkin_ignore")


def test_ros_package_path_first_entry_wins(tmp_path):
    _pkg(tmp_path / "one" / "same")
    _pkg(tmp_path / "two" / "same")
    env = {"ROS_PACKAGE_PATH": f"{tmp_path / 'two'}{os.pathsep}{tmp_path / 'one'}"}
    assert PackageResolver(environ=env, use_installed=False).find("same") == tmp_path / "two" / "same"


def _ament_oracle(prefixes: list[Path], names: list[str]) -> dict[str, str | None]:
    code = (
        "import sys, json\n"
        "from ament_index_python.packages import get_package_share_directory, PackageNotFoundError\n"
        "out = {}\n"
        "for n in sys.argv[1:]:\n"
        "    try: out[n] = get_package_share_directory(n)\n"
        "    except PackageNotFoundError: out[n] = None\n"
        "print(json.dumps(out))\n"
    )
    env = {**os.environ, "AMENT_PREFIX_PATH": os.pathsep.join(map(str, prefixes))}
    proc = subprocess.run(
        [sys.executable, "-c", code, *names], capture_output=True, text=True, env=env, check=True
    )
    import json

    return json.loads(proc.stdout)


def test_ament_prefix_path_matches_ament_index_python(tmp_path):
    first, second = tmp_path / "install_a", tmp_path / "install_b"
    _ament_prefix(first, "shared")
    _ament_prefix(second, "shared")
    _ament_prefix(second, "only_b")
    _ament_prefix(first, "unindexed", indexed=False)
    names = ["shared", "only_b", "unindexed", "absent"]
    oracle = _ament_oracle([first, second], names)
    env = {"AMENT_PREFIX_PATH": os.pathsep.join([str(first), str(second)])}
    r = PackageResolver(environ=env, use_installed=False)
    for name in names:
        if oracle[name] is None:
            with pytest.raises(PackageNotFound):
                r.find(name)
        else:
            assert r.find(name) == Path(oracle[name])
    assert oracle["shared"] == str(first / "share" / "shared")


def test_enclosing_workspace_finds_itself_and_siblings(tmp_path):
    src = tmp_path / "ws" / "src"
    a = _pkg(src / "pkg_a")
    _pkg(src / "group" / "pkg_b")
    urdf = a / "urdf" / "deeper" / "r.urdf"
    urdf.parent.mkdir(parents=True)
    urdf.write_text("<robot/>")
    r = PackageResolver(source=urdf, environ={}, use_installed=False)
    assert r.find("pkg_a") == a
    assert r.find("pkg_b") == src / "group" / "pkg_b"
    assert r.search_places() == [f"workspace of r.urdf: {src}"]
    lonely = tmp_path / "lonely.urdf"
    lonely.write_text("<robot/>")
    assert PackageResolver(source=lonely, environ={}, use_installed=False).search_places() == []


def test_installed_example_robot_data():
    r = PackageResolver(environ={})
    erd = r.find("example-robot-data")
    assert (erd / "package.xml").is_file() and (erd / "robots").is_dir()
    mesh = r.resolve("package://example-robot-data/robots/panda_description/meshes/visual/link0.dae")
    assert mesh.is_file()
    assert any(p.startswith("installed packages in ") for p in r.search_places())
    assert PackageResolver(environ={}, use_installed=False).search_places() == []


def test_resolve_uri_forms(tmp_path):
    pkg = _pkg(tmp_path / "pkgs" / "my_pkg")
    (pkg / "meshes").mkdir()
    source = pkg / "urdf" / "r.urdf"
    source.parent.mkdir()
    source.write_text("<robot/>")
    r = PackageResolver([tmp_path / "pkgs"], source=source, environ={}, use_installed=False)
    assert r.resolve("package://my_pkg/meshes/a%20b.stl") == pkg.resolve() / "meshes" / "a b.stl"
    assert r.resolve("  package://my_pkg/x.stl  ") == pkg.resolve() / "x.stl"
    assert r.resolve(f"file://{pkg}/meshes/x.stl") == pkg / "meshes" / "x.stl"
    assert r.resolve(str(pkg / "abs.stl")) == pkg / "abs.stl"
    assert r.resolve("../meshes/rel.stl") == source.resolve().parent / "../meshes/rel.stl"
    assert r.resolve("rel.stl", relative_to=pkg / "meshes") == pkg / "meshes" / "rel.stl"
    assert r.resolve("rel.stl", relative_to=source) == source.parent / "rel.stl"
    no_source = PackageResolver(environ={}, use_installed=False)
    assert no_source.resolve("rel.stl") == Path.cwd() / "rel.stl"
    for bad, message in [
        ("", "empty"),
        ("package://", "names no package"),
        ("http://example.com/x.stl", "unsupported URI scheme"),
    ]:
        with pytest.raises(ResourceError, match=message):
            r.resolve(bad)
    with pytest.raises(PackageNotFound, match="'other_pkg' not found"):
        r.resolve("package://other_pkg/x.stl")
    # Three slashes (seen in example-robot-data's Talos) are read as two; `check` warns about it.
    assert r.resolve("package:///my_pkg/x.stl") == r.resolve("package://my_pkg/x.stl")
