"""Insert-time forward composition for "latest" lookups (time 0), invalidated by sample identity.

For each frame the core keeps one record of its newest link composed onto its parent's record, the
way a state publisher's data arrives (parents first, one stamp for the whole tree):

    record = (sample, parent_record | None, anchor_id, stamp, qx, qy, qz, qw, tx, ty, tz)

``sample`` is the frame's cache ``latest`` tuple used; the transform is ``T_anchor_frame`` composed
from the newest samples of every link between the frame and its anchor, all dynamic ones sharing
``stamp`` (static links have no stamp; 0 = only static links). A record is used only after checking
that every link's current ``latest`` *is* the sample it was built from, and that every parent
record *is* the parent frame's current record, so any insert that changes a newest sample (or
``clear()``, or a cache-kind switch) invalidates it: nothing stale is ever returned. Whatever does
not fit (zero stamps, mixed stamps, parents inserted after children, targets inside the chain) is
left to the general walk. The core's lock is held by every caller.
"""

from __future__ import annotations

from typing import Any

from ._codes import MAX_GRAPH_DEPTH

__all__ = ["extend", "lookup_latest"]

_REFRESH_DEPTH = 8


def extend(records: list[Any], caches: list[Any], cid: int) -> None:
    """Refresh frame ``cid``'s record after an accepted insert into its cache."""
    cache = caches[cid]
    s = cache.latest
    old = records[cid]
    if old is not None and old[0] is s:
        return  # the newest sample did not change (older or duplicate data)
    if cache.static:
        records[cid] = _compose(records, caches, s, True, _REFRESH_DEPTH)
        return
    # the dynamic case of _compose, inlined (it runs on every insert)
    stamp, pid, x, y, z, w, tx, ty, tz = s
    pcache = caches[pid]
    p = records[pid]
    if not stamp or pcache is None or p is None or p[0] is not pcache.latest or pcache.static:
        records[cid] = _compose(records, caches, s, False, _REFRESH_DEPTH)
        return
    _, _, anchor, pstamp, px, py, pz, pw, vx, vy, vz = p
    if pstamp and pstamp != stamp:
        records[cid] = (s, None, pid, stamp, x, y, z, w, tx, ty, tz)
        return
    rx = pw * tx + py * tz - pz * ty
    ry = pw * ty + pz * tx - px * tz
    rz = pw * tz + px * ty - py * tx
    rw = -px * tx - py * ty - pz * tz
    records[cid] = (
        s,
        p,
        anchor,
        stamp,
        pw * x + px * w + py * z - pz * y,
        pw * y + py * w + pz * x - px * z,
        pw * z + pz * w + px * y - py * x,
        pw * w - px * x - py * y - pz * z,
        -rw * px + rx * pw - ry * pz + rz * py + vx,
        -rw * py + ry * pw - rz * px + rx * pz + vy,
        -rw * pz + rz * pw - rx * py + ry * px + vz,
    )


def _compose(records: list[Any], caches: list[Any], s: tuple, static: bool, budget: int) -> tuple | None:
    """The record of the link ``s`` (a cache's latest sample), composed onto its parent's if it can.

    A static parent (sent once, often before the rest of the tree existed) whose own record is not
    linked to its parent's current record is recomposed first, up to ``budget`` static levels.
    """
    stamp = 0 if static else s[0]
    if not static and not stamp:
        return None  # tf2's common time ignores zero stamps: leave it to the walk
    _, pid, x, y, z, w, tx, ty, tz = s
    pcache = caches[pid]
    p = records[pid]
    if pcache is None or p is None or p[0] is not pcache.latest:
        return (s, None, pid, stamp, x, y, z, w, tx, ty, tz)
    if budget and pcache.static:
        ppid = p[0][1]
        if caches[ppid] is not None and p[1] is not records[ppid]:
            p = records[pid] = _compose(records, caches, p[0], True, budget - 1)
    _, _, anchor, pstamp, px, py, pz, pw, vx, vy, vz = p
    if pstamp and stamp and pstamp != stamp:
        return (s, None, pid, stamp, x, y, z, w, tx, ty, tz)
    # T_anchor_child = T_anchor_parent * T_parent_child; raw quaternions as tf2's TransformAccum
    rx = pw * tx + py * tz - pz * ty
    ry = pw * ty + pz * tx - px * tz
    rz = pw * tz + px * ty - py * tx
    rw = -px * tx - py * ty - pz * tz
    return (
        s,
        p,
        anchor,
        pstamp or stamp,
        pw * x + px * w + py * z - pz * y,
        pw * y + py * w + pz * x - px * z,
        pw * z + pz * w + px * y - py * x,
        pw * w - px * x - py * y - pz * z,
        -rw * px + rx * pw - ry * pz + rz * py + vx,
        -rw * py + ry * pw - rz * px + rx * pz + vy,
        -rw * pz + rz * pw - rx * py + ry * px + vz,
    )


def lookup_latest(records: list[Any], caches: list[Any], target_id: int, source_id: int) -> tuple | None:
    """(stamp, qx, qy, qz, qw, tx, ty, tz) of T_target_source at time 0, or None if no valid record.

    Valid only when ``target_id`` is the anchor of ``source_id``'s record chain and every record of
    the chain is current; then the chain is exactly tf2's path and its stamp the latest common time.
    """
    rec = records[source_id]
    if rec is None:
        return None
    r = rec
    frame = source_id
    depth = 0
    while True:
        if caches[frame].latest is not r[0]:
            return None
        p = r[1]
        if p is None:
            break
        frame = r[0][1]
        if frame == target_id or records[frame] is not p:
            return None
        r = p
        depth += 1
        if depth >= MAX_GRAPH_DEPTH:
            return None
    if r[2] != target_id:
        return None
    return rec[3:]
