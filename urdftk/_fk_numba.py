"""Optional compiled FK kernels (numba), used when numba is installed (``urdftk[fast]``).

Every kernel composes ``T_root_link = T_root_parent @ T_origin @ J(q)`` in float64, link by link in
depth-first order, reading the structure packed by :func:`pack` into one array (few arguments make
calls from Python cheap):

* :func:`fk_one_all` and :func:`fk_one_link`: one configuration, scalar code without heap
  allocations, behind :meth:`urdftk.Robot.fk` and :meth:`urdftk.Robot.frame_pose` (they also check
  the configuration's length and finiteness);
* :func:`fk_batch_kernel`: blocks of configurations in structure-of-arrays layout (its loops over a
  block vectorize), each block transposed into a cache-resident staging buffer and copied out in one
  sequential pass, in the requested dtype.

Kernels are cached on disk by numba (``cache=True``). Numba's cache only notices changes to this
file, so every kernel and helper lives here, with its own joint type codes (:func:`pack` maps them).
"""

from __future__ import annotations

import math

import numba
import numpy as np

from urdftk import _structure as st

__all__ = [
    "BAD_SHAPE",
    "NOT_FINITE",
    "OK",
    "block_size",
    "fk_batch_kernel",
    "fk_one_all",
    "fk_one_link",
    "pack",
    "sincos",
]

# fdlibm's split of pi/2 (33 + 33 + 53 bits) and its polynomial kernels on [-pi/4, pi/4].
_PIO2_1 = 1.57079632673412561417e00
_PIO2_2 = 6.07710050630396597660e-11
_PIO2_3 = 2.02226624871116645580e-21
_TWO_OVER_PI = 6.36619772367581382433e-01
_S1, _S2, _S3 = -1.66666666666666324348e-01, 8.33333333332248946124e-03, -1.98412698298579493134e-04
_S4, _S5, _S6 = 2.75573137070700676789e-06, -2.50507602534068634195e-08, 1.58969099521155010221e-10
_C1, _C2, _C3 = 4.16666666666666019037e-02, -1.38888888888741095749e-03, 2.48015872894767294178e-05
_C4, _C5, _C6 = -2.75573143513906633035e-07, 2.08757232129817482790e-09, -1.13596475577881948265e-11
# Packed per-link columns: multiplier, offset, R_o (9, row-major), t_o (3), R_o K (9), R_o K K (9),
# R_o axis (3), then parent index, joint type code, first coordinate and the robot's number of
# coordinates (integers stored as exact floats).
_F_MULT, _F_OFF, _F_ROT, _F_TRANS, _F_RK, _F_RK2, _F_DIRN = 0, 1, 2, 11, 14, 23, 32
_I_PARENT, _I_TYPE, _I_COORD, _I_NCOORDS = 35, 36, 37, 38
_WIDTH = 39
_MAX_BLOCK = 128
_FIXED, _REVOLUTE, _PRISMATIC, _FLOATING, _PLANAR = 0, 1, 2, 3, 4  # the kernels' joint codes
_CODES = {st.FIXED: _FIXED, st.REVOLUTE: _REVOLUTE, st.PRISMATIC: _PRISMATIC}
_CODES.update({st.FLOATING: _FLOATING, st.PLANAR: _PLANAR})
OK, NOT_FINITE, BAD_SHAPE = 0, 1, 2
"""Status codes of the single-configuration kernels."""


@numba.njit(cache=True, nogil=True, boundscheck=False, inline="always")
def _sincos_poly(v):
    """``(sin v, cos v)`` by Cody-Waite reduction and fdlibm's polynomials (exact for ``|v| < 1e5``)."""
    k = math.floor(v * _TWO_OVER_PI + 0.5)
    r = ((v - k * _PIO2_1) - k * _PIO2_2) - k * _PIO2_3
    z = r * r
    sr = r + r * z * (_S1 + z * (_S2 + z * (_S3 + z * (_S4 + z * (_S5 + z * _S6)))))
    cr = 1.0 - 0.5 * z + z * z * (_C1 + z * (_C2 + z * (_C3 + z * (_C4 + z * (_C5 + z * _C6)))))
    quad = int(k) & 3
    swap = (quad & 1) == 1
    a = cr if swap else sr
    b = sr if swap else cr
    return (-a if (quad & 2) == 2 else a), (-b if ((quad + 1) & 2) == 2 else b)


@numba.njit(cache=True, nogil=True, boundscheck=False)
def sincos(x, s, c, n):
    """Write ``sin(x[:n])`` and ``cos(x[:n])`` into ``s`` and ``c`` (branch-free, so it vectorizes).

    Accurate to a few ulp (Cody-Waite reduction by pi/2 and fdlibm's polynomials for ``|x| < 1e5``,
    the C library beyond).
    """
    for i in range(n):
        s[i], c[i] = _sincos_poly(x[i])
    for i in range(n):  # beyond the reduction's exact range: the C library
        if not abs(x[i]) < 1e5:
            s[i] = math.sin(x[i])
            c[i] = math.cos(x[i])


def pack(struct: st.KinematicStructure) -> np.ndarray:
    """Pack the structure into the kernels' one array (a single argument is cheap to pass).

    Args:
        struct: The structure.

    Returns:
        (n_links, 39) float64, C-contiguous: per link, the multiplier, offset, ``R_o`` (row-major),
        ``t_o``, ``R_o K``, ``R_o K K``, ``R_o axis``, then the parent index, joint type code,
        first coordinate and the number of coordinates as exact floats.
    """
    s, n = struct, struct.n_links
    codes = [_CODES[int(c)] for c in s.jtype]
    ints = np.column_stack([s.parent, codes, s.coord, np.full(n, len(s.coord_names))]).reshape(n, 4)
    cols = [s.mult[:, None], s.off[:, None], s.rot.reshape(n, 9), s.trans, s.rk.reshape(n, 9)]
    pk = np.hstack([*cols, s.rk2.reshape(n, 9), s.dirn, ints.astype(np.float64)])
    return np.ascontiguousarray(pk, dtype=np.float64)


@numba.njit(cache=True, nogil=True, boundscheck=False, inline="always")
def _rot_times(pk, i, rq, a, b):
    """Entry (a, b) of ``R_o @ Rq`` for link ``i`` and a row-major 9-tuple ``rq``."""
    r = _F_ROT + 3 * a
    return pk[i, r] * rq[b] + pk[i, r + 1] * rq[3 + b] + pk[i, r + 2] * rq[6 + b]


@numba.njit(cache=True, nogil=True, boundscheck=False)
def _multi_local(q, c0, code, pk, i):
    """Local transform (R row-major, t) as a 12-tuple of a floating or planar joint reading ``q[c0:]``."""
    px, py, pz = q[c0], q[c0 + 1], 0.0
    if code == _FLOATING:
        pz = q[c0 + 2]
        x, y, z, w = q[c0 + 3], q[c0 + 4], q[c0 + 5], q[c0 + 6]
        nrm = math.sqrt(x * x + y * y + z * z + w * w)
        x, y, z, w = x / nrm, y / nrm, z / nrm, w / nrm
        rq = (
            1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w),
            2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w),
            2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y),
        )  # fmt: skip
    else:
        c, s = math.cos(q[c0 + 2]), math.sin(q[c0 + 2])
        rq = (c, -s, 0.0, s, c, 0.0, 0.0, 0.0, 1.0)
    t = (
        pk[i, _F_TRANS] + pk[i, _F_ROT] * px + pk[i, _F_ROT + 1] * py + pk[i, _F_ROT + 2] * pz,
        pk[i, _F_TRANS + 1] + pk[i, _F_ROT + 3] * px + pk[i, _F_ROT + 4] * py + pk[i, _F_ROT + 5] * pz,
        pk[i, _F_TRANS + 2] + pk[i, _F_ROT + 6] * px + pk[i, _F_ROT + 7] * py + pk[i, _F_ROT + 8] * pz,
    )
    return (
        _rot_times(pk, i, rq, 0, 0), _rot_times(pk, i, rq, 0, 1), _rot_times(pk, i, rq, 0, 2),
        _rot_times(pk, i, rq, 1, 0), _rot_times(pk, i, rq, 1, 1), _rot_times(pk, i, rq, 1, 2),
        _rot_times(pk, i, rq, 2, 0), _rot_times(pk, i, rq, 2, 1), _rot_times(pk, i, rq, 2, 2),
        t[0], t[1], t[2],
    )  # fmt: skip


# ----------------------------------------------------------------------------- single configuration
@numba.njit(cache=True, nogil=True, boundscheck=False, inline="always")
def _rev(pk, i, j, s, c1):
    return pk[i, _F_ROT + j] + s * pk[i, _F_RK + j] + c1 * pk[i, _F_RK2 + j]


@numba.njit(cache=True, nogil=True, boundscheck=False, inline="always")
def _local(u, pk, i):
    """``T_parent_link`` of link ``i`` as a 12-tuple (R row-major, then t); no heap allocation."""
    code = int(pk[i, _I_TYPE])
    if code == _REVOLUTE:
        th = pk[i, _F_MULT] * u[int(pk[i, _I_COORD])] + pk[i, _F_OFF]
        s, c = _sincos_poly(th) if abs(th) < 1e5 else (math.sin(th), math.cos(th))
        c1 = 1.0 - c
        return (
            _rev(pk, i, 0, s, c1), _rev(pk, i, 1, s, c1), _rev(pk, i, 2, s, c1),
            _rev(pk, i, 3, s, c1), _rev(pk, i, 4, s, c1), _rev(pk, i, 5, s, c1),
            _rev(pk, i, 6, s, c1), _rev(pk, i, 7, s, c1), _rev(pk, i, 8, s, c1),
            pk[i, _F_TRANS], pk[i, _F_TRANS + 1], pk[i, _F_TRANS + 2],
        )  # fmt: skip
    if code in (_FLOATING, _PLANAR):
        return _multi_local(u, int(pk[i, _I_COORD]), code, pk, i)
    d = 0.0
    if code == _PRISMATIC:
        d = pk[i, _F_MULT] * u[int(pk[i, _I_COORD])] + pk[i, _F_OFF]
    return (
        pk[i, _F_ROT], pk[i, _F_ROT + 1], pk[i, _F_ROT + 2],
        pk[i, _F_ROT + 3], pk[i, _F_ROT + 4], pk[i, _F_ROT + 5],
        pk[i, _F_ROT + 6], pk[i, _F_ROT + 7], pk[i, _F_ROT + 8],
        pk[i, _F_TRANS] + d * pk[i, _F_DIRN],
        pk[i, _F_TRANS + 1] + d * pk[i, _F_DIRN + 1],
        pk[i, _F_TRANS + 2] + d * pk[i, _F_DIRN + 2],
    )  # fmt: skip


@numba.njit(cache=True, nogil=True, boundscheck=False, inline="always")
def _mul(A, B):
    """``A @ B`` of two 12-tuple transforms."""
    return (
        A[0] * B[0] + A[1] * B[3] + A[2] * B[6], A[0] * B[1] + A[1] * B[4] + A[2] * B[7],
        A[0] * B[2] + A[1] * B[5] + A[2] * B[8],
        A[3] * B[0] + A[4] * B[3] + A[5] * B[6], A[3] * B[1] + A[4] * B[4] + A[5] * B[7],
        A[3] * B[2] + A[4] * B[5] + A[5] * B[8],
        A[6] * B[0] + A[7] * B[3] + A[8] * B[6], A[6] * B[1] + A[7] * B[4] + A[8] * B[7],
        A[6] * B[2] + A[7] * B[5] + A[8] * B[8],
        A[9] + A[0] * B[9] + A[1] * B[10] + A[2] * B[11],
        A[10] + A[3] * B[9] + A[4] * B[10] + A[5] * B[11],
        A[11] + A[6] * B[9] + A[7] * B[10] + A[8] * B[11],
    )  # fmt: skip


@numba.njit(cache=True, nogil=True, boundscheck=False, inline="always")
def _read(o, k):
    """Pose ``o[k]`` of a (n, 4, 4) array as a 12-tuple."""
    return (
        o[k, 0, 0], o[k, 0, 1], o[k, 0, 2], o[k, 1, 0], o[k, 1, 1], o[k, 1, 2],
        o[k, 2, 0], o[k, 2, 1], o[k, 2, 2], o[k, 0, 3], o[k, 1, 3], o[k, 2, 3],
    )  # fmt: skip


@numba.njit(cache=True, nogil=True, boundscheck=False)
def _write(T, o):
    """A 12-tuple pose into a (4, 4) array."""
    for a in range(3):
        o[a, 0] = T[3 * a]
        o[a, 1] = T[3 * a + 1]
        o[a, 2] = T[3 * a + 2]
        o[a, 3] = T[9 + a]
    o[3, 0] = 0.0
    o[3, 1] = 0.0
    o[3, 2] = 0.0
    o[3, 3] = 1.0


@numba.njit(cache=True, nogil=True, boundscheck=False, inline="always")
def _check(u, pk):
    """Status of a configuration: ``BAD_SHAPE``, ``NOT_FINITE`` or ``OK``."""
    if pk.shape[0] == 0 or u.shape[0] != int(pk[0, _I_NCOORDS]):
        return BAD_SHAPE
    for x in u:
        if not math.isfinite(x):
            return NOT_FINITE
    return OK


@numba.njit(
    "int64(float64[:], float64[:, ::1], float64[:, :, ::1])", cache=True, nogil=True, boundscheck=False
)
def fk_one_all(u, pk, out):
    """Every link pose of one configuration into ``out`` (n_links, 4, 4); returns a status code.

    Parents come before children, so each link reads its parent's pose back from ``out``. Compiled
    for float64 only (other types raise TypeError). ``out`` is not written unless the status is OK.
    """
    status = _check(u, pk)
    if status != OK:
        return status
    for i in range(pk.shape[0]):
        p = int(pk[i, _I_PARENT])
        T = _local(u, pk, i)
        _write(T if p < 0 else _mul(_read(out, p), T), out[i])
    return OK


@numba.njit(
    "int64(float64[:], float64[:, ::1], int64, float64[:, ::1])", cache=True, nogil=True, boundscheck=False
)
def fk_one_link(u, pk, link, out):
    """The pose of one link for one configuration into ``out`` (4, 4); returns a status code.

    Walks from the link up to the root, premultiplying by each ancestor's local transform. Compiled
    for float64 only (other types raise TypeError). ``out`` is not written unless the status is OK.
    """
    status = _check(u, pk)
    if status != OK:
        return status
    T = _local(u, pk, link)
    i = int(pk[link, _I_PARENT])
    while i >= 0:
        T = _mul(_local(u, pk, i), T)
        i = int(pk[i, _I_PARENT])
    _write(T, out)
    return OK


# ----------------------------------------------------------------------------- batches
def block_size(n_links: int, n_out: int) -> int:
    """Configurations per block of :func:`fk_batch_kernel`, keeping its buffers within ~1 MB."""
    per_config = n_links * 12 * 8 + n_out * 16 * 8
    return int(min(_MAX_BLOCK, max(8, (1 << 20) // max(per_config, 1) // 8 * 8)))


@numba.njit(cache=True, nogil=True, boundscheck=False)
def _local_block(Q, pk, i, k0, nb, L, TH, SN, CS):
    """Local transforms of link ``i`` for configurations ``k0 .. k0 + nb`` into ``L`` (12, block)."""
    code = int(pk[i, _I_TYPE])
    t0, t1, t2 = pk[i, _F_TRANS], pk[i, _F_TRANS + 1], pk[i, _F_TRANS + 2]
    if code == _REVOLUTE:
        c0 = int(pk[i, _I_COORD])
        m, o = pk[i, _F_MULT], pk[i, _F_OFF]
        for b in range(nb):
            TH[b] = m * Q[k0 + b, c0] + o
        sincos(TH, SN, CS, nb)
        for j in range(9):
            r, rk, rk2 = pk[i, _F_ROT + j], pk[i, _F_RK + j], pk[i, _F_RK2 + j]
            row = L[j]
            for b in range(nb):
                row[b] = r + SN[b] * rk + (1.0 - CS[b]) * rk2
    elif code in (_FLOATING, _PLANAR):
        c0 = int(pk[i, _I_COORD])
        for b in range(nb):
            T = _multi_local(Q[k0 + b], c0, code, pk, i)
            for j in range(12):
                L[j, b] = T[j]
        return
    else:
        for j in range(9):
            r = pk[i, _F_ROT + j]
            row = L[j]
            for b in range(nb):
                row[b] = r
    x, y, z = L[9], L[10], L[11]
    if code == _PRISMATIC:
        c0 = int(pk[i, _I_COORD])
        m, o = pk[i, _F_MULT], pk[i, _F_OFF]
        d0, d1, d2 = pk[i, _F_DIRN], pk[i, _F_DIRN + 1], pk[i, _F_DIRN + 2]
        for b in range(nb):
            d = m * Q[k0 + b, c0] + o
            x[b] = t0 + d * d0
            y[b] = t1 + d * d1
            z[b] = t2 + d * d2
    else:
        for b in range(nb):
            x[b] = t0
            y[b] = t1
            z[b] = t2


@numba.njit(cache=True, nogil=True, boundscheck=False)
def _compose_block(P, L, W, nb):
    """``W = P @ L`` for a block; one output row per loop so that each loop vectorizes."""
    for a in range(3):
        p0, p1, p2 = P[3 * a], P[3 * a + 1], P[3 * a + 2]
        for c in range(3):
            w, l0, l1, l2 = W[3 * a + c], L[c], L[3 + c], L[6 + c]
            for b in range(nb):
                w[b] = p0[b] * l0[b] + p1[b] * l1[b] + p2[b] * l2[b]
        w, pt, x, y, z = W[9 + a], P[9 + a], L[9], L[10], L[11]
        for b in range(nb):
            w[b] = pt[b] + p0[b] * x[b] + p1[b] * y[b] + p2[b] * z[b]


@numba.njit(cache=True, nogil=True, boundscheck=False)
def _stage_block(W, S, nb, sl):
    """Transpose a link's block ``W`` (12, block) into its slot of the staging rows ``S``."""
    base = sl * 16
    for b in range(nb):
        row = S[b]
        for a in range(3):
            row[base + 4 * a] = W[3 * a, b]
            row[base + 4 * a + 1] = W[3 * a + 1, b]
            row[base + 4 * a + 2] = W[3 * a + 2, b]
            row[base + 4 * a + 3] = W[9 + a, b]
        row[base + 12] = 0.0
        row[base + 13] = 0.0
        row[base + 14] = 0.0
        row[base + 15] = 1.0


@numba.njit(cache=True, nogil=True, boundscheck=False)
def fk_batch_kernel(Q, pk, order, slot, block, out):
    """Batched FK into ``out`` (N, n_out, 4, 4); see :func:`urdftk.kinematics.fk_batch`.

    Args:
        Q: (N, n_coords) float64 coordinates.
        pk: The packed structure (see :func:`pack`).
        order: Link indices to compute, parents first.
        slot: Output slot per link (-1: not written).
        block: Configurations per block (see :func:`block_size`).
        out: Output array (N, n_out, 4, 4), float32 or float64, C-contiguous.
    """
    n_cfg = Q.shape[0]
    n = pk.shape[0]
    flat = out.reshape((n_cfg, out.shape[1] * 16))
    W = np.empty((n, 12, block))
    L = np.empty((12, block))
    S = np.empty((block, flat.shape[1]), dtype=out.dtype)
    TH = np.empty(block)
    SN = np.empty(block)
    CS = np.empty(block)
    for k0 in range(0, n_cfg, block):
        nb = min(block, n_cfg - k0)
        for ii in range(order.shape[0]):
            i = order[ii]
            p = int(pk[i, _I_PARENT])
            if p < 0:
                _local_block(Q, pk, i, k0, nb, W[i], TH, SN, CS)
            else:
                _local_block(Q, pk, i, k0, nb, L, TH, SN, CS)
                _compose_block(W[p], L, W[i], nb)
            if slot[i] >= 0:
                _stage_block(W[i], S, nb, slot[i])
        for b in range(nb):
            src = S[b]
            dst = flat[k0 + b]
            for j in range(src.shape[0]):
                dst[j] = src[j]
