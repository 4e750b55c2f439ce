"""The example robots in examples/robots, checked against real tools.

Every ``.xacro`` is expanded by stock xacro 2.1.1 (the oracle); every robot file (a root ``<robot>`` with a
``name``) is then loaded by yourdfpy (meshes included) and by Pinocchio, and the two must agree on the links,
the joints and every link pose, the mimic gripper included. The expected names and counts come from the
stock expansion itself, the physics from the ``<inertial>`` elements, so adding a robot needs no edit here.

Stock xacro 2.1.1 resolves ``$(find pkg)`` through ament_index_python only, so the tests lay out a real
ament prefix (``share/ament_index/resource_index/packages/<pkg>`` and ``share/<pkg>``) pointing at the
example packages and pass it in ``AMENT_PREFIX_PATH``.
"""

from __future__ import annotations

import io
import itertools
import os
import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest
import trimesh
import yourdfpy
from lxml import etree

EXAMPLES = Path(__file__).resolve().parents[1] / "examples" / "robots"
XACRO_NS = "http://www.ros.org/wiki/xacro"
STOCK_XACRO = Path(sys.executable).with_name("xacro")
PACKAGE_URI = re.compile(r"package://([^/]+)/(.+)")
SAFE_PARSER = etree.XMLParser(resolve_entities=False, no_network=True, remove_comments=True)


def _package_dirs() -> dict[str, Path]:
    dirs = {}
    for manifest in sorted(EXAMPLES.rglob("package.xml")):
        dirs[etree.parse(str(manifest), SAFE_PARSER).findtext("name").strip()] = manifest.parent
    return dirs


def _description_files() -> list[Path]:
    return sorted(p for p in EXAMPLES.rglob("*") if p.suffix in (".urdf", ".xacro"))


def _is_robot(path: Path) -> bool:
    """A robot file names its robot; a macro library (meant to be included) does not."""
    root = etree.parse(str(path), SAFE_PARSER).getroot()
    return root.tag == "robot" and bool(root.get("name"))


def _arg_variants(path: Path) -> list[tuple[str, ...]]:
    """The defaults, each boolean xacro:arg flipped, and a non-empty prefix when the file takes one."""
    root = etree.parse(str(path), SAFE_PARSER).getroot()
    variants: list[tuple[str, ...]] = [()]
    for arg in root.iter(f"{{{XACRO_NS}}}arg"):
        name, default = arg.get("name"), arg.get("default", "")
        if default in ("true", "false"):
            variants.append((f"{name}:={'false' if default == 'true' else 'true'}",))
        elif name == "prefix":
            variants.append(("prefix:=ex_",))
    return variants


PACKAGES = _package_dirs()
FILES = _description_files()
ROBOTS = [p for p in FILES if _is_robot(p)]
CASES = [(p, args) for p in ROBOTS for args in _arg_variants(p)]
CASE_IDS = [f"{p.relative_to(EXAMPLES)}{'[' + ' '.join(a) + ']' if a else ''}" for p, a in CASES]
VARIED = [case for case in CASES if case[1]]
VARIED_IDS = [i for case, i in zip(CASES, CASE_IDS, strict=True) if case[1]]
MESHES = sorted(p for p in EXAMPLES.rglob("*") if p.suffix.lower() in (".stl", ".obj", ".dae"))


@pytest.fixture(scope="session")
def ament_prefix(tmp_path_factory: pytest.TempPathFactory) -> Path:
    prefix = tmp_path_factory.mktemp("ament_prefix")
    index = prefix / "share" / "ament_index" / "resource_index" / "packages"
    index.mkdir(parents=True)
    for name, folder in PACKAGES.items():
        (index / name).write_text("")
        (prefix / "share" / name).symlink_to(folder, target_is_directory=True)
    return prefix


@pytest.fixture(scope="session")
def stock(ament_prefix: Path):
    """Expand a file with stock xacro; results are kept for the session."""
    assert STOCK_XACRO.is_file(), f"stock xacro not installed next to {sys.executable}"
    cache: dict[tuple[Path, tuple[str, ...]], str] = {}
    env = {k: v for k, v in os.environ.items() if k not in ("ROS_PACKAGE_PATH", "AMENT_PREFIX_PATH")}
    env["AMENT_PREFIX_PATH"] = str(ament_prefix)

    def expand(path: Path, args: tuple[str, ...] = ()) -> str:
        if (path, args) not in cache:
            run = subprocess.run(
                [str(STOCK_XACRO), str(path), *args], capture_output=True, text=True, env=env, timeout=60
            )
            assert run.returncode == 0, f"stock xacro failed on {path} {args}:\n{run.stderr}"
            cache[path, args] = run.stdout
        return cache[path, args]

    return expand


def _resolve(fname: str) -> str:
    match = PACKAGE_URI.fullmatch(fname)
    assert match, f"mesh {fname!r} is not a package:// URI"
    return str(PACKAGES[match.group(1)] / match.group(2))


def _parse(text: str) -> etree._Element:
    return etree.fromstring(text.encode(), SAFE_PARSER)


def _sample(urdf: yourdfpy.URDF, rng: np.random.Generator) -> dict[str, float]:
    values = {}
    for name in urdf.actuated_joint_names:
        joint = urdf.joint_map[name]
        if joint.type == "continuous":
            values[name] = rng.uniform(-np.pi, np.pi)
        else:
            values[name] = rng.uniform(joint.limit.lower, joint.limit.upper)
    return values


def _pin_q(model: pin.Model, values: dict[str, float]) -> np.ndarray:
    q = pin.neutral(model)
    for jid in range(1, model.njoints):
        joint = model.joints[jid]
        if joint.nq == 0:  # a mimic follower: Pinocchio derives it from its master
            continue
        value = values[model.names[jid]]
        q[joint.idx_q : joint.idx_q + joint.nq] = [np.cos(value), np.sin(value)] if joint.nq == 2 else [value]
    return q


def test_examples_exist():
    assert ROBOTS, f"no robot files under {EXAMPLES}"
    assert MESHES, f"no meshes under {EXAMPLES}"
    for name, folder in PACKAGES.items():
        assert folder.name == name, f"package {name} lives in {folder}"
        assert any(folder in p.parents for p in ROBOTS), f"package {name} holds no robot file"


@pytest.mark.parametrize("path", FILES, ids=lambda p: p.name)
def test_stock_xacro_expands(stock, path: Path):
    root = _parse(stock(path))
    assert root.tag == "robot"
    assert not any(el.tag.startswith(f"{{{XACRO_NS}}}") for el in root.iter(etree.Element))


@pytest.mark.parametrize(("path", "args"), CASES, ids=CASE_IDS)
def test_loads_in_yourdfpy_and_pinocchio(stock, path: Path, args: tuple[str, ...]):
    text = stock(path, args) if path.suffix == ".xacro" else path.read_text()
    root = _parse(text)
    links = [el.get("name") for el in root.findall("link")]
    joints = {el.get("name"): el.get("type") for el in root.findall("joint")}
    mimics = {el.get("name") for el in root.findall("joint") if el.find("mimic") is not None}
    assert links and len(set(links)) == len(links)

    urdf = yourdfpy.URDF.load(io.BytesIO(text.encode()), filename_handler=_resolve, load_meshes=True)
    assert urdf.validate()
    assert sorted(urdf.link_map) == sorted(links)
    assert sorted(urdf.joint_map) == sorted(joints)
    assert len(urdf.scene.geometry) == len(root.findall("link/visual"))

    model = pin.buildModelFromXML(text)
    movable = sorted(name for name, kind in joints.items() if kind != "fixed")
    assert sorted(model.names[1:]) == movable
    bodies = {f.name for f in model.frames if f.type == pin.FrameType.BODY}
    assert bodies == set(links)
    fixed = {f.name for f in model.frames if f.type == pin.FrameType.FIXED_JOINT} - {"universe"}
    assert fixed == {name for name, kind in joints.items() if kind == "fixed"}

    # Pinocchio applies <mimic> by itself here, so it is an independent oracle for yourdfpy's followers.
    mimic_model = pin.buildModelFromXML(text, mimic=True)
    assert sorted(urdf.actuated_joint_names) == sorted(set(movable) - mimics)
    data = mimic_model.createData()
    rng = np.random.default_rng(7)
    for _ in range(5):
        values = _sample(urdf, rng)
        urdf.update_cfg(values)
        pin.framesForwardKinematics(mimic_model, data, _pin_q(mimic_model, values))
        for link in links:
            expected = data.oMf[mimic_model.getFrameId(link, pin.FrameType.BODY)].homogeneous
            np.testing.assert_allclose(urdf.get_transform(link, urdf.base_link), expected, atol=1e-9)
        for name in mimics:
            _assert_follows(urdf, name, values)


def _assert_follows(urdf: yourdfpy.URDF, name: str, values: dict[str, float]) -> None:
    joint = urdf.joint_map[name]
    target = joint.mimic.multiplier * values[joint.mimic.joint] + joint.mimic.offset
    motion = np.linalg.inv(joint.origin) @ urdf.get_transform(joint.child, joint.parent)
    if joint.type == "prismatic":
        np.testing.assert_allclose(motion[:3, 3], target * np.asarray(joint.axis), atol=1e-12)
    else:
        np.testing.assert_allclose(
            motion[:3, :3], trimesh.transformations.rotation_matrix(target, joint.axis)[:3, :3], atol=1e-12
        )


@pytest.mark.parametrize(("path", "args"), CASES, ids=CASE_IDS)
def test_physics_and_limits(stock, path: Path, args: tuple[str, ...]):
    root = _parse(stock(path, args) if path.suffix == ".xacro" else path.read_text())
    for inertial in root.iter("inertial"):
        where = inertial.getparent().get("name")
        mass = float(inertial.find("mass").get("value"))
        e = inertial.find("inertia")
        ixx, ixy, ixz, iyy, iyz, izz = (float(e.get(k)) for k in ("ixx", "ixy", "ixz", "iyy", "iyz", "izz"))
        moments = np.linalg.eigvalsh(np.array([[ixx, ixy, ixz], [ixy, iyy, iyz], [ixz, iyz, izz]]))
        assert mass > 0, where
        assert moments[0] > 0, f"{where}: inertia not positive definite {moments}"
        for a, b, c in itertools.permutations(moments):
            assert a + b >= c * (1 - 1e-12), (
                f"{where}: principal moments {moments} break the triangle inequality"
            )
    moving = {j.find("child").get("link") for j in root.findall("joint") if j.get("type") != "fixed"}
    with_mass = {link.get("name") for link in root.findall("link") if link.find("inertial") is not None}
    assert moving <= with_mass, f"moving links without <inertial>: {sorted(moving - with_mass)}"
    for joint in root.findall("joint"):
        kind, name = joint.get("type"), joint.get("name")
        if kind == "fixed":
            continue
        axis = np.array(joint.find("axis").get("xyz").split(), dtype=float)
        np.testing.assert_allclose(np.linalg.norm(axis), 1.0, atol=1e-12, err_msg=name)
        limit = joint.find("limit")
        assert float(limit.get("effort")) > 0 and float(limit.get("velocity")) > 0, name
        if kind in ("revolute", "prismatic"):
            assert float(limit.get("lower")) < float(limit.get("upper")), name
    model = pin.buildModelFromXML(etree.tostring(root, encoding="unicode"))
    for jid in range(1, model.njoints):
        assert model.inertias[jid].mass > 0, model.names[jid]
        assert np.linalg.eigvalsh(model.inertias[jid].inertia)[0] > 0, model.names[jid]


@pytest.mark.parametrize(("path", "args"), VARIED, ids=VARIED_IDS)
def test_args_take_effect(stock, path: Path, args: tuple[str, ...]):
    default, varied = _parse(stock(path)), _parse(stock(path, args))
    assert etree.tostring(default) != etree.tostring(varied)
    name, value = args[0].split(":=")
    if name == "prefix":
        names = [el.get("name") for el in varied.iter("link", "joint")]
        assert names and all(n.startswith(value) for n in names)
        assert len(names) == len(list(default.iter("link", "joint")))


def test_meshes_small_and_loadable(stock):
    sizes = {p.name: p.stat().st_size for p in MESHES}
    assert all(size < 100_000 for size in sizes.values()), sizes
    assert sum(sizes.values()) < 300_000, sizes
    for path in MESHES:
        mesh = trimesh.load(path, force="mesh")
        assert len(mesh.faces) > 0 and mesh.is_watertight, path
        if path.suffix == ".obj" and "mtllib" in path.read_text():
            colour = mesh.visual.material.main_color
            assert tuple(colour[:3]) != (102, 102, 102), f"{path}: its .mtl colour was not applied"
    referenced = set()
    for path, args in CASES:
        text = stock(path, args) if path.suffix == ".xacro" else path.read_text()
        referenced |= {Path(_resolve(m.get("filename"))) for m in _parse(text).iter("mesh")}
    assert referenced <= set(MESHES), sorted(referenced - set(MESHES))
    assert any(p.suffix == ".obj" for p in referenced)


def test_workspace_resolution_finds_every_package():
    from urdftk.resources import PackageResolver

    for path in FILES:
        used = set(re.findall(r"\$\(find ([^)\s]+)\)|package://([^/]+)/", path.read_text()))
        for name in {n for pair in used for n in pair if n}:
            resolver = PackageResolver(source=path, environ={})
            assert resolver.find(name) == PACKAGES[name], (path, name)


def test_mesh_script_reproduces_committed_meshes(tmp_path: Path):
    scripts = sorted(EXAMPLES.rglob("scripts/make_meshes.py"))
    assert scripts, "no make_meshes.py script"
    for script in scripts:
        run = subprocess.run(
            [sys.executable, str(script), "--out", str(tmp_path)], capture_output=True, text=True, timeout=60
        )
        assert run.returncode == 0, run.stderr
        made = sorted(p for p in tmp_path.iterdir() if p.suffix.lower() in (".stl", ".obj", ".dae"))
        committed = sorted(p for p in MESHES if p.parent == script.parent.parent / "meshes")
        assert [p.name for p in made] == [p.name for p in committed]
        for new, old in zip(made, committed, strict=True):
            a, b = trimesh.load(new, force="mesh"), trimesh.load(old, force="mesh")
            np.testing.assert_allclose(a.vertices, b.vertices, atol=1e-5, err_msg=old.name)
            np.testing.assert_array_equal(a.faces, b.faces, err_msg=old.name)
