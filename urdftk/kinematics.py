"""Forward kinematics on a :class:`~urdftk._structure.KinematicStructure`: single, batched, per joint.

Batched FK is vectorized over configurations: the only Python loop runs over links. Two backends
compute the same thing:

* ``"numba"``: a compiled kernel (:mod:`urdftk._fk_numba`), used when numba is installed
  (``pip install urdftk[fast]``). It computes in float64 and stores the requested dtype.
* ``"numpy"``: plain numpy (:mod:`urdftk._fk_numpy`), blocks of configurations, a few vectorized
  steps per link.

``"auto"`` picks numba when it can be imported, numpy otherwise.
"""

from __future__ import annotations

import importlib.util
from collections.abc import Sequence
from typing import Literal

import numpy as np

from urdftk._fk_numpy import fk_numpy, multi_coordinate, quaternion_matrices
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


def fk_batch(
    struct: KinematicStructure,
    Q: np.ndarray,
    links: Sequence[int],
    out: np.ndarray,
    backend: Backend = "auto",
    plan: tuple[np.ndarray, np.ndarray] | None = None,
    packed: np.ndarray | None = None,
) -> np.ndarray:
    """Compute ``T_root_link`` for many configurations at once.

    Args:
        struct: The structure.
        Q: (N, n_coords) float64 coordinates, already validated.
        links: Link indices, in output order, without duplicates.
        out: C-contiguous (N, len(links), 4, 4) float32/float64 array to fill.
        backend: ``"auto"``, ``"numba"`` or ``"numpy"``.
        plan: The result of :func:`make_plan` for ``links``, if already known.
        packed: The result of :func:`urdftk._fk_numba.pack` for ``struct``, if already known.

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
        from urdftk._fk_numba import block_size, fk_batch_kernel, pack

        pk = packed if packed is not None else pack(struct)
        fk_batch_kernel(Q, pk, order, slot, block_size(struct.n_links, out.shape[1]), out)
    else:
        fk_numpy(struct, Q, order, slot, out)
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
    if moving.any():
        value = np.where(moving, struct.mult * q[np.where(moving, struct.coord, 0)] + struct.off, 0.0)
    else:  # a robot with no movable joint has no coordinates to index
        value = np.zeros(n)
    rev = struct.jtype == REVOLUTE
    s = np.where(rev, np.sin(value), 0.0)[:, None, None]
    c1 = np.where(rev, 1.0 - np.cos(value), 0.0)[:, None, None]
    T = np.zeros((n, 4, 4))
    T[:, :3, :3] = struct.rot + s * struct.rk + c1 * struct.rk2
    d = np.where(struct.jtype == PRISMATIC, value, 0.0)
    T[:, :3, 3] = struct.trans + d[:, None] * struct.dirn
    T[:, 3, 3] = 1.0
    for i in np.flatnonzero((struct.jtype == FLOATING) | (struct.jtype == PLANAR)):
        R, t = multi_coordinate(struct, int(i), q[None, :])
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
