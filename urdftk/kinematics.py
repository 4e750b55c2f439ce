"""Forward kinematics on a :class:`~urdftk._structure.KinematicStructure`: single, batched, per joint.

Batched FK is vectorized over configurations: the only Python loop runs over links. Two backends
compute the same thing:

* ``"numba"``: a compiled kernel (:mod:`urdftk._fk_numba`), used when numba is installed
  (``pip install urdftk[fast]``). It computes in float64 and stores the requested dtype.
* ``"numpy"``: plain numpy, one vectorized step per link, computing in the requested dtype.

``"auto"`` picks numba when it can be imported, numpy otherwise.
"""

from __future__ import annotations

import importlib.util
from collections.abc import Sequence
from typing import Literal

import numpy as np

from urdftk._structure import FLOATING, PLANAR, PRISMATIC, REVOLUTE, KinematicStructure

__all__ = [
    "Backend",
    "fk_batch",
    "fk_chain",
    "has_numba",
    "local_transforms",
    "make_plan",
    "quaternion_matrices",
]

Backend = Literal["auto", "numba", "numpy"]


def has_numba() -> bool:
    """Tell whether the optional numba fast path is installed."""
    return importlib.util.find_spec("numba") is not None


def make_plan(struct: KinematicStructure, links: Sequence[int]) -> tuple[np.ndarray, np.ndarray]:
    """Work out which links to compute, in order, and where each requested link is stored.

    Args:
        struct: The structure.
        links: Requested link indices, in output order (no duplicates).

    Returns:
        ``(order, slot)``: the link indices to compute (parents first) and, per link, its output
        slot or -1.
    """
    needed = np.zeros(struct.n_links, dtype=bool)
    slot = np.full(struct.n_links, -1, dtype=np.int64)
    for k, i in enumerate(links):
        slot[i] = k
        while i >= 0 and not needed[i]:
            needed[i] = True
            i = int(struct.parent[i])
    return np.flatnonzero(needed).astype(np.int64), slot


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


def _multi_coordinate(
    struct: KinematicStructure, i: int, Qc: np.ndarray, dt
) -> tuple[np.ndarray, np.ndarray]:
    """Local (R, t) of a floating or planar joint for (N, n_coords) coordinates."""
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
    return R.astype(dt, copy=False), t.astype(dt, copy=False)


def _fk_numpy(
    struct: KinematicStructure, Q: np.ndarray, order: np.ndarray, slot: np.ndarray, out: np.ndarray
):
    dt = out.dtype
    n_cfg = Q.shape[0]
    children_left = np.bincount(struct.parent[order][struct.parent[order] >= 0], minlength=struct.n_links)
    Rs: dict[int, np.ndarray] = {}
    ts: dict[int, np.ndarray] = {}
    rot = struct.rot.astype(dt)
    trans = struct.trans.astype(dt)
    for i in (int(k) for k in order):
        code = struct.jtype[i]
        tl: np.ndarray = trans[i]
        if code == REVOLUTE:
            th = struct.mult[i] * Q[:, struct.coord[i]] + struct.off[i]
            s = np.sin(th).astype(dt)[:, None, None]
            c1 = (1.0 - np.cos(th)).astype(dt)[:, None, None]
            Rl = rot[i] + s * struct.rk[i].astype(dt) + c1 * struct.rk2[i].astype(dt)
        elif code == PRISMATIC:
            d = (struct.mult[i] * Q[:, struct.coord[i]] + struct.off[i]).astype(dt)
            Rl, tl = rot[i], trans[i] + d[:, None] * struct.dirn[i].astype(dt)
        elif code in (FLOATING, PLANAR):
            Rl, tl = _multi_coordinate(struct, i, Q, dt)
        else:
            Rl = rot[i]
        p = int(struct.parent[i])
        if p < 0:
            R = np.broadcast_to(Rl, (n_cfg, 3, 3))
            t = np.broadcast_to(tl, (n_cfg, 3))
        else:
            Rp, tp = Rs[p], ts[p]
            R = np.matmul(Rp, Rl)
            t = tp + (np.matmul(Rp, tl) if tl.ndim == 1 else np.einsum("nij,nj->ni", Rp, tl))
            children_left[p] -= 1
            if children_left[p] == 0:
                del Rs[p], ts[p]
        sl = int(slot[i])
        if sl >= 0:
            out[:, sl, :3, :3] = R
            out[:, sl, :3, 3] = t
            out[:, sl, 3, :3] = 0.0
            out[:, sl, 3, 3] = 1.0
            R, t = out[:, sl, :3, :3], out[:, sl, :3, 3]
        if children_left[i] > 0:
            Rs[i], ts[i] = R, t


def fk_batch(
    struct: KinematicStructure,
    Q: np.ndarray,
    links: Sequence[int],
    out: np.ndarray,
    backend: Backend = "auto",
    plan: tuple[np.ndarray, np.ndarray] | None = None,
) -> np.ndarray:
    """Compute ``T_root_link`` for many configurations at once.

    Args:
        struct: The structure.
        Q: (N, n_coords) float64 coordinates, already validated.
        links: Link indices, in output order, without duplicates.
        out: C-contiguous (N, len(links), 4, 4) float32/float64 array to fill.
        backend: ``"auto"``, ``"numba"`` or ``"numpy"``.
        plan: The result of :func:`make_plan` for ``links``, if already known.

    Returns:
        ``out``.

    Raises:
        ValueError: For an unknown backend.
        ModuleNotFoundError: If ``"numba"`` is asked for and numba is not installed.
    """
    if backend not in ("auto", "numba", "numpy"):
        raise ValueError(f"backend must be 'auto', 'numba' or 'numpy', not {backend!r}")
    order, slot = plan if plan is not None else make_plan(struct, links)
    use_numba = backend == "numba" or (backend == "auto" and has_numba())
    if use_numba:
        from urdftk._fk_numba import fk_kernel

        s = struct
        args = (s.parent, s.jtype, s.coord, s.mult, s.off, s.rot, s.trans, s.rk, s.rk2, s.dirn)
        fk_kernel(Q, s.angles, order, *args, slot, out)
    else:
        _fk_numpy(struct, Q, order, slot, out)
    return out


def local_transforms(struct: KinematicStructure, q: np.ndarray) -> np.ndarray:
    """Return ``T_parent_child`` of the joint ending in every link (identity for a fixed-based root).

    Args:
        struct: The structure.
        q: (n_coords,) float64 coordinates.

    Returns:
        (n_links, 4, 4) array.
    """
    n = struct.n_links
    moving = struct.coord >= 0
    value = np.where(moving, struct.mult * q[np.where(moving, struct.coord, 0)] + struct.off, 0.0)
    rev = struct.jtype == REVOLUTE
    s = np.where(rev, np.sin(value), 0.0)[:, None, None]
    c1 = np.where(rev, 1.0 - np.cos(value), 0.0)[:, None, None]
    T = np.zeros((n, 4, 4))
    T[:, :3, :3] = struct.rot + s * struct.rk + c1 * struct.rk2
    d = np.where(struct.jtype == PRISMATIC, value, 0.0)
    T[:, :3, 3] = struct.trans + d[:, None] * struct.dirn
    T[:, 3, 3] = 1.0
    for i in np.flatnonzero((struct.jtype == FLOATING) | (struct.jtype == PLANAR)):
        R, t = _multi_coordinate(struct, int(i), q[None, :], np.float64)
        T[i, :3, :3], T[i, :3, 3] = R[0], t[0]
    return T


def fk_chain(struct: KinematicStructure, local: np.ndarray, link: int) -> np.ndarray:
    """Compose the local transforms from the root to one link.

    Args:
        struct: The structure.
        local: (n_links, 4, 4) from :func:`local_transforms`.
        link: The link index.

    Returns:
        (4, 4) ``T_root_link``.
    """
    chain = []
    i = link
    while i >= 0:
        chain.append(i)
        i = int(struct.parent[i])
    T = np.eye(4)
    for i in reversed(chain):
        T = T @ local[i]
    return T
