"""Optional compiled batched FK kernel (numba), used when numba is installed (``urdftk[fast]``).

The kernel walks the links in depth-first order for each configuration and composes
``T_root_link = T_root_parent @ T_origin @ J(q)``, computing in float64 whatever the output dtype.
It is compiled on first use and cached on disk by numba (``cache=True``).
"""

from __future__ import annotations

import math

import numba
import numpy as np

__all__ = ["fk_kernel", "sincos"]

# fdlibm's split of pi/2 (33 + 33 + 53 bits) and its polynomial kernels on [-pi/4, pi/4].
_PIO2_1 = 1.57079632673412561417e00
_PIO2_2 = 6.07710050630396597660e-11
_PIO2_3 = 2.02226624871116645580e-21
_TWO_OVER_PI = 6.36619772367581382433e-01
_S1, _S2, _S3 = -1.66666666666666324348e-01, 8.33333333332248946124e-03, -1.98412698298579493134e-04
_S4, _S5, _S6 = 2.75573137070700676789e-06, -2.50507602534068634195e-08, 1.58969099521155010221e-10
_C1, _C2, _C3 = 4.16666666666666019037e-02, -1.38888888888741095749e-03, 2.48015872894767294178e-05
_C4, _C5, _C6 = -2.75573143513906633035e-07, 2.08757232129817482790e-09, -1.13596475577881948265e-11
_BLOCK = 128


@numba.njit(cache=True, nogil=True, boundscheck=False)
def sincos(x, s, c, n):
    """Write ``sin(x[:n])`` and ``cos(x[:n])`` into ``s`` and ``c`` (branch-free, so it vectorizes).

    Accurate to a few ulp (Cody-Waite reduction by pi/2 and fdlibm's polynomials for ``|x| < 1e5``,
    the C library beyond).
    """
    for i in range(n):
        v = x[i]
        k = math.floor(v * _TWO_OVER_PI + 0.5)
        r = ((v - k * _PIO2_1) - k * _PIO2_2) - k * _PIO2_3
        z = r * r
        sr = r + r * z * (_S1 + z * (_S2 + z * (_S3 + z * (_S4 + z * (_S5 + z * _S6)))))
        cr = 1.0 - 0.5 * z + z * z * (_C1 + z * (_C2 + z * (_C3 + z * (_C4 + z * (_C5 + z * _C6)))))
        quad = int(k) & 3
        swap = (quad & 1) == 1
        a = cr if swap else sr
        b = sr if swap else cr
        s[i] = -a if (quad & 2) == 2 else a
        c[i] = -b if ((quad + 1) & 2) == 2 else b
    for i in range(n):  # beyond the reduction's exact range: the C library
        if not abs(x[i]) < 1e5:
            s[i] = math.sin(x[i])
            c[i] = math.cos(x[i])


@numba.njit(cache=True, nogil=True, boundscheck=False)
def fk_kernel(Q, angles, order, parent, jtype, coord, mult, off, rot, trans, rk, rk2, dirn, slot, out):
    """Batched FK into ``out`` (N, n_out, 4, 4); see :func:`urdftk.kinematics.fk_batch`.

    Revolute angles are first gathered for a block of configurations and their sines and cosines
    computed in one vectorized pass; joints sharing an angle (mimic) share the work.

    Args:
        Q: (N, n_coords) float64 coordinates.
        angles: Per link, the index of its angle in the per-configuration angle table (-1: none);
            the table holds ``mult * Q[:, coord] + off`` of the first link using each index.
        order: Link indices to compute, parents first.
        parent: Parent link index (-1 for the root).
        jtype: Joint type code per link (0 fixed, 1 revolute, 2 prismatic, 3 floating, 4 planar).
        coord: First coordinate index per link.
        mult: Mimic multiplier per link.
        off: Mimic offset per link.
        rot: Origin rotations (n, 3, 3).
        trans: Origin translations (n, 3).
        rk: ``R_o K`` (n, 3, 3).
        rk2: ``R_o K K`` (n, 3, 3).
        dirn: ``R_o axis`` (n, 3).
        slot: Output slot per link (-1: not written).
        out: Output array (N, n_out, 4, 4), float32 or float64.
    """
    n_cfg = Q.shape[0]
    n = parent.shape[0]
    n_ang = 0
    for i in range(n):
        n_ang = max(n_ang, angles[i] + 1)
    ang_link = np.zeros(max(n_ang, 1), dtype=np.int64)
    for i in range(n):
        if angles[i] >= 0:
            ang_link[angles[i]] = i
    TH = np.zeros(_BLOCK * max(n_ang, 1))
    SN = np.zeros_like(TH)
    CS = np.zeros_like(TH)
    WR = np.zeros((n, 3, 3))
    Wt = np.zeros((n, 3))
    Rl = np.empty((3, 3))
    Rq = np.empty((3, 3))
    tl = np.empty(3)
    for k in range(n_cfg):
        kb = k % _BLOCK
        if kb == 0 and n_ang > 0:
            nb = min(_BLOCK, n_cfg - k)
            for b in range(nb):
                for a in range(n_ang):
                    li = ang_link[a]
                    TH[b * n_ang + a] = mult[li] * Q[k + b, coord[li]] + off[li]
            sincos(TH, SN, CS, nb * n_ang)
        for ii in range(order.shape[0]):
            i = order[ii]
            code = jtype[i]
            for a in range(3):
                tl[a] = trans[i, a]
            if code == 1:
                s = SN[kb * n_ang + angles[i]]
                c1 = 1.0 - CS[kb * n_ang + angles[i]]
                for a in range(3):
                    for b in range(3):
                        Rl[a, b] = rot[i, a, b] + s * rk[i, a, b] + c1 * rk2[i, a, b]
            elif code == 2:
                d = mult[i] * Q[k, coord[i]] + off[i]
                for a in range(3):
                    tl[a] += d * dirn[i, a]
                    for b in range(3):
                        Rl[a, b] = rot[i, a, b]
            elif code == 3 or code == 4:
                c0 = coord[i]
                px = Q[k, c0]
                py = Q[k, c0 + 1]
                if code == 3:
                    pz = Q[k, c0 + 2]
                    x = Q[k, c0 + 3]
                    y = Q[k, c0 + 4]
                    z = Q[k, c0 + 5]
                    w = Q[k, c0 + 6]
                    nrm = math.sqrt(x * x + y * y + z * z + w * w)
                    x /= nrm
                    y /= nrm
                    z /= nrm
                    w /= nrm
                    Rq[0, 0] = 1 - 2 * (y * y + z * z)
                    Rq[0, 1] = 2 * (x * y - z * w)
                    Rq[0, 2] = 2 * (x * z + y * w)
                    Rq[1, 0] = 2 * (x * y + z * w)
                    Rq[1, 1] = 1 - 2 * (x * x + z * z)
                    Rq[1, 2] = 2 * (y * z - x * w)
                    Rq[2, 0] = 2 * (x * z - y * w)
                    Rq[2, 1] = 2 * (y * z + x * w)
                    Rq[2, 2] = 1 - 2 * (x * x + y * y)
                else:
                    pz = 0.0
                    th = Q[k, c0 + 2]
                    c = math.cos(th)
                    s = math.sin(th)
                    Rq[0, 0] = c
                    Rq[0, 1] = -s
                    Rq[0, 2] = 0.0
                    Rq[1, 0] = s
                    Rq[1, 1] = c
                    Rq[1, 2] = 0.0
                    Rq[2, 0] = 0.0
                    Rq[2, 1] = 0.0
                    Rq[2, 2] = 1.0
                for a in range(3):
                    tl[a] += rot[i, a, 0] * px + rot[i, a, 1] * py + rot[i, a, 2] * pz
                    for b in range(3):
                        Rl[a, b] = rot[i, a, 0] * Rq[0, b] + rot[i, a, 1] * Rq[1, b] + rot[i, a, 2] * Rq[2, b]
            else:
                for a in range(3):
                    for b in range(3):
                        Rl[a, b] = rot[i, a, b]
            p = parent[i]
            if p < 0:
                for a in range(3):
                    Wt[i, a] = tl[a]
                    for b in range(3):
                        WR[i, a, b] = Rl[a, b]
            else:
                for a in range(3):
                    Wt[i, a] = Wt[p, a] + WR[p, a, 0] * tl[0] + WR[p, a, 1] * tl[1] + WR[p, a, 2] * tl[2]
                    for b in range(3):
                        WR[i, a, b] = WR[p, a, 0] * Rl[0, b] + WR[p, a, 1] * Rl[1, b] + WR[p, a, 2] * Rl[2, b]
            sl = slot[i]
            if sl >= 0:
                for a in range(3):
                    for b in range(3):
                        out[k, sl, a, b] = WR[i, a, b]
                    out[k, sl, a, 3] = Wt[i, a]
                out[k, sl, 3, 0] = 0.0
                out[k, sl, 3, 1] = 0.0
                out[k, sl, 3, 2] = 0.0
                out[k, sl, 3, 3] = 1.0
