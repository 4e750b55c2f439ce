"""Batched FK in plain numpy: the fallback when numba is not installed.

Configurations are processed in blocks that stay in cache, in structure-of-arrays layout: a block's
rotations are (3, 3, B) and translations (3, B) arrays. Composing with a joint's constant matrices
is then one small matrix product per link (``np.matmul`` of a (m, 3) constant with the parent's
(3, 3, B) rotations, which numpy hands to BLAS), followed by a few element-wise operations:

* fixed: ``R = R_p R_o``, ``t = t_p + R_p t_o``;
* revolute: ``R = R_p R_o + sin(q) R_p R_o K + (1 - cos(q)) R_p R_o K K``;
* prismatic: ``t = t_p + R_p t_o + q R_p R_o axis``.

Everything is computed in float64 and stored in the output's dtype.
"""

from __future__ import annotations

import numpy as np

from urdftk._structure import FLOATING, PLANAR, PRISMATIC, REVOLUTE, KinematicStructure

__all__ = ["fk_numpy", "multi_coordinate", "quaternion_matrices"]

_BLOCK = 2048


def quaternion_matrices(quat: np.ndarray) -> np.ndarray:
    """Rotation matrices of (..., 4) xyzw quaternions, normalized first.

    Args:
        quat: Quaternions, xyzw, any non-zero norm.

    Returns:
        (..., 3, 3) rotation matrices.
    """
    q = quat / np.linalg.norm(quat, axis=-1, keepdims=True)
    x, y, z, w = q[..., 0], q[..., 1], q[..., 2], q[..., 3]
    R = np.empty((*q.shape[:-1], 3, 3), dtype=q.dtype)
    R[..., 0, 0] = 1 - 2 * (y * y + z * z)
    R[..., 0, 1] = 2 * (x * y - z * w)
    R[..., 0, 2] = 2 * (x * z + y * w)
    R[..., 1, 0] = 2 * (x * y + z * w)
    R[..., 1, 1] = 1 - 2 * (x * x + z * z)
    R[..., 1, 2] = 2 * (y * z - x * w)
    R[..., 2, 0] = 2 * (x * z - y * w)
    R[..., 2, 1] = 2 * (y * z + x * w)
    R[..., 2, 2] = 1 - 2 * (x * x + y * y)
    return R


def multi_coordinate(struct: KinematicStructure, i: int, Qc: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Local (R, t), shapes (N, 3, 3) and (N, 3), of a floating or planar joint for (N, n_coords) ``Qc``."""
    c0 = int(struct.coord[i])
    n = Qc.shape[0]
    pos = np.zeros((n, 3))
    if struct.jtype[i] == FLOATING:
        pos[:] = Qc[:, c0 : c0 + 3]
        Rq = quaternion_matrices(Qc[:, c0 + 3 : c0 + 7])
    else:
        pos[:, :2] = Qc[:, c0 : c0 + 2]
        c, s = np.cos(Qc[:, c0 + 2]), np.sin(Qc[:, c0 + 2])
        Rq = np.zeros((n, 3, 3))
        Rq[:, 0, 0], Rq[:, 0, 1], Rq[:, 1, 0], Rq[:, 1, 1], Rq[:, 2, 2] = c, -s, s, c, 1.0
    R = np.matmul(struct.rot[i], Rq)
    t = struct.trans[i] + pos @ struct.rot[i].T
    return R, t


def _constants(struct: KinematicStructure, i: int) -> np.ndarray:
    """Rows ``M`` such that ``np.matmul(M, R_p)`` gives ``R_p C`` (as ``C^T`` rows) and ``R_p v``."""
    code = struct.jtype[i]
    rows = [struct.rot[i].T]
    if code == REVOLUTE:
        rows += [struct.rk[i].T, struct.rk2[i].T]
    rows.append(struct.trans[i][None, :])
    if code == PRISMATIC:
        rows.append(struct.dirn[i][None, :])
    return np.ascontiguousarray(np.vstack(rows))


def _link_block(struct, i, M, Rp, tp, Qb, sin, one_minus_cos):
    """(R, t) of link ``i`` for a block, from its parent's ``Rp`` (3, 3, B) and ``tp`` (3, B)."""
    code = struct.jtype[i]
    if code in (FLOATING, PLANAR):
        Rl, tl = multi_coordinate(struct, i, Qb)
        return np.einsum("ikb,bkj->ijb", Rp, Rl), tp + np.einsum("ikb,bk->ib", Rp, tl)
    A = np.matmul(M, Rp)  # (3, m, B): row block r of A[i] is (R_p C)[i, :] for C = M[r]^T
    if code == REVOLUTE:
        R = A[:, 0:3] + sin * A[:, 3:6]
        R += one_minus_cos * A[:, 6:9]
        return R, tp + A[:, 9]
    t = tp + A[:, 3]
    if code == PRISMATIC:
        d = struct.mult[i] * Qb[:, struct.coord[i]] + struct.off[i]
        t += d * A[:, 4]
    return A[:, 0:3], t


def fk_numpy(
    struct: KinematicStructure, Q: np.ndarray, order: np.ndarray, slot: np.ndarray, out: np.ndarray
) -> None:
    """Batched FK into ``out`` (N, n_out, 4, 4); see :func:`urdftk.kinematics.fk_batch`."""
    n_cfg, n_out = Q.shape[0], out.shape[1]
    par = struct.parent[order]
    n_children = np.bincount(par[par >= 0], minlength=struct.n_links)
    consts = {int(i): _constants(struct, int(i)) for i in order}
    rev = order[struct.jtype[order] == REVOLUTE]
    angle_row = {int(i): k for k, i in enumerate(rev)}
    stage = np.zeros((min(n_cfg, _BLOCK), n_out, 4, 4))
    stage[:, :, 3, 3] = 1.0
    for k0 in range(0, n_cfg, _BLOCK):
        Qb = Q[k0 : k0 + _BLOCK]
        nb = Qb.shape[0]
        th = (Qb[:, struct.coord[rev]] * struct.mult[rev] + struct.off[rev]).T  # (n_revolute, B)
        sin, one_minus_cos = np.sin(th), 1.0 - np.cos(th)
        st = stage[:nb]
        root_R = np.broadcast_to(np.eye(3)[:, :, None], (3, 3, nb))
        root_t = np.zeros((3, nb))
        left = n_children.copy()
        kept: dict[int, tuple[np.ndarray, np.ndarray]] = {}
        for i in (int(k) for k in order):
            p = int(struct.parent[i])
            Rp, tp = (root_R, root_t) if p < 0 else kept[p]
            a = angle_row.get(i)
            trig = (None, None) if a is None else (sin[a], one_minus_cos[a])
            R, t = _link_block(struct, i, consts[i], Rp, tp, Qb, *trig)
            if p >= 0:
                left[p] -= 1
                if left[p] == 0:
                    del kept[p]
            if left[i] > 0:
                kept[i] = (R, t)
            sl = int(slot[i])
            if sl >= 0:  # transpose into the staging block, then copy it out in one go
                st[:, sl, :3, :3] = R.transpose(2, 0, 1)
                st[:, sl, :3, 3] = t.T
        out[k0 : k0 + nb] = st
