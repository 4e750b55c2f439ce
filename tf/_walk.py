"""tf2's tree walks (walkToTopParent, getLatestCommonTime) over the core's frame tables.

A mixin of ``_core.BufferCore``: every method runs with the core's lock held and reads
``self._caches`` (frame id -> cache or None) and ``self._names`` (frame id -> name).
Results are ``(code, payload)``: code 0 and the value, or an error code and tf2's text.
"""

from __future__ import annotations

import math
from bisect import bisect_right as _bisect
from typing import Any

from . import _fk, _frames_text
from ._cache import PAIR
from ._codes import CONNECTIVITY, LOOKUP, MAX_GRAPH_DEPTH, NO_ERROR
from ._math import quat_multiply, quat_rotate

__all__ = ["HIT", "TreeWalker", "up"]

_PAIR = PAIR.unpack_from
_sin = math.sin
_STOP = 0  # reached ``end``, a frame without data, or (source pass only) a failing link
HIT = _HIT = 1  # reached ``other``
_FAIL = 2  # a link has no data at t (target pass: reported at once)
_LOOP = 3
_DEPTHS = range(MAX_GRAPH_DEPTH + 1)
_NEVER = 1 << 64  # later than any stamp


def up(caches: list[Any], frame: int, t: int, end: int, other: int) -> tuple:
    """One half of walkToTopParent: compose links upwards from ``frame`` at time ``t``.

    Stops at ``end`` or a frame without a cache (_STOP), at ``other`` (_HIT), when a link has no
    data at ``t`` (_STOP with that cache as ``failed`` when ``end`` is 0, i.e. the source pass;
    _FAIL otherwise), or after MAX_GRAPH_DEPTH links (_LOOP). Returns (kind, frame, last frame
    composed, failed cache, qx, qy, qz, qw, tx, ty, tz) with tf2's TransformAccum arithmetic;
    interpolation (tf2 TimeCache::interpolate) is inlined for the common case.
    """
    sx = sy = sz = 0.0
    sw = 1.0
    svx = svy = svz = 0.0
    last = frame
    miss = _FAIL if end else _STOP
    before = t or _NEVER  # ``before < stamp``: t is before the stamp (never true at t = 0)
    for depth in _DEPTHS:  # after MAX_GRAPH_DEPTH + 1 links: a loop (tf2 walkToTopParent)
        if frame == end:
            break
        if frame == other:
            return _HIT, frame, last, None, sx, sy, sz, sw, svx, svy, svz
        cache = caches[frame]
        if cache is None:
            break
        s = cache.latest
        if s is None:
            return miss, frame, last, cache, sx, sy, sz, sw, svx, svy, svz
        if before < s[0]:  # t before a dynamic cache's newest stamp (static stamps are 0)
            p = cache.pair
            if p[0] < t:  # between the two newest samples, one parent
                s1, parent, x, y, z, w, tx, ty, tz, th, k, x2, y2, z2, w2, inv, dx, dy, dz = p
                r = (t - s1) * inv
            else:
                stamps = cache.stamps
                lo = cache.lo
                i = _bisect(stamps, t, lo) - 1
                s1 = stamps[i]
                parents = cache.parents
                parent = parents[i]
                if i >= lo and s1 != t and parent == parents[i + 1]:
                    r = (t - s1) / (stamps[i + 1] - s1)
                    x, y, z, w, tx, ty, tz, th, k, x2, y2, z2, w2, dx, dy, dz = _PAIR(cache.data, i * 72)
                    dx -= tx
                    dy -= ty
                    dz -= tz
                    if th < 0.0:  # shortest path: negate q2 (as the newest pair already holds it)
                        th = -th
                        x2 = -x2
                        y2 = -y2
                        z2 = -z2
                        w2 = -w2
                else:  # exact stamp, re-parenting, or before the oldest sample
                    s = cache.sample_at(t)
                    if s is None:
                        return miss, frame, last, cache, sx, sy, sz, sw, svx, svy, svz
                    _, parent, x, y, z, w, tx, ty, tz = s
                    th = r = dx = dy = dz = 0.0  # "interpolating" at r = 0 keeps the sample as is
            if th:  # tf2 Quaternion::slerp with theta and 1 / sin(theta) precomputed at insert
                a = _sin((1.0 - r) * th) * k
                b = _sin(r * th) * k
                x = x * a + x2 * b
                y = y * a + y2 * b
                z = z * a + z2 * b
                w = w * a + w2 * b
            tx += r * dx  # lerp
            ty += r * dy
            tz += r * dz
        elif t == s[0] or not t or cache.static:
            _, parent, x, y, z, w, tx, ty, tz = s
        else:  # after the newest sample: extrapolation into the future
            return miss, frame, last, cache, sx, sy, sz, sw, svx, svy, svz
        if depth:
            # tf2 TransformAccum::accum: v = q v q* + t (q unnormalised), then q = q_link q
            rx = w * svx + y * svz - z * svy
            ry = w * svy + z * svx - x * svz
            rz = w * svz + x * svy - y * svx
            mw = x * svx + y * svy + z * svz
            svx = mw * x + rx * w - ry * z + rz * y + tx
            svy = mw * y + ry * w - rz * x + rx * z + ty
            svz = mw * z + rz * w - rx * y + ry * x + tz
            nx = w * sx + x * sw + y * sz - z * sy
            ny = w * sy + y * sw + z * sx - x * sz
            nz = w * sz + z * sw + x * sy - y * sx
            sw = w * sw - x * sx - y * sy - z * sz
            sx = nx
            sy = ny
            sz = nz
        else:
            sx, sy, sz, sw, svx, svy, svz = x, y, z, w, tx, ty, tz
        last = frame
        frame = parent
    else:
        return _LOOP, frame, last, None, sx, sy, sz, sw, svx, svy, svz
    return _STOP, frame, last, None, sx, sy, sz, sw, svx, svy, svz


class TreeWalker:
    """Walks from frames to their roots, accumulating transforms exactly as tf2 does."""

    _caches: list[Any]
    _records: list[Any]
    _names: list[str]

    def _loop_error(self) -> tuple[int, str]:
        text = _frames_text.as_string(self._names, self._caches)
        return LOOKUP, "The tf tree is invalid because it contains a loop.\n" + text + "\n"

    def _connectivity_error(self, source_id: int, target_id: int) -> tuple[int, str]:
        return CONNECTIVITY, (
            f"Could not find a connection between '{self._names[target_id]}' and "
            f"'{self._names[source_id]}' because they are not part of the same tree."
            "Tf has two or more unconnected trees."
        )

    def _latest_common_time(self, target_id: int, source_id: int) -> tuple[int, Any]:
        """tf2 getLatestCommonTime: (0, time_ns) or (code, message)."""
        caches = self._caches
        if source_id == target_id:
            cache = caches[source_id]
            return NO_ERROR, (cache.latest_stamp_and_parent()[0] if cache is not None else 0)
        parents_seen: dict[int, int] = {}  # parent id -> newest stamp of the link leading to it
        order: list[tuple[int, int]] = []
        frame = source_id
        depth = 0
        common = -1
        while frame:
            cache = caches[frame]
            if cache is None:
                break
            latest = cache.latest
            if latest is None:
                break
            stamp = 0 if cache.static else latest[0]
            parent = latest[1]
            if stamp and (common < 0 or stamp < common):
                common = stamp
            order.append((stamp, parent))
            if parent not in parents_seen:
                parents_seen[parent] = len(order) - 1
            frame = parent
            if frame == target_id:
                return NO_ERROR, max(common, 0)
            depth += 1
            if depth > MAX_GRAPH_DEPTH:
                return self._loop_error()
        frame = target_id
        depth = 0
        common = -1
        common_index = -1
        while True:
            cache = caches[frame]
            if cache is None:
                break
            latest = cache.latest
            if latest is None:
                break
            stamp = 0 if cache.static else latest[0]
            parent = latest[1]
            if stamp and (common < 0 or stamp < common):
                common = stamp
            common_index = parents_seen.get(parent, -1)
            if common_index >= 0:
                break
            frame = parent
            if frame == source_id:
                return NO_ERROR, max(common, 0)
            depth += 1
            if depth > MAX_GRAPH_DEPTH:
                return self._loop_error()
        if common_index < 0:
            return self._connectivity_error(source_id, target_id)
        for stamp, _parent in order[: common_index + 1]:
            if stamp and (common < 0 or stamp < common):
                common = stamp
        return NO_ERROR, max(common, 0)

    def _walk(self, t: int, target_id: int, source_id: int) -> tuple[int, Any]:
        """tf2 walkToTopParent with TransformAccum.

        Returns (0, (stamp, qx, qy, qz, qw, tx, ty, tz)) with the raw accumulated rotation, or
        (code, message).
        """
        if source_id == target_id:
            return NO_ERROR, (t, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0)
        if not t:
            found = _fk.lookup_latest(self._records, self._caches, target_id, source_id)
            if found is not None:
                return NO_ERROR, found
            found = self._walk_latest(target_id, source_id)
            if found is not None:
                return found
            code, t = self._latest_common_time(target_id, source_id)
            if code:
                return code, t
        # ---- source -> root (stops early if the target is an ancestor of the source)
        r = up(self._caches, source_id, t, 0, target_id)
        if r[0] == _HIT:
            return NO_ERROR, (t, *r[4:])
        return self._walk_rest(t, target_id, source_id, r)

    def _walk_rest(self, t: int, target_id: int, source_id: int, r: tuple) -> tuple[int, Any]:
        """``_walk`` after a source pass ``r`` (``up`` from the source) that did not reach the target."""
        caches = self._caches
        kind = r[0]
        if kind == _LOOP:
            return self._loop_error()
        _, top, last, failed, sx, sy, sz, sw, svx, svy, svz = r
        if not top:  # a link to "NO_PARENT" (id 0): tf2 stops at the last frame walked
            top = last
        # ---- target -> top of the source chain (stops early if the source is an ancestor)
        r = up(caches, target_id, t, top, source_id)
        kind = r[0]
        if kind == _LOOP:
            return self._loop_error()
        if kind == _FAIL:
            code, text = r[3].error_at(t)
            return code, text + self._suffix(source_id, target_id)
        _, frame, _, _, gx, gy, gz, gw, gvx, gvy, gvz = r
        if kind == _HIT:
            ix, iy, iz = quat_rotate(-gx, -gy, -gz, gw, -gvx, -gvy, -gvz)
            return NO_ERROR, (t, -gx, -gy, -gz, gw, ix, iy, iz)
        if frame != top:
            if failed is not None:
                code, text = failed.error_at(t)
                return code, text + self._suffix(source_id, target_id)
            return self._connectivity_error(source_id, target_id)
        # ---- full path: inverse(target->top) * (source->top)
        ix, iy, iz = quat_rotate(-gx, -gy, -gz, gw, -gvx, -gvy, -gvz)
        vx, vy, vz = quat_rotate(-gx, -gy, -gz, gw, svx, svy, svz)
        qx, qy, qz, qw = quat_multiply(-gx, -gy, -gz, gw, sx, sy, sz, sw)
        return NO_ERROR, (t, qx, qy, qz, qw, vx + ix, vy + iy, vz + iz)

    def _suffix(self, source_id: int, target_id: int) -> str:
        return (
            f", when looking up transform from frame [{self._names[source_id]}] "
            f"to frame [{self._names[target_id]}]"
        )

    def _walk_latest(self, target_id: int, source_id: int) -> tuple[int, Any] | None:
        """Fast path of ``_walk`` at time 0 when the target is an ancestor of the source.

        One pass walks up from the source composing the newest samples, while computing the
        chain's latest common time (tf2's getLatestCommonTime, source side). If every dynamic link
        has that same newest stamp (a state publisher's pattern) the composition is the answer;
        otherwise the general walk runs at that common time (tf2's getLatestCommonTime gives the
        same value on this path). Returns None whenever the general two-pass walk is needed from
        the start (other topologies, zero stamps only), so results are always the general walk's.
        """
        caches = self._caches
        depth = 0
        frame = source_id
        common = 0
        uniform = True
        sx = sy = sz = 0.0
        sw = 1.0
        svx = svy = svz = 0.0
        first = True
        while True:
            cache = caches[frame]
            if cache is None:
                return None
            s = cache.latest
            if s is None:
                return None
            stamp = s[0]
            if not cache.static:
                if not stamp:
                    uniform = False  # tf2 ignores zero stamps in the common time: recompose at it
                elif not common:
                    common = stamp
                elif stamp != common:
                    uniform = False
                    if stamp < common:
                        common = stamp
            depth += 1
            _, frame, x, y, z, w, tx, ty, tz = s
            if first:
                sx, sy, sz, sw, svx, svy, svz = x, y, z, w, tx, ty, tz
                first = False
            elif uniform:
                # tf2 TransformAccum::accum (same as _walk): v = q v q* + t, q = q_link q
                rx = w * svx + y * svz - z * svy
                ry = w * svy + z * svx - x * svz
                rz = w * svz + x * svy - y * svx
                rw = -x * svx - y * svy - z * svz
                svx = -rw * x + rx * w - ry * z + rz * y + tx
                svy = -rw * y + ry * w - rz * x + rx * z + ty
                svz = -rw * z + rz * w - rx * y + ry * x + tz
                nx = w * sx + x * sw + y * sz - z * sy
                ny = w * sy + y * sw + z * sx - x * sz
                nz = w * sz + z * sw + x * sy - y * sx
                sw = w * sw - x * sx - y * sy - z * sz
                sx = nx
                sy = ny
                sz = nz
            if frame == target_id:
                break
            if not frame or depth > MAX_GRAPH_DEPTH:
                return None
        if uniform:
            return NO_ERROR, (common, sx, sy, sz, sw, svx, svy, svz)
        if not common:
            return None
        # mixed stamps: the general walk at the common time just found (what tf2 does next)
        return self._walk(common, target_id, source_id)

    def _walk_many(self, t: int, target_id: int, source_ids: list[int]) -> list[tuple[int, Any]]:
        """``_walk`` for many sources; shared links are composed once when the target is an ancestor.

        Each frame's ``T_target_frame`` is memoised for this call only (the lock is held, so the
        data cannot change). At time 0 a memo entry also carries its chain's common time; any
        source whose chain does not fit the shortcut (different stamps, re-parenting, errors,
        other topologies) goes through the general ``_walk``, so results equal single lookups up
        to rounding (composition order differs).
        """
        caches = self._caches
        memo: dict[int, tuple[int, tuple]] = {target_id: (0, (0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0))}
        out = []
        for source_id in source_ids:
            hit = memo.get(source_id)
            if hit is None:
                hit = self._memo_chain(t, source_id, memo, caches)
            if hit is None:
                out.append(self._walk(t, target_id, source_id))
            else:
                out.append((NO_ERROR, (t or hit[0], *hit[1])))
        return out

    def _memo_chain(self, t: int, source_id: int, memo: dict, caches: list[Any]) -> tuple[int, tuple] | None:
        path = []
        frame = source_id
        while frame not in memo:
            cache = caches[frame] if frame else None
            if cache is None or len(path) > MAX_GRAPH_DEPTH:
                return None
            s = cache.latest if not t else cache.sample_at(t)
            if s is None:
                return None
            path.append((frame, cache.static, s))
            frame = s[1]
        common, (qx, qy, qz, qw, vx, vy, vz) = memo[frame]
        for frame, static, s in reversed(path):
            _, _, x, y, z, w, tx, ty, tz = s
            if not t and not static:
                if not s[0] or (common and s[0] != common):
                    return None
                common = s[0]
            rx, ry, rz = quat_rotate(qx, qy, qz, qw, tx, ty, tz)
            vx, vy, vz = vx + rx, vy + ry, vz + rz
            qx, qy, qz, qw = quat_multiply(qx, qy, qz, qw, x, y, z, w)
            memo[frame] = (common, (qx, qy, qz, qw, vx, vy, vz))
        return memo[source_id]
