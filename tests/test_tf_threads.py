"""Thread safety: 4 writer threads at 1 kHz and 4 reader threads for 10 s on one tf.Buffer."""

from __future__ import annotations

import math
import threading
import time

import pytest

import tf

WRITERS = 4
READERS = 4
RATE_HZ = 1000.0
DURATION_S = 10.0
CACHE_S = 2.0


def _writer(
    buf: tf.Buffer, index: int, stop: threading.Event, sent: list[int], errors: list[BaseException]
) -> None:
    """Publishes its own chain link (w -> l{index}) on a 1 kHz schedule with strictly increasing stamps."""
    try:
        child = f"l{index}"
        parent = "w" if index == 0 else f"l{index - 1}"
        start = time.monotonic()
        n = 0
        while not stop.is_set():
            n += 1
            stamp = tf.Time.from_nsec(1_000_000_000 + n * 1_000_000)  # 1 ms apart, like a 1 kHz publisher
            angle = 0.001 * n
            msg = tf.TransformStamped(
                tf.Header(stamp, parent),
                child,
                tf.Transform(
                    tf.Vector3(0.1, 0.0, 0.0), tf.Quaternion(0.0, 0.0, math.sin(angle), math.cos(angle))
                ),
            )
            if not buf.set_transform(msg, f"writer{index}"):
                raise AssertionError(f"sample {n} of {child} rejected")
            sent[index] = n
            delay = start + n / RATE_HZ - time.monotonic()
            if delay > 0:
                stop.wait(delay)
    except BaseException as exc:  # reported to the main thread
        errors.append(exc)


def _reader(
    buf: tf.Buffer, index: int, stop: threading.Event, counts: list[int], errors: list[BaseException]
) -> None:
    try:
        source = f"l{WRITERS - 1 - index % WRITERS}"
        k = 0
        while not stop.is_set():
            k += 1
            try:
                if k % 3 == 0:
                    t = buf.lookup_transform("w", source, tf.Time())
                    assert t.header.frame_id == "w"
                    assert abs(math.hypot(t.transform.rotation.z, t.transform.rotation.w) - 1.0) < 1e-9
                elif k % 3 == 1:
                    latest = buf.get_latest_common_time("w", source)
                    buf.lookup_transform(source, "w", latest - tf.Duration.from_sec(0.0005))
                else:
                    buf.lookup_transforms("w", ["l0", "l1", "l2", "l3"])
                counts[index] += 1
            except (tf.ExtrapolationException, tf.LookupException, tf.ConnectivityException):
                pass  # expected while links start or when a reader races past the newest stamps
    except BaseException as exc:
        errors.append(exc)


@pytest.mark.timeout(60)
def test_four_writers_at_1khz_and_four_readers_for_10s() -> None:
    buf = tf.Buffer(tf.Duration.from_sec(CACHE_S))
    stop = threading.Event()
    errors: list[BaseException] = []
    sent = [0] * WRITERS
    reads = [0] * READERS
    threads = [threading.Thread(target=_writer, args=(buf, i, stop, sent, errors)) for i in range(WRITERS)]
    threads += [threading.Thread(target=_reader, args=(buf, i, stop, reads, errors)) for i in range(READERS)]
    for th in threads:
        th.start()
    peak = 0
    deadline = time.monotonic() + DURATION_S
    while time.monotonic() < deadline and not errors:
        stop.wait(0.5)
        peak = max(peak, max(len(buf._core._caches[buf._core._ids[f"l{i}"]]) for i in range(WRITERS)))
    stop.set()
    for th in threads:
        th.join(10)
    assert not errors, errors
    core = buf._core
    for i in range(WRITERS):
        cache = core._caches[core._ids[f"l{i}"]]
        stamps = cache.stamps[cache.lo :]
        # no lost samples: every stamp the writer sent within the cache window is there, once, in order
        newest = 1_000_000_000 + sent[i] * 1_000_000
        # ROS 2 prunes before inserting, against the previous newest stamp (1 ms earlier)
        oldest_kept = max(1_001_000_000, newest - 1_000_000 - int(CACHE_S * 1e9))
        assert stamps == list(range(oldest_kept, newest + 1, 1_000_000))
        assert stamps == sorted(stamps)
        assert stamps[-1] == newest
        # memory bounded by cache_time: at most cache_time worth of samples (+1 before the next prune)
        assert len(cache) <= CACHE_S * 1000 + 2
        assert len(cache.stamps) <= (CACHE_S * 1000 + 2) * 9 / 8 + 32  # dead entries are compacted
    assert min(sent) > DURATION_S * RATE_HZ * 0.3, f"writers fell far behind 1 kHz: {sent}"
    assert min(reads) > 1000, reads
    assert peak <= CACHE_S * 1000 + 2
