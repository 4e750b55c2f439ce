"""Map the user's coordinates to Pinocchio's ``q`` (positions) and ``v`` (velocities).

Pinocchio is built without its own mimic support, so every mimic follower is an independent
Pinocchio joint whose value we set from its master. Continuous joints are ``(cos, sin)`` in
Pinocchio and one angle for the user; planar joints are ``(x, y, cos, sin)`` and ``(x, y, theta)``;
free-flyers are ``(x, y, z, qx, qy, qz, qw)`` in both (normalized here).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from urdftk._structure import FLOATING, PLANAR, KinematicStructure
from urdftk.errors import DescriptionError

__all__ = ["PinMap", "build_pinmap", "check_joints", "frame_ids"]


@dataclass(frozen=True, eq=False)
class PinMap:
    """Index arrays for the user -> Pinocchio conversion.

    Attributes:
        nq: Pinocchio's configuration size.
        nv: Pinocchio's tangent size.
        lin_dst: q slots filled with ``mult * u[lin_src] + lin_off`` (revolute, prismatic).
        lin_src: Source coordinates.
        lin_mult: Multipliers.
        lin_off: Offsets.
        cs_dst: q slots receiving ``cos`` (``sin`` goes to the next slot) of an angle.
        cs_src: Source coordinates of those angles.
        cs_mult: Multipliers.
        cs_off: Offsets.
        copy_dst: q slots copied verbatim (planar x y, free-flyer position and quaternion).
        copy_src: Source coordinates.
        quat: (q slot, coordinate) of every free-flyer quaternion (its x component).
        identity: True when ``q_pin == u`` (only revolute/prismatic joints, no mimic).
        G: Constant part of ``dv/du`` (nv, n_coords).
        planar: (v slot, coordinate) per planar joint.
        floating: (v slot, coordinate) per free-flyer.
    """

    nq: int
    nv: int
    lin_dst: np.ndarray
    lin_src: np.ndarray
    lin_mult: np.ndarray
    lin_off: np.ndarray
    cs_dst: np.ndarray
    cs_src: np.ndarray
    cs_mult: np.ndarray
    cs_off: np.ndarray
    copy_dst: np.ndarray
    copy_src: np.ndarray
    quat: tuple[tuple[int, int], ...]
    identity: bool
    G: np.ndarray
    planar: tuple[tuple[int, int], ...]
    floating: tuple[tuple[int, int], ...]

    def to_pin(self, u: np.ndarray) -> np.ndarray:
        """Convert user coordinates (n_coords,) to Pinocchio's q (nq,)."""
        if self.identity:
            return u
        q = np.empty(self.nq)
        q[self.lin_dst] = self.lin_mult * u[self.lin_src] + self.lin_off
        if self.cs_dst.size:
            th = self.cs_mult * u[self.cs_src] + self.cs_off
            q[self.cs_dst] = np.cos(th)
            q[self.cs_dst + 1] = np.sin(th)
        if self.copy_dst.size:
            q[self.copy_dst] = u[self.copy_src]
            for dst, _ in self.quat:
                q[dst : dst + 4] /= np.linalg.norm(q[dst : dst + 4])
        return q

    def velocity_map(self, u: np.ndarray) -> np.ndarray:
        """Return ``dv/du`` (nv, n_coords) at ``u``: Pinocchio's Jacobian times this is ours."""
        if not (self.planar or self.floating):
            return self.G
        G = self.G.copy()
        for iv, c in self.planar:
            th = u[c + 2]
            ct, st = np.cos(th), np.sin(th)
            G[iv : iv + 2, c : c + 2] = [[ct, st], [-st, ct]]  # R(theta)^T: parent axes -> local
            G[iv + 2, c + 2] = 1.0
        for iv, c in self.floating:
            quat = u[c + 3 : c + 7]
            norm = np.linalg.norm(quat)
            x, y, z, w = quat / norm
            R = _quat_matrix(x, y, z, w)
            G[iv : iv + 3, c : c + 3] = R.T
            # omega_local = 2 vec(conj(qn) * dqn), with dqn = (I - qn qn^T) dq / |q|
            M = np.array([[w, z, -y, -x], [-z, w, x, -y], [y, -x, w, -z]])
            G[iv + 3 : iv + 6, c + 3 : c + 7] = 2.0 * M / norm
        return G


def _quat_matrix(x: float, y: float, z: float, w: float) -> np.ndarray:
    return np.array(
        [
            [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
            [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
            [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
        ]
    )


def check_joints(struct: KinematicStructure, model, filename: str | None = None) -> None:
    """Check that Pinocchio's movable joints are the description's (what :func:`build_pinmap` needs).

    Raises:
        DescriptionError: If Pinocchio's joints differ from the description's.
    """
    names = [r.name for r in struct.joints if r.type != "fixed"]
    njoints = model.njoints
    if len(names) == njoints - 1:  # fast exact test: the names are ids 1..njoints-1, each once
        get_id = model.getJointId
        ids = {get_id(name) for name in names}
        if len(ids) == len(names) and all(0 < i < njoints for i in ids):
            return
    pin_names = list(model.names)[1:]
    if sorted(pin_names) != sorted(names):
        missing = sorted(set(names) ^ set(pin_names))
        raise DescriptionError(
            f"Pinocchio and the description disagree on the movable joints ({', '.join(missing[:10])})",
            filename,
        )


def frame_ids(model, links: Sequence[str], body: Any, filename: str | None = None) -> dict[str, int]:
    """Return the Pinocchio frame id of each link's body frame (``body`` is ``pinocchio.BODY``).

    Raises:
        DescriptionError: If Pinocchio has no frame for a link.
    """
    ids: dict[str, int] = {}
    get_frame_id, nframes = model.getFrameId, model.nframes
    for link in links:
        fid = get_frame_id(link, body)
        if fid >= nframes:
            raise DescriptionError(f"Pinocchio has no frame for link '{link}'", filename)
        ids[link] = fid
    return ids


def build_pinmap(struct: KinematicStructure, model, filename: str | None = None) -> PinMap:
    """Match the structure's joints with the Pinocchio model's and build the index arrays.

    Args:
        struct: The kinematic structure.
        model: The ``pinocchio.Model`` built from the same text.
        filename: For error messages.

    Returns:
        The map.

    Raises:
        DescriptionError: If Pinocchio's joints differ from the description's.
    """
    lin: list[tuple[int, int, float, float]] = []
    cs: list[tuple[int, int, float, float]] = []
    copy: list[tuple[int, int]] = []
    quat: list[tuple[int, int]] = []
    planar: list[tuple[int, int]] = []
    floating: list[tuple[int, int]] = []
    check_joints(struct, model, filename)
    n_coords = len(struct.coord_names)
    G = np.zeros((model.nv, n_coords))
    movable = [r for r in struct.joints if r.type != "fixed"]
    # Fetch Pinocchio's index vectors once (indexing them is cheap; converting them is not).
    get_id, idx_qs, idx_vs, nqs = model.getJointId, model.idx_qs, model.idx_vs, model.nqs
    mults, offs, jtypes = struct.mult.tolist(), struct.off.tolist(), struct.jtype.tolist()
    for rec in movable:
        jid = get_id(rec.name)
        iq, iv = idx_qs[jid], idx_vs[jid]
        i = rec.link
        mult, off, c = mults[i], offs[i], rec.coord
        nq = nqs[jid]
        if rec.type in ("revolute", "prismatic", "continuous"):
            if nq == 1:
                lin.append((iq, c, mult, off))
            else:
                cs.append((iq, c, mult, off))
            G[iv, c] = mult
        elif jtypes[i] == PLANAR:
            copy.extend([(iq, c), (iq + 1, c + 1)])
            cs.append((iq + 2, c + 2, 1.0, 0.0))
            planar.append((iv, c))
        elif jtypes[i] == FLOATING:
            copy.extend((iq + k, c + k) for k in range(7))
            quat.append((iq + 3, c + 3))
            floating.append((iv, c))

    def arr(rows, k, dtype):
        return np.array([r[k] for r in rows], dtype=dtype)

    identity = (
        not cs
        and not copy
        and model.nq == n_coords
        and all(d == s and m == 1.0 and o == 0.0 for d, s, m, o in lin)
    )
    return PinMap(
        nq=model.nq,
        nv=model.nv,
        lin_dst=arr(lin, 0, np.int64),
        lin_src=arr(lin, 1, np.int64),
        lin_mult=arr(lin, 2, float),
        lin_off=arr(lin, 3, float),
        cs_dst=arr(cs, 0, np.int64),
        cs_src=arr(cs, 1, np.int64),
        cs_mult=arr(cs, 2, float),
        cs_off=arr(cs, 3, float),
        copy_dst=arr(copy, 0, np.int64),
        copy_src=arr(copy, 1, np.int64),
        quat=tuple(quat),
        identity=identity,
        G=G,
        planar=tuple(planar),
        floating=tuple(floating),
    )
