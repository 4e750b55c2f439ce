"""The clock-free, thread-safe transform store: tf2's BufferCore, rule for rule.

Times are integer nanoseconds and 0 means "latest". The core reports failures as integer error
codes plus tf2's text (``Result`` = ``(code, payload)``); ``tf.buffer`` turns them into typed
exceptions at the API edge. One ``threading.Lock`` guards the frame tables; transformable-request
callbacks are collected under it and run after it is released.
"""

from __future__ import annotations

import logging
import threading
from collections.abc import Callable
from typing import Any

from . import _fk, _frames_text
from ._cache import Sample, StaticCache, TimeCache
from ._codes import (
    BACKWARD_EXTRAPOLATION,
    CONNECTIVITY,
    FORWARD_EXTRAPOLATION,
    INVALID_ARGUMENT,
    LOOKUP,
    MAX_GRAPH_DEPTH,
    NO_DATA_FOR_EXTRAPOLATION,
    NO_ERROR,
)
from ._math import canonical_rotation, compose
from ._reject import reject
from ._walk import HIT, TreeWalker, up

__all__ = [
    "BACKWARD_EXTRAPOLATION",
    "CONNECTIVITY",
    "FORWARD_EXTRAPOLATION",
    "INVALID_ARGUMENT",
    "LOOKUP",
    "MAX_GRAPH_DEPTH",
    "NEVER_TRANSFORMABLE",
    "NO_DATA_FOR_EXTRAPOLATION",
    "NO_ERROR",
    "BufferCore",
    "TransformableCallback",
]

NEVER_TRANSFORMABLE = 0xFFFFFFFFFFFFFFFF
_TOLERANCE = 10e-3  # QUATERNION_NORMALIZATION_TOLERANCE
_MAX_NAMES_IN_ERRORS = 30

_log = logging.getLogger("tf")

# callback(handle, target_frame, source_frame, time_ns, available)
TransformableCallback = Callable[[int, str, str, int, bool], Any]


def _strip(name: str) -> str:
    return name[1:] if name[:1] == "/" else name


class BufferCore(TreeWalker):
    """tf2's BufferCore: per-frame time caches, tree walks, latest common time, requests.

    Args:
        cache_ns: how long (nanoseconds) dynamic samples are kept, relative to each frame's newest.
    """

    def __init__(self, cache_ns: int) -> None:
        self._cache_ns = int(cache_ns)
        self._lock = threading.Lock()
        self._ids: dict[str, int] = {"NO_PARENT": 0}
        self._names: list[str] = ["NO_PARENT"]
        self._caches: list[TimeCache | StaticCache | None] = [None]
        self._records: list[tuple | None] = [None]  # see _fk: composed newest links, per frame
        self._authority: dict[int, str] = {}
        self._requests: dict[int, tuple[TransformableCallback, str, str, int]] = {}
        self._request_counter = 0

    # ------------------------------------------------------------------ insertion
    def insert(
        self,
        parent: str,
        child: str,
        stamp_ns: int,
        values: tuple[float, float, float, float, float, float, float],
        authority: str,
        is_static: bool,
    ) -> bool:
        """tf2 setTransform: validate, then store; returns False (and logs, as tf2) if rejected.

        ``values`` is (qx, qy, qz, qw, tx, ty, tz).
        """
        if parent[:1] == "/":
            parent = parent[1:]
        if child[:1] == "/":
            child = child[1:]
        qx, qy, qz, qw, tx, ty, tz = values
        norm_error = abs(qw * qw + qx * qx + qy * qy + qz * qz - 1.0)
        if child == parent or not child or not parent or not norm_error < _TOLERANCE:
            return reject(parent, child, values, authority)
        if tx != tx or ty != ty or tz != tz:  # NaN rotations already fail the norm test
            return reject(parent, child, values, authority)
        fire: list[tuple[TransformableCallback, int, str, str, int, bool]] | None = None
        with self._lock:
            ids = self._ids
            cid = ids.get(child)
            if cid is None:
                cid = self._new_frame(child)
            pid = ids.get(parent)
            if pid is None:
                pid = self._new_frame(parent)
            cache = self._caches[cid]
            if cache is None or cache.static != is_static:  # ROS 2: a kind switch reallocates
                cache = StaticCache() if is_static else TimeCache(self._cache_ns)
                self._caches[cid] = cache
            if not cache.insert((stamp_ns, pid, qx, qy, qz, qw, tx, ty, tz)):
                ok = False
            else:
                ok = True
                _fk.extend(self._records, self._caches, cid)
                self._authority[cid] = authority
                if self._requests:
                    fire = self._test_requests()
        if not ok:
            _log.warning(
                "TF_OLD_DATA ignoring data from the past for frame %s at time %s according to authority %s\n"
                "Possible reasons are listed at http://wiki.ros.org/tf/Errors%%20explained",
                child,
                "%.6f" % (stamp_ns * 1e-9),
                authority,
            )
            return False
        if fire:
            for cb, handle, target, source, t, available in fire:
                cb(handle, target, source, t, available)
        return True

    def _new_frame(self, name: str) -> int:
        fid = len(self._names)
        self._ids[name] = fid
        self._names.append(name)
        self._caches.append(None)
        self._records.append(None)
        return fid

    def clear(self) -> None:
        """Empty every dynamic cache; static values and frame names stay (tf2 clear)."""
        with self._lock:
            for cache in self._caches:
                if cache is not None:
                    cache.clear()

    # ------------------------------------------------------------------ names
    def _frame_list_hint(self) -> str:
        names = self._names[1:]
        shown = ", ".join(names[:_MAX_NAMES_IN_ERRORS])
        more = f" (and {len(names) - _MAX_NAMES_IN_ERRORS} more)" if len(names) > _MAX_NAMES_IN_ERRORS else ""
        return f"Known frames: [{shown}]{more}." if names else "No frames are known yet."

    def validate(self, function_arg: str, name: str) -> tuple[int, Any]:
        """tf2 validateFrameId (throwing flavour): (0, id) or (code, message)."""
        if not name:
            return INVALID_ARGUMENT, (
                f'Invalid argument "{name}" passed to {function_arg} - in tf2 frame_ids cannot be empty'
            )
        if name[0] == "/":
            return INVALID_ARGUMENT, (
                f'Invalid argument "{name}" passed to {function_arg} - '
                "in tf2 frame_ids cannot start with a '/'"
            )
        fid = self._ids.get(name, 0)
        if not fid:
            return LOOKUP, f'"{name}" passed to {function_arg} does not exist. ' + self._frame_list_hint()
        return NO_ERROR, fid

    def _check_can_name(self, function_arg: str, name: str) -> tuple[int, str]:
        """tf2 validateFrameId (message flavour used by canTransform): (id, "") or (0, reason)."""
        if not name:
            why = "in tf2 frame_ids cannot be empty"
        elif name[0] == "/":
            why = "in tf2 frame_ids cannot start with a '/'"
        else:
            fid = self._ids.get(name, 0)
            if fid:
                return fid, ""
            why = "frame does not exist"
        return 0, f'Invalid frame ID "{name}" passed to {function_arg} - {why}'

    # ------------------------------------------------------------------ queries
    def lookup(self, target: str, source: str, t: int) -> tuple[int, Any]:
        """tf2 lookupTransform: (0, (stamp, qx, qy, qz, qw, tx, ty, tz)) or (code, message).

        The rotation is returned as ROS 2 does: normalised through a rotation matrix.
        """
        with self._lock:
            if target == source:
                if not t:
                    cache = self._caches[self._ids.get(target, 0)]
                    t = cache.latest_stamp_and_parent()[0] if cache is not None else 0
                return NO_ERROR, (t, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0)
            ids = self._ids
            target_id = ids.get(target, 0)
            source_id = ids.get(source, 0)
            if not target_id or target[0] == "/":
                code, target_id = self.validate("lookupTransform argument target_frame", target)
                if code:
                    return code, target_id
            if not source_id or source[0] == "/":
                code, source_id = self.validate("lookupTransform argument source_frame", source)
                if code:
                    return code, source_id
            if t and source_id != target_id:  # _walk's source pass, inlined for ancestor targets
                hit = up(self._caches, source_id, t, 0, target_id)
                if hit[0] != HIT:
                    code, r = self._walk_rest(t, target_id, source_id, hit)
                    hit = None
            else:
                hit = None
                code, r = self._walk(t, target_id, source_id)
        if hit is not None:  # normalised outside the lock
            return NO_ERROR, (t, *canonical_rotation(hit[4], hit[5], hit[6], hit[7]), hit[8], hit[9], hit[10])
        if code:
            return code, r
        return NO_ERROR, (r[0], *canonical_rotation(r[1], r[2], r[3], r[4]), r[5], r[6], r[7])

    def lookup_many(self, target: str, sources: list[str], t: int) -> list[tuple[int, Any]]:
        """``lookup`` for many sources under one lock, with the raw (unnormalised) rotations."""
        out = []
        with self._lock:
            ids = self._ids
            target_id = ids.get(target, 0)
            code, target_id = (
                (NO_ERROR, target_id)
                if target_id and target[0] != "/"
                else self.validate("lookupTransform argument target_frame", target)
            )
            if code:
                return [(code, target_id)] * len(sources)
            found = []
            for source in sources:
                source_id = ids.get(source, 0)
                if source == target:
                    found.append(target_id)
                elif not source_id or source[0] == "/":
                    found.append(self.validate("lookupTransform argument source_frame", source))
                else:
                    found.append(source_id)
            valid = [f for f in found if isinstance(f, int)]
            walked = iter(self._walk_many(t, target_id, valid))
            out = [next(walked) if isinstance(f, int) else f for f in found]
        return out

    def lookup_full(
        self, target: str, t_target: int, source: str, t_source: int, fixed: str
    ) -> tuple[int, Any]:
        """Fixed-frame lookup: (target<-fixed at t_target) * (fixed<-source at t_source)."""
        with self._lock:
            for arg, name in (("target_frame", target), ("source_frame", source), ("fixed_frame", fixed)):
                code, msg = self.validate("lookupTransform argument " + arg, name)
                if code:
                    return code, msg
        code, a = self.lookup(fixed, source, t_source)
        if code:
            return code, a
        code, b = self.lookup(target, fixed, t_target)
        if code:
            return code, b
        return NO_ERROR, (b[0], *compose(b[1:], a[1:]))

    def _can(self, target_id: int, source_id: int, t: int) -> str:
        """tf2 canTransformInternal (lock held): "" if transformable, else the reason."""
        if not target_id or not source_id:
            return "Source or target frame is not yet defined"
        if target_id == source_id:
            return ""
        code, r = self._walk(t, target_id, source_id)
        return r if code else ""

    def can_transform_reason(self, target: str, source: str, t: int) -> str:
        """tf2 canTransform: "" if transformable now, else tf2's reason; never raises."""
        if target == source:
            return ""
        with self._lock:
            target_id, why = self._check_can_name("canTransform argument target_frame", target)
            if not target_id:
                return why
            source_id, why = self._check_can_name("canTransform argument source_frame", source)
            if not source_id:
                return why
            return self._can(target_id, source_id, t)

    def can_transform_full_reason(
        self, target: str, t_target: int, source: str, t_source: int, fixed: str
    ) -> str:
        """tf2 canTransform with a fixed frame: "" if transformable now, else the reason."""
        with self._lock:
            ids = []
            for arg, name in (("target_frame", target), ("source_frame", source), ("fixed_frame", fixed)):
                fid, why = self._check_can_name("canTransform argument " + arg, name)
                if not fid:
                    return why
                ids.append(fid)
            target_id, source_id, fixed_id = ids
            return self._can(target_id, fixed_id, t_target) or self._can(fixed_id, source_id, t_source)

    def latest_common_time(self, target: str, source: str) -> tuple[int, Any]:
        """(0, time_ns) or (code, message) for the latest time both frames share (0 = static only)."""
        with self._lock:
            code, target_id = self.validate("get_latest_common_time", target)
            if code:
                return code, target_id
            code, source_id = self.validate("get_latest_common_time", source)
            if code:
                return code, source_id
            return self._latest_common_time(target_id, source_id)

    # ------------------------------------------------------------------ transformable requests
    def add_transformable_request(
        self, callback: TransformableCallback, target: str, source: str, t: int
    ) -> int:
        """tf2 addTransformableRequest.

        Returns 0 if already transformable, ``NEVER_TRANSFORMABLE`` if ``t`` is older than the latest
        common time minus the cache time, else a handle; ``callback(handle, target, source, t,
        available)`` then runs once, from the thread that inserts the deciding transform, outside
        every lock.
        """
        if target == source:
            return 0
        with self._lock:
            target_id = self._ids.get(target, 0)
            source_id = self._ids.get(source, 0)
            if target_id and source_id:
                if not self._can(target_id, source_id, t):
                    return 0
                code, latest = self._latest_common_time(target_id, source_id)
                if not code and latest and t + self._cache_ns < latest:
                    return NEVER_TRANSFORMABLE
            self._request_counter += 1
            handle = self._request_counter
            self._requests[handle] = (callback, target, source, t)
            return handle

    def cancel_transformable_request(self, handle: int) -> None:
        """Forget a pending request (no-op if it already fired)."""
        with self._lock:
            self._requests.pop(handle, None)

    def _test_requests(self) -> list[tuple[TransformableCallback, int, str, str, int, bool]]:
        fire = []
        ids = self._ids
        for handle, (cb, target, source, t) in list(self._requests.items()):
            target_id = ids.get(target, 0)
            source_id = ids.get(source, 0)
            available = None
            if target_id and source_id:
                code, latest = self._latest_common_time(target_id, source_id)
                if not code and latest and t + self._cache_ns < latest:
                    available = False
                elif not self._can(target_id, source_id, t):
                    available = True
            if available is not None:
                del self._requests[handle]
                fire.append((cb, handle, target, source, t, available))
        return fire

    # ------------------------------------------------------------------ introspection
    def all_frames_as_string(self) -> str:
        """tf2 allFramesAsString."""
        with self._lock:
            return _frames_text.as_string(self._names, self._caches)

    def all_frames_as_yaml(self, current_time_ns: int = 0) -> str:
        """tf2 (ROS 2) allFramesAsYAML."""
        with self._lock:
            return _frames_text.as_yaml(self._names, self._caches, self._authority, current_time_ns)

    def all_frames_as_dot(self, current_time_ns: int = 0) -> str:
        """tf2 _allFramesAsDot (graphviz)."""
        with self._lock:
            return _frames_text.as_dot(self._names, self._caches, self._authority, current_time_ns)

    def frame_names(self) -> list[str]:
        """Every frame name seen, in first-seen order."""
        with self._lock:
            return self._names[1:]

    def frame_exists(self, name: str) -> bool:
        """Whether ``name`` has been seen as a frame or a parent."""
        with self._lock:
            return self._ids.get(name, 0) != 0

    def parent_of(self, name: str, t: int) -> str | None:
        """The parent of ``name`` at time ``t`` (0 = latest), or None."""
        with self._lock:
            cache = self._caches[self._ids.get(name, 0)]
            if cache is None:
                return None
            s: Sample | None = cache.sample_at(t)
            return None if s is None or not s[1] else self._names[s[1]]
