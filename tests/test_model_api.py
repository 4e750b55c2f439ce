"""The named-joint Robot API on synthetic robots, checked against raw Pinocchio and finite differences."""

from __future__ import annotations

import time
import warnings
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest
from _kinematics_oracle import fd_jacobians, raw_pin_poses

import urdftk
from urdftk.errors import (
    ConfigurationError,
    DescriptionError,
    JointNotFound,
    KinematicsError,
    LinkNotFound,
    UrdftkError,
)

LIMIT = '<limit lower="-1.0" upper="1.5" effort="10" velocity="2"/>'
ALL_TYPES = f"""<robot name="zoo">
  <link name="base"/><link name="arm"/><link name="slide"/><link name="wheel"/><link name="cart"/>
  <link name="drone"/><link name="finger"/><link name="finger2"/><link name="j_rev"/>
  <joint name="j_rev" type="revolute"><parent link="base"/><child link="arm"/>
    <origin xyz="0.1 0.2 0.3" rpy="0.3 -0.2 0.1"/><axis xyz="0 1 0"/>{LIMIT}</joint>
  <joint name="j_pri" type="prismatic"><parent link="arm"/><child link="slide"/>
    <origin xyz="0 0 0.5" rpy="0 0.4 0"/><axis xyz="0.6 0 0.8"/>{LIMIT}</joint>
  <joint name="j_cont" type="continuous"><parent link="slide"/><child link="wheel"/>
    <origin xyz="0.2 0 0" rpy="1.0 0 0"/><axis xyz="0 0 1"/></joint>
  <joint name="j_planar" type="planar"><parent link="wheel"/><child link="cart"/>
    <origin xyz="0 0.3 0" rpy="0 0 0.5"/><axis xyz="0 0 1"/></joint>
  <joint name="j_float" type="floating"><parent link="cart"/><child link="drone"/>
    <origin xyz="0 0 1" rpy="0.1 0.2 0.3"/></joint>
  <joint name="j_f1" type="revolute"><parent link="drone"/><child link="finger"/>
    <origin xyz="0.1 0 0"/><axis xyz="1 0 0"/>
    <mimic joint="j_rev" multiplier="2" offset="0.1"/>{LIMIT}</joint>
  <joint name="j_f2" type="revolute"><parent link="finger"/><child link="finger2"/>
    <origin xyz="0.1 0 0"/><axis xyz="0 0 1"/>
    <mimic joint="j_f1" multiplier="-0.5" offset="0.2"/>{LIMIT}</joint>
  <joint name="j_tip" type="fixed"><parent link="finger2"/><child link="j_rev"/>
    <origin xyz="0 0 0.05"/></joint>
</robot>"""


def chain(n: int) -> str:
    links = "".join(f'<link name="l{i}"/>' for i in range(n + 1))
    joints = "".join(
        f'<joint name="j{i}" type="revolute"><parent link="l{i}"/><child link="l{i + 1}"/>'
        f'<origin xyz="0 0 0.1"/><axis xyz="0 1 0"/>{LIMIT}</joint>'
        for i in range(n)
    )
    return f'<robot name="chain{n}">{links}{joints}</robot>'


@pytest.fixture(scope="module")
def zoo():
    return urdftk.load(ALL_TYPES)


def test_coordinates_and_names(zoo):
    planar = ("j_planar/x", "j_planar/y", "j_planar/theta")
    floating = tuple(f"j_float/{s}" for s in ("x", "y", "z", "qx", "qy", "qz", "qw"))
    assert zoo.joint_names == ("j_rev", "j_pri", "j_cont", *planar, *floating)
    assert zoo.mimic == {"j_f1": ("j_rev", 2.0, 0.1), "j_f2": ("j_rev", -1.0, -0.05 + 0.2)}
    assert zoo.root_link == "base" and set(zoo.link_names) == {link.name for link in zoo.parsed.tree.links}
    assert zoo.link_names[0] == "base"
    np.testing.assert_array_equal(zoo.limits.lower[:3], [-1.0, -1.0, -np.inf])
    np.testing.assert_array_equal(zoo.limits.upper[:3], [1.5, 1.5, np.inf])
    assert zoo.limits.velocity[0] == 2.0 and zoo.limits.effort[1] == 10.0
    with pytest.raises(ValueError):
        zoo.limits.lower[0] = 5.0


def test_fk_matches_raw_pinocchio_for_every_joint_type(zoo):
    rng = np.random.default_rng(1)
    for _ in range(20):
        q = zoo.random(rng)
        expected = raw_pin_poses(zoo, q)
        np.testing.assert_allclose(zoo.fk(q), expected, atol=1e-12)
        np.testing.assert_allclose(zoo.fk(q, backend="numpy"), expected, atol=1e-12)
        for i, link in enumerate(zoo.link_names):
            np.testing.assert_allclose(zoo.frame_pose(link, q), expected[i], atol=1e-12)
        Q = np.stack([q, zoo.random(rng)])
        np.testing.assert_allclose(zoo.fk_batch(Q)[0], expected, atol=1e-12)
        np.testing.assert_allclose(zoo.fk_batch(Q, backend="numpy")[0], expected, atol=1e-12)


def test_continuous_joint_is_one_unbounded_angle(zoo):
    q = zoo.neutral()
    q2 = q.copy()
    q2[2] = 2 * np.pi + 0.0
    q[2] = 0.0
    np.testing.assert_allclose(zoo.fk(q), zoo.fk(q2), atol=1e-12)
    assert zoo.q(q2)[2] == pytest.approx(2 * np.pi)  # no limit on a continuous joint


def test_jacobian_matches_finite_differences_all_types(zoo):
    rng = np.random.default_rng(2)
    for _ in range(3):
        q = zoo.random(rng)
        fd = fd_jacobians(zoo, q)
        for reference, expected in fd.items():
            for i, link in enumerate(zoo.link_names):
                J = zoo.jacobian(link, q, reference=reference)
                np.testing.assert_allclose(J, expected[i], atol=1e-6, err_msg=f"{link} {reference}")


def test_floating_base():
    robot = urdftk.load(chain(3), floating_base=True)
    assert robot.joint_names[:7] == tuple(f"root_joint/{s}" for s in ("x", "y", "z", "qx", "qy", "qz", "qw"))
    assert robot.world_frame == "world"
    q = robot.random(3)
    np.testing.assert_allclose(robot.fk(q), raw_pin_poses(robot, q), atol=1e-12)
    T = robot.frame_pose("l0", q)
    np.testing.assert_allclose(T[:3, 3], q[:3])
    np.testing.assert_allclose(robot.frame_pose("world", q), np.eye(4))
    first = robot.joint_transforms(q)[0]
    assert first[:2] == ("world", "l0")
    np.testing.assert_allclose(first[2], T, atol=1e-12)
    fd = fd_jacobians(robot, q)
    np.testing.assert_allclose(robot.jacobian("l3", q, "local"), fd["local"][3], atol=1e-6)
    assert robot.neutral()[3:7].tolist() == [0.0, 0.0, 0.0, 1.0]


def test_q_from_dict_and_errors(zoo):
    q = zoo.q({"j_rev": 0.5, "j_float/qw": 2.0})
    assert q[0] == 0.5 and q[-1] == pytest.approx(1.0)  # quaternion normalized
    assert zoo.q({"j_f1": 2 * 0.5 + 0.1})[0] == pytest.approx(0.5)  # a follower sets its master
    with pytest.raises(ConfigurationError, match="disagrees"):
        zoo.q({"j_rev": 0.5, "j_f1": 0.0})
    with pytest.raises(JointNotFound, match="did you mean 'j_rev'"):
        zoo.q({"j_reb": 0.5})
    with pytest.raises(ConfigurationError, match=f"expected {zoo.dof} joint values"):
        zoo.q([0.0, 1.0])
    with pytest.raises(ConfigurationError, match="j_rev=2 not in"):
        zoo.q({"j_rev": 2.0})
    assert zoo.q({"j_rev": 2.0}, clip=True)[0] == 1.5
    with pytest.raises(ConfigurationError, match="non-finite"):
        zoo.q({"j_rev": float("nan")})
    with pytest.raises(ConfigurationError, match="zero"):
        zoo.q({f"j_float/{s}": 0.0 for s in ("qx", "qy", "qz", "qw")})
    for exc in (ConfigurationError, JointNotFound):
        assert issubclass(exc, UrdftkError)
    assert issubclass(ConfigurationError, ValueError)


def test_random_and_neutral_within_limits(zoo):
    rng = np.random.default_rng(5)
    for q in [zoo.neutral(), *(zoo.random(rng) for _ in range(200))]:
        checked = zoo.q(q)  # raises if out of limits
        np.testing.assert_allclose(checked, q)
    assert np.array_equal(zoo.random(7), zoo.random(7))


def test_unknown_frames_list_valid_names(zoo):
    with pytest.raises(LinkNotFound, match="did you mean 'arm'") as info:
        zoo.frame_pose("armm", zoo.neutral())
    assert "base" in str(info.value)
    for call in (
        lambda: zoo.jacobian("nope", zoo.neutral()),
        lambda: zoo.fk_batch(np.zeros((1, zoo.dof)), ["x"]),
    ):
        with pytest.raises(LinkNotFound):
            call()
    with pytest.raises(ConfigurationError, match="reference"):
        zoo.jacobian("arm", zoo.neutral(), reference="global")


def test_link_named_like_a_joint(zoo):
    q = zoo.random(9)
    i = zoo.link_names.index("j_rev")
    np.testing.assert_allclose(zoo.frame_pose("j_rev", q), zoo.fk(q)[i])
    assert zoo.link_names[i - 1] == "finger2"


def test_transform_joint_and_fixed_transforms_compose_to_fk(zoo):
    q = zoo.random(11)
    F = dict(zip(zoo.link_names, zoo.fk(q), strict=True))
    T_a_b = zoo.transform("arm", "finger2", q)
    np.testing.assert_allclose(F["arm"] @ T_a_b, F["finger2"], atol=1e-12)
    edges = zoo.joint_transforms(q) + zoo.fixed_transforms()
    assert len(edges) == len(zoo.link_names) - 1
    assert {c for _, c, _ in zoo.fixed_transforms()} == {"j_rev"}
    for parent, child, T in edges:
        np.testing.assert_allclose(F[parent] @ T, F[child], atol=1e-12)
    positions = zoo.joint_positions(q)
    assert positions["j_f1"] == pytest.approx(2 * q[0] + 0.1) and "j_planar" not in positions


def test_com_and_mass_match_pinocchio():
    robot = urdftk.load(_inertial_robot())
    model = pin.buildModelFromXML(robot.urdf_text)
    data = model.createData()
    q = robot.random(3)
    assert robot.mass == pytest.approx(3.5)
    np.testing.assert_allclose(robot.com(q), pin.centerOfMass(model, data, q), atol=1e-12)


def _inertial_robot() -> str:
    inertial = (
        '<inertial><mass value="{m}"/><origin xyz="0.1 0 0"/>'
        '<inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial>'
    )
    return (
        f'<robot name="m"><link name="a">{inertial.format(m=1.0)}</link>'
        f'<link name="b">{inertial.format(m=2.5)}</link>'
        f'<joint name="j" type="revolute"><parent link="a"/><child link="b"/>'
        f'<axis xyz="0 0 1"/>{LIMIT}</joint>'
        "</robot>"
    )


def test_large_chain_loads_fast_and_refuses_jacobian_clearly():
    t0 = time.perf_counter()
    robot = urdftk.load(chain(1000))
    assert time.perf_counter() - t0 < 20.0  # generous: the point is no O(nv^3) Data at load
    q = robot.random(0)
    F = robot.fk(q)
    np.testing.assert_allclose(robot.frame_pose("l1000", q), F[-1], atol=1e-9)
    with pytest.raises(KinematicsError, match="1000"):
        robot.jacobian("l1000", q)


@pytest.mark.parametrize(
    ("mimic", "message"),
    [
        ('<mimic joint="j0"/>', "mimics itself"),
        ('<mimic joint="nope"/>', "'nope', which is not a joint"),
        ('<mimic joint="j1"/>', "mimic cycle"),
    ],
)
def test_bad_mimic_is_a_description_error_with_line(mimic, message):
    text = chain(2).replace("</joint>", mimic + "</joint>", 1)
    if "cycle" in message:
        text = text.replace(
            '<origin xyz="0 0 0.1"/><axis xyz="0 1 0"/>' + LIMIT + "</joint></robot>",
            '<origin xyz="0 0 0.1"/><axis xyz="0 1 0"/>' + LIMIT + '<mimic joint="j0"/></joint></robot>',
        )
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with pytest.raises(DescriptionError, match=message) as info:
            urdftk.load(text)
    assert info.value.line == 1


def test_random_with_size_draws_a_batch_within_limits():
    path = "examples/robots/mobile_manipulator_description/urdf/mobile_manipulator.urdf.xacro"
    robot = urdftk.load(Path(__file__).resolve().parents[1] / path)
    Q = robot.random(7, size=500)
    assert Q.shape == (500, robot.dof)
    assert np.all(robot.limits.lower <= Q) and np.all(robot.limits.upper >= Q)
    np.testing.assert_array_equal(Q, robot.random(7, size=500))  # seeded: reproducible
    assert np.ptp(Q, axis=0).min() > 0  # every coordinate varies
    batch = robot.fk_batch(Q[:20])
    for k in range(20):
        np.testing.assert_allclose(batch[k], robot.fk(Q[k]), atol=1e-12)
    floating = urdftk.load(Path(__file__).resolve().parents[1] / path, floating_base=True)
    Qf = floating.random(3, size=50)
    quat = [i for i, n in enumerate(floating.joint_names) if n.endswith(("/qx", "/qy", "/qz", "/qw"))]
    np.testing.assert_allclose(np.linalg.norm(Qf[:, quat], axis=1), 1.0, atol=1e-12)
