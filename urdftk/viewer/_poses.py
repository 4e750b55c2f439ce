"""Vectorised pose helpers: homogeneous matrices to position + quaternion (xyzw), rigid inverses."""

from __future__ import annotations

import numpy as np

__all__ = ["matrices_to_pose", "rigid_inverse_mul", "xyzw_to_matrix"]


def rigid_inverse_mul(A: np.ndarray, B: np.ndarray) -> np.ndarray:
    """``inv(A) @ B`` for stacks of rigid transforms ``(n, 4, 4)`` (no general inverse)."""
    Rt = np.swapaxes(A[:, :3, :3], 1, 2)
    out = np.zeros(B.shape)
    out[:, :3, :3] = Rt @ B[:, :3, :3]
    out[:, :3, 3] = np.einsum("nij,nj->ni", Rt, B[:, :3, 3] - A[:, :3, 3])
    out[:, 3, 3] = 1.0
    return out


def matrices_to_pose(T: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Positions ``(n, 3)`` and unit quaternions ``(n, 4)`` **xyzw** of homogeneous matrices ``(n, 4, 4)``.

    Uses the numerically stable branch per row (largest of w, x, y, z); ``w >= 0``.
    """
    R = T[:, :3, :3]
    m00, m11, m22 = R[:, 0, 0], R[:, 1, 1], R[:, 2, 2]
    trace = m00 + m11 + m22
    cand = np.stack([trace, m00, m11, m22], axis=1)
    k = np.argmax(cand, axis=1)
    q = np.empty((len(T), 4))
    # w largest
    s = np.sqrt(np.maximum(1.0 + trace, 1e-300)) * 2.0
    qw = np.stack(
        [(R[:, 2, 1] - R[:, 1, 2]) / s, (R[:, 0, 2] - R[:, 2, 0]) / s, (R[:, 1, 0] - R[:, 0, 1]) / s, s / 4],
        1,
    )
    s = np.sqrt(np.maximum(1.0 + m00 - m11 - m22, 1e-300)) * 2.0
    qx = np.stack(
        [s / 4, (R[:, 0, 1] + R[:, 1, 0]) / s, (R[:, 0, 2] + R[:, 2, 0]) / s, (R[:, 2, 1] - R[:, 1, 2]) / s],
        1,
    )
    s = np.sqrt(np.maximum(1.0 - m00 + m11 - m22, 1e-300)) * 2.0
    qy = np.stack(
        [(R[:, 0, 1] + R[:, 1, 0]) / s, s / 4, (R[:, 1, 2] + R[:, 2, 1]) / s, (R[:, 0, 2] - R[:, 2, 0]) / s],
        1,
    )
    s = np.sqrt(np.maximum(1.0 - m00 - m11 + m22, 1e-300)) * 2.0
    qz = np.stack(
        [(R[:, 0, 2] + R[:, 2, 0]) / s, (R[:, 1, 2] + R[:, 2, 1]) / s, s / 4, (R[:, 1, 0] - R[:, 0, 1]) / s],
        1,
    )
    for branch, value in enumerate((qw, qx, qy, qz)):
        sel = k == branch
        q[sel] = value[sel]
    q /= np.linalg.norm(q, axis=1, keepdims=True)
    q[q[:, 3] < 0] *= -1.0
    return T[:, :3, 3].copy(), q


def xyzw_to_matrix(position: np.ndarray, xyzw: np.ndarray) -> np.ndarray:
    """One homogeneous matrix from a position and an xyzw quaternion."""
    x, y, z, w = np.asarray(xyzw, dtype=np.float64) / np.linalg.norm(xyzw)
    T = np.eye(4)
    T[:3, :3] = [
        [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
        [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
        [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
    ]
    T[:3, 3] = position
    return T
