"""Oracles for the kinematics tests: raw Pinocchio, yourdfpy, and central finite differences.

Nothing here uses urdftk's FK: joint values for the oracles are worked out from the XML text, the
Pinocchio model is built afresh from the same text (no mimic), and yourdfpy applies mimic itself.
"""

from __future__ import annotations

import io
from pathlib import Path

import numpy as np
import pinocchio as pin
import yourdfpy
from lxml import etree

from urdftk.resources import PackageResolver

ROOT = Path(__file__).resolve().parents[1]
EXAMPLES = ROOT / "examples" / "robots"
SAFE = etree.XMLParser(resolve_entities=False, no_network=True, load_dtd=False)


def erd_urdfs() -> list[Path]:
    """Every URDF installed by example-robot-data (iterated, never listed by hand)."""
    robots = PackageResolver().find("example-robot-data") / "robots"
    files = sorted(robots.glob("**/*.urdf"))
    assert len(files) > 50, f"expected example-robot-data's ~69 URDFs under {robots}, found {len(files)}"
    return files


def example_robots() -> list[Path]:
    """Every robot file (root <robot> with a name) under examples/robots."""
    found = []
    for p in sorted(EXAMPLES.rglob("*")):
        if p.suffix in (".urdf", ".xacro"):
            root = etree.parse(str(p), SAFE).getroot()
            if root.tag == "robot" and root.get("name"):
                found.append(p)
    assert found, f"no robot files under {EXAMPLES}"
    return found


def xml_mimics(robot) -> dict[str, tuple[str, float, float]]:
    """Follower -> (master, multiplier, offset) straight from the <mimic> elements (movable joints).

    A target that is not a joint (alex_psyonic_hands' unprefixed names) is taken from the robot only
    after checking that it is the follower's prefix + the written target.
    """
    root = etree.fromstring(robot.urdf_text.encode(), SAFE)
    joints = {j.get("name"): j for j in root.findall("joint")}
    out = {}
    for name, j in joints.items():
        m = j.find("mimic")
        if m is None or j.get("type") == "fixed":
            continue
        target = m.get("joint")
        if target not in joints:
            repaired = robot.mimic[name][0]
            assert repaired.endswith(target) and name.startswith(repaired[: -len(target)]), (name, repaired)
            target = repaired
        out[name] = (target, float(m.get("multiplier", 1.0)), float(m.get("offset", 0.0)))
    return out


def joint_values(robot, q: np.ndarray) -> dict[str, float]:
    """Value of every one-coordinate joint: independent ones from q, followers through the XML mimic."""
    values = {n: float(v) for n, v in zip(robot.joint_names, q, strict=True) if "/" not in n}
    mimics = xml_mimics(robot)

    def value(name: str, depth: int = 0) -> float:
        if name in values:
            return values[name]
        master, mult, off = mimics[name]
        assert depth < 50
        return mult * value(master, depth + 1) + off

    for name in mimics:
        values[name] = value(name)
    return values


def raw_pin_poses(robot, q: np.ndarray) -> np.ndarray:
    """Link poses (link_names order) from a fresh Pinocchio model (mimic off) of the same text."""
    if robot.world_frame is not None:
        model = pin.buildModelFromXML(robot.urdf_text, pin.JointModelFreeFlyer())
    else:
        model = pin.buildModelFromXML(robot.urdf_text)
    data = model.createData()
    values = joint_values(robot, q)
    coords = dict(zip(robot.joint_names, q, strict=True))
    pq = pin.neutral(model)
    for jid in range(1, model.njoints):
        name, iq, nq = model.names[jid], model.idx_qs[jid], model.nqs[jid]
        if nq == 1:
            pq[iq] = values[name]
        elif nq == 2:
            pq[iq : iq + 2] = np.cos(values[name]), np.sin(values[name])
        elif nq == 4:  # planar: x y cos sin
            th = coords[f"{name}/theta"]
            pq[iq : iq + 4] = coords[f"{name}/x"], coords[f"{name}/y"], np.cos(th), np.sin(th)
        else:  # free-flyer: x y z qx qy qz qw
            v = np.array([coords[f"{name}/{s}"] for s in ("x", "y", "z", "qx", "qy", "qz", "qw")])
            v[3:] /= np.linalg.norm(v[3:])
            pq[iq : iq + 7] = v
    pin.framesForwardKinematics(model, data, pq)
    return np.array([data.oMf[model.getFrameId(link, pin.BODY)].homogeneous for link in robot.link_names])


def yourdfpy_model(robot) -> yourdfpy.URDF:
    """yourdfpy's model of the same text (mimic targets repaired as :func:`xml_mimics` checks)."""
    root = etree.fromstring(robot.urdf_text.encode(), SAFE)
    for j in root.findall("joint"):  # yourdfpy needs the real target name
        m = j.find("mimic")
        if m is not None and j.get("name") in robot.mimic and m.get("joint") not in robot.mimic:
            m.set("joint", xml_mimics(robot)[j.get("name")][0])
    text = etree.tostring(root)
    return yourdfpy.URDF.load(io.BytesIO(text), build_scene_graph=True, load_meshes=False)


def yourdfpy_poses(urdf: yourdfpy.URDF, robot, q: np.ndarray) -> np.ndarray:
    """Link poses from yourdfpy, given only the independent joints (yourdfpy applies mimic)."""
    cfg = {n: float(v) for n, v in zip(robot.joint_names, q, strict=True) if n not in robot.mimic}
    urdf.update_cfg(cfg)
    base = robot.root_link
    return np.array([urdf.get_transform(link, base) for link in robot.link_names])


def fd_jacobians(robot, q: np.ndarray, h: float = 1e-6) -> dict[str, np.ndarray]:
    """Central-difference Jacobians of every link for the three reference conventions.

    Returns:
        ``{"world" | "local" | "local_world_aligned": (n_links, 6, dof)}``.
    """
    n, dof = len(robot.link_names), robot.dof
    Q = np.repeat(q[None, :], 2 * dof, axis=0)
    Q[np.arange(dof), np.arange(dof)] += h
    Q[dof + np.arange(dof), np.arange(dof)] -= h
    F = robot.fk_batch(Q, backend="numpy")
    T0 = robot.fk(q)
    dp = (F[:dof, :, :3, 3] - F[dof:, :, :3, 3]) / (2 * h)  # (dof, n, 3)
    out = {k: np.zeros((n, 6, dof)) for k in ("world", "local", "local_world_aligned")}
    for i in range(n):
        R, p = T0[i, :3, :3], T0[i, :3, 3]
        for j in range(dof):
            Rp, Rm = F[j, i, :3, :3], F[dof + j, i, :3, :3]
            w_world = pin.log3(Rp @ Rm.T) / (2 * h)
            w_local = pin.log3(Rm.T @ Rp) / (2 * h)
            v = dp[j, i]
            out["local_world_aligned"][i, :, j] = np.r_[v, w_world]
            out["world"][i, :, j] = np.r_[v - np.cross(w_world, p), w_world]
            out["local"][i, :, j] = np.r_[R.T @ v, w_local]
    return out
