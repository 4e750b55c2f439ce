"""Per-child-frame time caches (tf2's TimeCache and StaticCache), clock-free and lock-free.

Samples are kept oldest-first in parallel columns: ``stamps`` (int nanoseconds, a list so that
``bisect`` runs at C speed), ``parents`` (frame ids) and ``data`` (an ``array('d')`` of nine
doubles per sample: qx qy qz qw tx ty tz, then ``theta`` and ``k`` describing the slerp from this
sample to the next one, computed when the pair forms; see ``pair_constants``). Pruned samples
are skipped with a start offset ``lo`` and compacted in batches, which keeps pruning O(1)
amortised with tf2's exact semantics. The newest sample is also kept as a ready-made tuple,
``latest`` = (stamp, parent, qx, qy, qz, qw, tx, ty, tz), for the hot "latest" path, and so is
the newest pair when both samples have the same parent, ``pair`` = (the older sample's 9 fields,
|theta|, k, the newer quaternion (negated when theta < 0), 1 / (newer stamp - older stamp), newer
translation - older translation), for interpolation between them. It is replaced on every append
and is ``NO_NEWEST_PAIR`` after any other insert or once pruning removed its older sample. The owner
(``_core.BufferCore``) does the locking.
"""

from __future__ import annotations

import math
from array import array
from bisect import bisect_right
from struct import Struct

__all__ = [
    "NO_DATA",
    "NO_NEWEST_PAIR",
    "PAIR",
    "Sample",
    "StaticCache",
    "TimeCache",
    "extrapolation_error",
    "interpolate",
    "pair_constants",
]

Sample = tuple  # (stamp_ns, parent_id, qx, qy, qz, qw, tx, ty, tz)

# Extrapolation error codes, shared with _core (values match tf2's TF2Error order).
FORWARD = 3
BACKWARD = 4
NO_DATA = 5

_REC = Struct("7d")
PAIR = Struct("16d")  # sample i (7), theta, k, sample i + 1 (7): everything to interpolate
_STRIDE = 9
_BYTES = _STRIDE * 8
_COMPACT_MIN = 32
NO_NEWEST_PAIR = (1 << 64,)  # ``TimeCache.pair`` when there is none: its "older stamp" is never < t
_sin = math.sin
_acos = math.acos
_sqrt = math.sqrt


def _fmt_time(ns: int) -> str:
    """tf2's displayTimePoint: float seconds with six decimals."""
    sec, nsec = divmod(ns, 1_000_000_000)
    return "%.6f" % (sec + nsec * 1e-9)


def extrapolation_error(code: int, t: int, bound: int) -> str:
    """tf2's (ROS 2) extrapolation text for ``code`` at requested time ``t``."""
    if code == FORWARD:
        return (
            "Lookup would require extrapolation into the future.  Requested time "
            f"{_fmt_time(t)} but the latest data is at time {_fmt_time(bound)}"
        )
    if code == BACKWARD:
        return (
            "Lookup would require extrapolation into the past.  Requested time "
            f"{_fmt_time(t)} but the earliest data is at time {_fmt_time(bound)}"
        )
    return (
        f"Lookup would require extrapolation at time {_fmt_time(t)}, "
        f"but only time {_fmt_time(bound)} is in the buffer"
    )


def pair_constants(
    x1: float, y1: float, z1: float, w1: float, x2: float, y2: float, z2: float, w2: float
) -> tuple[float, float]:
    """(theta, k) for slerp from q1 to q2, as tf2's Quaternion::slerp computes them.

    ``theta`` is the half angle of tf2's angleShortestPath (acos argument clamped as tf2Acos does),
    negated when the shortest path negates q2; ``k`` = 1 / sin(theta). theta 0 means "use q1".
    """
    d = x1 * x2 + y1 * y2 + z1 * z2 + w1 * w2
    s = math.sqrt((x1 * x1 + y1 * y1 + z1 * z1 + w1 * w1) * (x2 * x2 + y2 * y2 + z2 * z2 + w2 * w2))
    c = (-d if d < 0.0 else d) / s
    theta = math.acos(c if c < 1.0 else 1.0)
    if theta == 0.0:
        return 0.0, 0.0
    return (-theta if d < 0.0 else theta), 1.0 / math.sin(theta)


def interpolate(data: array, i: int, r: float) -> tuple[float, ...]:
    """tf2's TimeCache::interpolate of samples i and i + 1 at ratio ``r``: slerp + lerp.

    Same arithmetic as tf2's Quaternion::slerp with theta and 1/sin(theta) taken from the row.
    """
    x1, y1, z1, w1, ax, ay, az, th, k, x2, y2, z2, w2, bx, by, bz = PAIR.unpack_from(data, i * _BYTES)
    q = 1.0 - r
    if th:
        a = _sin(q * th) * k
        b = _sin(r * th) * k
        if th < 0.0:
            a = -a
        x1 = x1 * a + x2 * b
        y1 = y1 * a + y2 * b
        z1 = z1 * a + z2 * b
        w1 = w1 * a + w2 * b
    return x1, y1, z1, w1, q * ax + r * bx, q * ay + r * by, q * az + r * bz


class StaticCache:
    """One value valid at every time (tf2's StaticCache); re-inserting overwrites it."""

    __slots__ = ("latest",)
    static = True

    def __init__(self) -> None:
        self.latest: Sample | None = None

    def insert(self, sample: Sample) -> bool:
        """Store ``sample`` (its stamp is kept but never used: static data has stamp 0)."""
        self.latest = (0, *sample[1:])
        return True

    def sample_at(self, t: int) -> Sample | None:
        """The stored value, whatever ``t``."""
        return self.latest

    def error_at(self, t: int) -> tuple[int, str]:  # pragma: no cover - a static cache never fails
        """Never called: static data is valid at every time."""
        return NO_DATA, extrapolation_error(NO_DATA, t, 0)

    def clear(self) -> None:
        """Static values survive ``clear()``."""

    def latest_stamp_and_parent(self) -> tuple[int, int]:
        """(0, parent): static links do not constrain the latest common time."""
        return 0, self.latest[1]

    def oldest_stamp(self) -> int:
        """Always 0."""
        return 0

    def __len__(self) -> int:
        return 1


class TimeCache:
    """Time-stamped samples of one child frame, tf2 (ROS 2) TimeCache semantics."""

    __slots__ = ("data", "latest", "lo", "max_ns", "pair", "parents", "stamps")
    static = False

    def __init__(self, max_ns: int) -> None:
        self.max_ns = max_ns
        self.stamps: list[int] = []
        self.parents: list[int] = []
        self.data = array("d")
        self.lo = 0
        self.latest: Sample | None = None
        self.pair: tuple = NO_NEWEST_PAIR  # the newest pair (see the module docstring)

    def __len__(self) -> int:
        return len(self.stamps) - self.lo

    def clear(self) -> None:
        """Drop every sample."""
        self.stamps = []
        self.parents = []
        self.data = array("d")
        self.lo = 0
        self.latest = None
        self.pair = NO_NEWEST_PAIR

    def _record(self, i: int) -> Sample:
        return (self.stamps[i], self.parents[i], *_REC.unpack_from(self.data, i * _BYTES))

    def _set_pair(self, i: int) -> None:
        """Store the slerp constants of samples (i, i + 1) in sample i's row."""
        data = self.data
        j = i * _STRIDE
        data[j + 7 : j + 9] = array("d", pair_constants(*data[j : j + 4], *data[j + 9 : j + 13]))

    def insert(self, sample: Sample) -> bool:
        """Insert ``sample``; False (TF_OLD_DATA) if older than newest - cache time.

        As in ROS 2: prune first (entries older than the newest stamp minus the cache time), then
        reject data older than that bound; a sample equal in every field to one already stored at the
        same stamp is silently dropped, while same-stamp samples with different data are kept.
        """
        stamps = self.stamps
        n = len(stamps)
        lo = self.lo
        t = sample[0]
        if n > lo:
            newest = stamps[-1]
            limit = newest - self.max_ns
            if stamps[lo] < limit:
                lo += 1
                while stamps[lo] < limit:
                    lo += 1
                self.lo = lo
                if lo > n - 2:
                    self.pair = NO_NEWEST_PAIR  # its older sample is gone (this insert may yet be rejected)
                if lo >= _COMPACT_MIN and lo * 8 >= n:
                    self._compact()
                    n = len(stamps := self.stamps)
                    lo = 0
            if t < limit:
                return False
            if t > newest:
                # pair_constants(previous newest, sample), inlined: this is the hot insert path
                prev = self.latest
                _, _, x1, y1, z1, w1, ax, ay, az = prev
                _, parent, x2, y2, z2, w2, bx, by, bz = sample
                d = x1 * x2 + y1 * y2 + z1 * z2 + w1 * w2
                c = (-d if d < 0.0 else d) / _sqrt(
                    (x1 * x1 + y1 * y1 + z1 * z1 + w1 * w1) * (x2 * x2 + y2 * y2 + z2 * z2 + w2 * w2)
                )
                data = self.data
                j = n * _STRIDE - 2
                if c < 1.0:
                    th = _acos(c)
                    k = data[j + 1] = 1.0 / _sin(th)
                    data[j] = -th if d < 0.0 else th
                else:
                    th = k = 0.0
                inv = 1.0 / (t - newest)
                if prev[1] != parent:  # re-parenting: no pair
                    self.pair = NO_NEWEST_PAIR
                elif d < 0.0:  # shortest path: the pair holds -q2 and a positive theta
                    self.pair = (*prev, th, k, -x2, -y2, -z2, -w2, inv, bx - ax, by - ay, bz - az)
                else:
                    self.pair = (*prev, th, k, x2, y2, z2, w2, inv, bx - ax, by - ay, bz - az)
                stamps.append(t)
                self.parents.append(parent)
                data.extend((x2, y2, z2, w2, bx, by, bz, 0.0, 0.0))
                self.latest = sample
                return True
            i = bisect_right(stamps, t, lo)
            k = i - 1
            while k >= lo and stamps[k] == t:
                if self._record(k) == sample:
                    return True  # exact duplicate: dropped, not an error
                k -= 1
        else:
            i = n
        self.pair = NO_NEWEST_PAIR  # rare (out of order, equal stamps): the walk's general path takes over
        stamps.insert(i, t)
        self.parents.insert(i, sample[1])
        self.data[i * _STRIDE : i * _STRIDE] = array("d", (*sample[2:], 0.0, 0.0))
        if i == len(stamps) - 1:
            self.latest = sample
        else:
            self._set_pair(i)
        if i > 0:
            self._set_pair(i - 1)
        return True

    def _compact(self) -> None:
        lo = self.lo
        del self.stamps[:lo]
        del self.parents[:lo]
        del self.data[: lo * _STRIDE]
        self.lo = 0

    def sample_at(self, t: int) -> Sample | None:
        """tf2's getData: the sample at ``t`` (0 = newest), interpolated if needed; None on error."""
        stamps = self.stamps
        lo = self.lo
        n = len(stamps)
        if n == lo:
            return None
        if t == 0:
            return self.latest
        if n - lo == 1:
            return self.latest if stamps[lo] == t else None
        newest = stamps[-1]
        if t == newest:
            return self.latest
        if t == stamps[lo]:
            return self._record(lo)
        if t > newest or t < stamps[lo]:
            return None
        i = bisect_right(stamps, t, lo) - 1
        s1 = stamps[i]
        parents = self.parents
        if s1 == t or parents[i] != parents[i + 1]:
            return self._record(i)  # exact hit, or re-parenting: the older sample, no interpolation
        return (t, parents[i], *interpolate(self.data, i, (t - s1) / (stamps[i + 1] - s1)))

    def error_at(self, t: int) -> tuple[int, str]:
        """The error code and tf2 text explaining why ``sample_at(t)`` returned None."""
        stamps = self.stamps
        lo = self.lo
        if len(stamps) == lo:
            return NO_DATA, extrapolation_error(NO_DATA, t, 0)
        if len(stamps) - lo == 1:
            return NO_DATA, extrapolation_error(NO_DATA, t, stamps[lo])
        if t > stamps[-1]:
            return FORWARD, extrapolation_error(FORWARD, t, stamps[-1])
        return BACKWARD, extrapolation_error(BACKWARD, t, stamps[lo])

    def latest_stamp_and_parent(self) -> tuple[int, int]:
        """(newest stamp, its parent), or (0, 0) when empty."""
        s = self.latest
        return (0, 0) if s is None else (s[0], s[1])

    def oldest_stamp(self) -> int:
        """The oldest stamp held, 0 when empty."""
        return self.stamps[self.lo] if len(self.stamps) > self.lo else 0
