"""Every URDF installed by example-robot-data, loaded with urdftk and checked against oracles.

For each file (iterated from the installed package, never a hand-written list):

* ``fk`` agrees with raw Pinocchio (built afresh, mimic off, followers set from the XML) and with
  yourdfpy (which applies mimic itself) to 1e-9 m at 20 seeded random configurations;
* ``jacobian`` (three references) agrees with central finite differences to 1e-6;
* ``fk_batch`` (numba and numpy, float64) equals ``fk`` row by row; float32 within 1e-5 m.

Files that cannot load are listed in ``EXPECTED_FAILURES`` with the reason, and must fail with a
clear :class:`urdftk.errors.UrdftkError` naming the file.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from _kinematics_oracle import erd_urdfs, fd_jacobians, raw_pin_poses, yourdfpy_model, yourdfpy_poses

import urdftk
from urdftk.errors import DescriptionError, MimicWarning

FILES = erd_urdfs()
ROBOTS_DIR = FILES[0].parents[2] if "robots" not in FILES[0].parts[-3:] else FILES[0].parents[3]

EXPECTED_FAILURES = {
    # ur3.urdf in example-robot-data is a xacro-style wrapper with no <link> at all.
    "ur_description/urdf/ur3.urdf": "robot has no <link> elements",
}


def _rel(path) -> str:
    parts = path.parts
    return "/".join(parts[parts.index("robots") + 1 :])


def _load(path):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", MimicWarning)  # alex_psyonic_hands: checked in test_model_mimic
        return urdftk.load(path)


def test_expected_failures_exist():
    names = {_rel(p) for p in FILES}
    assert set(EXPECTED_FAILURES) <= names


@pytest.mark.parametrize("path", [p for p in FILES if _rel(p) in EXPECTED_FAILURES], ids=_rel)
def test_broken_file_gives_clear_error(path):
    with pytest.raises(DescriptionError) as info:
        urdftk.load(path)
    message = str(info.value)
    assert EXPECTED_FAILURES[_rel(path)] in message
    assert str(path) in message and "\n" not in message


@pytest.mark.parametrize("path", [p for p in FILES if _rel(p) not in EXPECTED_FAILURES], ids=_rel)
def test_fk_jacobian_batch_against_oracles(path):
    robot = _load(path)
    rng = np.random.default_rng(20240601)
    ydf = yourdfpy_model(robot)
    Q = np.array([robot.random(rng) for _ in range(20)]).reshape(20, robot.dof)
    for q in Q:
        F = robot.fk(q)
        assert F.shape == (len(robot.link_names), 4, 4)
        np.testing.assert_allclose(F, raw_pin_poses(robot, q), atol=1e-9, rtol=0)
        np.testing.assert_allclose(F, yourdfpy_poses(ydf, robot, q), atol=1e-9, rtol=0)
    singles = np.array([robot.fk(q) for q in Q])
    for backend in ("numba", "numpy"):
        np.testing.assert_allclose(robot.fk_batch(Q, backend=backend), singles, atol=1e-12, rtol=0)
        f32 = robot.fk_batch(Q, dtype=np.float32, backend=backend)
        assert f32.dtype == np.float32
        np.testing.assert_allclose(f32, singles, atol=1e-5, rtol=0)
    if robot.dof == 0:
        return
    for q in Q[:2]:
        fd = fd_jacobians(robot, q)
        for reference, expected in fd.items():
            for i, link in enumerate(robot.link_names):
                J = robot.jacobian(link, q, reference=reference)
                assert J.shape == (6, robot.dof)
                np.testing.assert_allclose(J, expected[i], atol=1e-6, rtol=0, err_msg=f"{link} {reference}")


@pytest.mark.parametrize("path", [p for p in FILES if _rel(p) not in EXPECTED_FAILURES], ids=_rel)
def test_joint_and_fixed_transforms_compose_to_fk(path):
    """The robot-state-publisher contract: the per-joint T_parent_child of fixed_transforms() and
    joint_transforms(q), chained from the root, reproduce fk(q) for every link."""
    robot = _load(path)
    q = robot.random(np.random.default_rng(11))
    pairs = [*robot.fixed_transforms(), *robot.joint_transforms(q)]
    edges = {child: (parent, T) for parent, child, T in pairs}
    assert set(edges) == set(robot.link_names) - {robot.root_link}
    fk = robot.fk(q)
    for i, link in enumerate(robot.link_names):
        T = np.eye(4)
        node = link
        while node != robot.root_link:
            parent, T_parent_node = edges[node]
            T = T_parent_node @ T
            node = parent
        np.testing.assert_allclose(T, fk[i], atol=1e-9, err_msg=link)
