"""Recording and playback: rosbag2 folders with MCAP storage, written and read with ``rosbags``.

A recording is a folder ``run/`` holding ``metadata.yaml`` and ``run_0.mcap``, ``run_1.mcap``...:
the recorder closes a complete MCAP file every ``flush_interval`` seconds and then atomically
rewrites ``metadata.yaml`` to list it. A recorder that is killed therefore leaves a bag that
ROS 2 tools, Foxglove and ``rosbags.highlevel.AnyReader`` open, holding everything up to its
last flush (the unfinished segment stays in a hidden ``.segment_N`` folder).

Messages are stored exactly as they travel (ROS 2 CDR), stamped with their arrival time.
"""

from __future__ import annotations

import logging
import math
import os
import queue
import shutil
import threading
import time
from collections.abc import Iterable, Iterator, Sequence
from pathlib import Path
from typing import Any

import yaml

from tf.messages import JointState, TFMessage
from tf.transport import Transport
from tf.transport import _cdr as cdr
from tf.transport._keys import type_info
from tf.transport._warn import RateLimitedWarning
from urdftk._atomic import write_atomic

__all__ = ["DEFAULT_TOPICS", "Recorder", "bag_info", "export_csv", "play", "read_messages"]

DEFAULT_TOPICS = ("/tf", "/tf_static", "/joint_states")
_log = logging.getLogger("urdftk.recording")


def _msg_type(topic: str) -> type:
    name = "/" + topic.strip("/")
    if name.endswith(("/tf", "/tf_static")):
        return TFMessage
    if name.endswith("/joint_states"):
        return JointState
    raise ValueError(f"{topic}: only /tf, /tf_static and /joint_states (or namespaced ones) can be recorded")


def _typestore() -> Any:
    from rosbags.typesys import Stores, get_typestore

    return get_typestore(Stores.ROS2_JAZZY)


def _qos(latched: bool) -> list[Any]:
    from rosbags.interfaces import Qos, QosDurability, QosHistory, QosLiveliness, QosReliability, QosTime

    never = QosTime(sec=0x7FFFFFFF, nsec=0xFFFFFFFF)
    return [
        Qos(
            history=QosHistory.KEEP_LAST,
            depth=1 if latched else 100,
            reliability=QosReliability.RELIABLE,
            durability=QosDurability.TRANSIENT_LOCAL if latched else QosDurability.VOLATILE,
            deadline=never,
            lifespan=never,
            liveliness=QosLiveliness.AUTOMATIC,
            liveliness_lease_duration=never,
            avoid_ros_namespace_conventions=False,
        )
    ]


class Recorder:
    """Records topics from a transport into a rosbag2 (MCAP) folder.

    Args:
        path: The bag folder to create (must not exist, or be an empty folder).
        transport: A Zenoh transport (``subscribe_raw`` keeps the payloads byte for byte).
        topics: Topics to record.
        flush_interval: Seconds between two complete MCAP files (what a crash can lose).

    Raises:
        FileExistsError: ``path`` exists and is not an empty folder.
        ValueError: A topic cannot be recorded.
    """

    def __init__(
        self,
        path: str | os.PathLike[str],
        transport: Any,
        topics: Sequence[str] = DEFAULT_TOPICS,
        *,
        flush_interval: float = 1.0,
    ) -> None:
        self.path = Path(path)
        if self.path.exists() and (not self.path.is_dir() or any(self.path.iterdir())):
            raise FileExistsError(f"{self.path} exists already; choose a new output folder")
        if not flush_interval > 0:
            raise ValueError(f"flush_interval must be > 0 s, got {flush_interval}")
        self.topics = tuple(dict.fromkeys(topics))
        self.types = {topic: _msg_type(topic) for topic in self.topics}
        self.flush_interval = float(flush_interval)
        self.count = 0
        self._segments: list[dict[str, Any]] = []
        self._store = _typestore()
        self._inbox: queue.SimpleQueue[tuple[str, int, bytes] | None] = queue.SimpleQueue()
        self._stopped = threading.Event()
        self.path.mkdir(parents=True, exist_ok=True)
        self._subs = [
            transport.subscribe_raw(topic, self.types[topic], self._receiver(topic)) for topic in self.topics
        ]

    def _receiver(self, topic: str) -> Any:
        put = self._inbox.put

        def on_payload(payload: bytes, info: Any) -> None:
            put((topic, info.received_ns, payload))

        return on_payload

    def stop(self) -> None:
        """Make :meth:`run` write what it has and return (thread-safe)."""
        self._stopped.set()
        self._inbox.put(None)

    def run(self) -> int:
        """Record until :meth:`stop` or Ctrl-C, closing a file every ``flush_interval``; returns the count."""
        try:
            while not self._stopped.is_set():
                self._segment()
        finally:
            for sub in self._subs:
                sub.close()
            self._drain_into_last_segment()
            if not self._segments:
                self._write_segment([])
        return self.count

    def _segment(self) -> None:
        deadline = time.monotonic() + self.flush_interval
        items: list[tuple[str, int, bytes]] = []
        while True:
            remaining = deadline - time.monotonic()
            if remaining <= 0:
                break
            try:
                item = self._inbox.get(timeout=remaining)
            except queue.Empty:
                break
            if item is None:
                break
            items.append(item)
        if items:
            self._write_segment(items)

    def _drain_into_last_segment(self) -> None:
        items = []
        while True:
            try:
                item = self._inbox.get_nowait()
            except queue.Empty:
                break
            if item is not None:
                items.append(item)
        if items:
            self._write_segment(items)

    def _write_segment(self, items: list[tuple[str, int, bytes]]) -> None:
        from rosbags.rosbag2 import StoragePlugin, Writer

        index = len(self._segments)
        staging = self.path / f".segment_{index}"
        if staging.exists():
            shutil.rmtree(staging)
        writer = Writer(staging, version=9, storage_plugin=StoragePlugin.MCAP)
        writer.open()
        connections = {
            topic: writer.add_connection(
                topic,
                type_info(self.types[topic]).ros_name,
                typestore=self._store,
                offered_qos_profiles=_qos(topic.endswith("tf_static")),
            )
            for topic in self.topics
        }
        for topic, stamp_ns, payload in sorted(items, key=lambda item: item[1]):
            writer.write(connections[topic], stamp_ns, payload)
        writer.close()
        name = f"{self.path.name}_{index}.mcap"
        os.replace(staging / f"{staging.name}.mcap", self.path / name)
        meta = yaml.safe_load((staging / "metadata.yaml").read_text(encoding="utf-8"))[
            "rosbag2_bagfile_information"
        ]
        shutil.rmtree(staging)
        for entry in meta["files"]:
            entry["path"] = name
        self._segments.append(meta)
        self.count += len(items)
        write_atomic(self.path / "metadata.yaml", yaml.safe_dump(_merge(self._segments), sort_keys=False))


def _merge(segments: list[dict[str, Any]]) -> dict[str, Any]:
    """One rosbag2 metadata document for several MCAP files with the same topics."""
    first = segments[0]
    counted = [s for s in segments if s["message_count"]]
    start = min((s["starting_time"]["nanoseconds_since_epoch"] for s in counted), default=0)
    end = max(
        (s["starting_time"]["nanoseconds_since_epoch"] + s["duration"]["nanoseconds"] for s in counted),
        default=0,
    )
    topics = [dict(t) for t in first["topics_with_message_count"]]
    for t in topics:
        t["message_count"] = 0
    for s in segments:
        for total, t in zip(topics, s["topics_with_message_count"], strict=True):
            total["message_count"] += t["message_count"]
    files = [f for s in segments for f in s["files"]]
    info = dict(first)
    info.update(
        relative_file_paths=[f["path"] for f in files],
        files=files,
        starting_time={"nanoseconds_since_epoch": start},
        duration={"nanoseconds": max(0, end - start)},
        message_count=sum(s["message_count"] for s in segments),
        topics_with_message_count=topics,
        ros_distro="urdftk",
    )
    return {"rosbag2_bagfile_information": info}


def read_messages(
    path: str | os.PathLike[str], topics: Iterable[str] | None = None
) -> Iterator[tuple[str, int, bytes]]:
    """Yield ``(topic, log_time_ns, cdr_bytes)`` of a bag in time order (AnyReader).

    Raises:
        OSError: The bag cannot be opened.
    """
    from rosbags.highlevel import AnyReader
    from rosbags.rosbag2.errors import ReaderError

    wanted = None if topics is None else set(topics)
    try:
        with AnyReader([Path(path)], default_typestore=_typestore()) as reader:
            conns = [c for c in reader.connections if wanted is None or c.topic in wanted]
            for conn, stamp, raw in reader.messages(connections=conns):
                yield conn.topic, stamp, bytes(raw)
    except (ReaderError, FileNotFoundError) as exc:
        raise OSError(f"{path}: cannot read the bag: {exc}") from None


def play(
    path: str | os.PathLike[str],
    transport: Transport,
    *,
    rate: float = 1.0,
    loop: bool = False,
    topics: Iterable[str] | None = None,
    stop: threading.Event | None = None,
    wait_for_subscribers: float = 1.0,
) -> int:
    """Republish a bag with its original timing (scaled by ``rate``); returns messages sent.

    Args:
        path: The bag folder.
        transport: Where to publish.
        rate: Playback speed factor (2.0 = twice as fast).
        loop: Start again at the end, until ``stop``.
        topics: Only these topics (default: every /tf, /tf_static, /joint_states topic).
        stop: Set it to stop early.
        wait_for_subscribers: Seconds to wait, per topic, for a subscriber before starting.
    """
    if not rate > 0 or not math.isfinite(rate):
        raise ValueError(f"rate must be a positive number, got {rate}")
    stop = stop or threading.Event()
    warn = RateLimitedWarning(_log)
    messages = list(read_messages(path, topics))
    pubs: dict[str, Any] = {}
    for topic in dict.fromkeys(t for t, _, _ in messages):
        try:
            msg_type = _msg_type(topic)
        except ValueError:
            warn.warn(f"skip:{topic}", "play: skipping topic %s (not a tf or joint-state topic)", topic)
            continue
        pubs[topic] = transport.publisher(topic, msg_type, latched=topic.endswith("tf_static"))
    for pub in pubs.values():
        waiter = getattr(pub, "wait_for_subscribers", None)
        if waiter is not None:
            waiter(wait_for_subscribers)
    sent = 0
    try:
        while True:
            start = time.monotonic()
            t0 = messages[0][1] if messages else 0
            for topic, stamp, payload in messages:
                pub = pubs.get(topic)
                if pub is None:
                    continue
                if stop.wait(max(0.0, start + (stamp - t0) / 1e9 / rate - time.monotonic())):
                    return sent
                try:
                    msg = cdr.decode(pub.msg_type, payload)
                except cdr.CdrError as exc:
                    warn.warn(f"bad:{topic}", "play: skipping a bad message on %s: %s", topic, exc)
                    continue
                publish_cdr = getattr(pub, "publish_cdr", None)
                if publish_cdr is not None:
                    publish_cdr(payload)
                else:
                    pub.publish(msg)
                sent += 1
            if not loop or stop.is_set() or not messages:
                return sent
    finally:
        for pub in pubs.values():
            pub.close()


def bag_info(path: str | os.PathLike[str]) -> str:
    """A ``ros2 bag info``-style summary of a bag.

    Raises:
        OSError: The bag cannot be opened.
    """
    from rosbags.rosbag2 import Reader
    from rosbags.rosbag2.errors import ReaderError

    bag = Path(path)
    try:
        with Reader(bag) as reader:
            meta = yaml.safe_load((bag / "metadata.yaml").read_text(encoding="utf-8"))
            files = meta["rosbag2_bagfile_information"].get("relative_file_paths", [])
            size = sum(p.stat().st_size for p in bag.iterdir() if p.is_file())
            count = reader.message_count
            start, end = (reader.start_time, reader.end_time) if count else (0, 0)
            lines = [
                f"Files:             {', '.join(files)}",
                f"Bag size:          {size / 1024:.1f} KiB",
                "Storage id:        mcap",
                f"Duration:          {(end - start) / 1e9:.9f}s",
                f"Start:             {start / 1e9:.9f}",
                f"End:               {end / 1e9:.9f}",
                f"Messages:          {count}",
                "Topic information:",
            ]
            for conn in reader.connections:
                lines.append(
                    f"  Topic: {conn.topic} | Type: {conn.msgtype} | Count: {conn.msgcount} | "
                    "Serialization Format: cdr"
                )
    except (ReaderError, FileNotFoundError) as exc:
        raise OSError(f"{bag}: cannot read the bag: {exc}") from None
    return "\n".join(lines)


def _flatten(prefix: str, value: Any, out: dict[str, Any]) -> None:
    import dataclasses

    from tf.messages import Duration, Time

    if isinstance(value, (Time, Duration)):
        out[prefix] = value.nanoseconds
    elif dataclasses.is_dataclass(value):
        for f in dataclasses.fields(value):
            _flatten(f"{prefix}.{f.name}", getattr(value, f.name), out)
    elif isinstance(value, tuple):
        for i, item in enumerate(value):
            _flatten(f"{prefix}{i}", item, out)
    else:
        out[prefix] = value


def export_csv(path: str | os.PathLike[str], topic: str, output: str | os.PathLike[str]) -> int:
    """Write one topic of a bag as CSV, like ``rostopic echo -b BAG -p TOPIC``; returns the row count.

    Columns: ``%time`` (log time, ns) then ``field.…`` for every leaf (stamps in ns, arrays
    flattened with an index: ``field.transforms0.child_frame_id``).

    Raises:
        OSError: The bag cannot be read.
        ValueError: The topic is not in the bag or cannot be decoded.
    """
    import csv
    import io

    msg_type = _msg_type(topic)
    rows: list[dict[str, Any]] = []
    columns: dict[str, None] = {"%time": None}
    for _, stamp, payload in read_messages(path, [topic]):
        row: dict[str, Any] = {"%time": stamp}
        _flatten("field", cdr.decode(msg_type, payload), row)
        columns.update(dict.fromkeys(row))
        rows.append(row)
    if not rows:
        raise ValueError(f"{path}: no messages on {topic}")
    text = io.StringIO()
    writer = csv.DictWriter(text, fieldnames=list(columns), lineterminator="\n")
    writer.writeheader()
    for row in rows:
        writer.writerow({k: (repr(v) if isinstance(v, float) else v) for k, v in row.items()})
    write_atomic(output, text.getvalue())
    return len(rows)
