"""urdftk record / play / bag info / bag export against rosbags' AnyReader (real processes, real Zenoh)."""

from __future__ import annotations

import csv
import sys
import time
from pathlib import Path

import pytest
from helpers.procs import CHILD, Child, child_env, unique_domain, urdftk_cmd
from rosbags.highlevel import AnyReader
from rosbags.typesys import Stores, get_typestore

from tf.messages import TFMessage
from tf.transport import _cdr
from urdftk.recording import read_messages

pytestmark = pytest.mark.timeout(180)
STORE = get_typestore(Stores.ROS2_JAZZY)


def _anyreader(bag: Path) -> list[tuple[str, int, object, bytes]]:
    with AnyReader([bag], default_typestore=STORE) as reader:
        return [
            (c.topic, t, reader.deserialize(raw, c.msgtype), bytes(raw)) for c, t, raw in reader.messages()
        ]


def _stamps(msgs: list[TFMessage]) -> list[tuple[int, int]]:
    return [(m.transforms[0].header.stamp.sec, m.transforms[0].header.stamp.nanosec) for m in msgs]


def test_record_play_roundtrip_info_export(tmp_path: Path) -> None:
    domain = unique_domain()
    env = child_env(domain)
    run1, run2 = tmp_path / "run1", tmp_path / "run2"
    with Child([sys.executable, CHILD, "broadcast", "--rate", "50", "--frames", "3"], env) as pub:
        pub.expect("ready", 30)
        rec = Child(urdftk_cmd("record", "-o", str(run1), "--flush-interval", "0.5"), env)
        try:
            rec.expect("recording", 30)
            pub.expect("first sent", 30)
            time.sleep(2.0)
            rec.interrupt()
            assert rec.wait(30) == 0, rec.describe()
        finally:
            rec.kill()
    recorded = _anyreader(run1)
    assert len(recorded) > 40
    ours = [_cdr.decode(TFMessage, raw) for _, _, _, raw in recorded]
    for (_, _, ros, _), mine in zip(recorded, ours, strict=True):  # AnyReader gives identical messages
        assert len(ros.transforms) == len(mine.transforms) == 3
        for a, b in zip(ros.transforms, mine.transforms, strict=True):
            assert (a.header.stamp.sec, a.header.stamp.nanosec) == (
                b.header.stamp.sec,
                b.header.stamp.nanosec,
            )
            assert (a.header.frame_id, a.child_frame_id) == (b.header.frame_id, b.child_frame_id)
            v, w = a.transform.translation, b.transform.translation
            assert (v.x, v.y, v.z) == (w.x, w.y, w.z)
            q, r = a.transform.rotation, b.transform.rotation
            assert (q.x, q.y, q.z, q.w) == (r.x, r.y, r.z, r.w)
    assert [t for _, t, _, _ in recorded] == sorted(t for _, t, _, _ in recorded)

    # play it back (twice as fast) while a second recorder listens
    rec2 = Child(urdftk_cmd("record", "-o", str(run2), "--flush-interval", "0.5"), env)
    try:
        rec2.expect("recording", 30)
        player = Child(urdftk_cmd("play", str(run1), "--rate", "2.0", "--wait", "5"), env)
        try:
            played = player.expect(r"played (\d+) messages", 60)
            assert int(played.group(1)) == len(recorded)
        finally:
            player.kill()
        time.sleep(1.0)  # let the last messages reach the recorder
        rec2.interrupt()
        assert rec2.wait(30) == 0, rec2.describe()
    finally:
        rec2.kill()
    replayed = [_cdr.decode(TFMessage, raw) for _, _, _, raw in _anyreader(run2)]
    assert len(replayed) == len(ours)
    assert _stamps(replayed) == _stamps(ours)  # same stamps, same order, none lost
    t1 = [t for _, t, _, _ in recorded]
    t2 = [t for _, t, _, _ in _anyreader(run2)]
    span1, span2 = (t1[-1] - t1[0]) / 1e9, (t2[-1] - t2[0]) / 1e9
    assert span2 == pytest.approx(span1 / 2.0, rel=0.25, abs=0.1)  # original timing, scaled by --rate

    info = Child(urdftk_cmd("bag", "info", str(run1)), env)
    assert info.wait(60) == 0
    text = "".join(info.stdout)
    assert f"Messages:          {len(recorded)}" in text
    assert f"Topic: /tf | Type: tf2_msgs/msg/TFMessage | Count: {len(recorded)}" in text

    out = tmp_path / "tf.csv"
    export = Child(urdftk_cmd("bag", "export", str(run1), "/tf", "-o", str(out)), env)
    assert export.wait(60) == 0, export.describe()
    with out.open() as fh:
        rows = list(csv.DictReader(fh))
    assert len(rows) == len(recorded)
    for row, (_, t, _, _), msg in zip(rows, recorded, ours, strict=True):
        assert int(row["%time"]) == t
        tr = msg.transforms[2]
        assert int(row["field.transforms2.header.stamp"]) == tr.header.stamp.nanoseconds
        assert row["field.transforms2.child_frame_id"] == tr.child_frame_id
        assert float(row["field.transforms2.transform.rotation.z"]) == tr.transform.rotation.z


def test_killed_recorder_leaves_a_readable_bag(tmp_path: Path) -> None:
    domain = unique_domain()
    env = child_env(domain)
    bag = tmp_path / "killed"
    with Child([sys.executable, CHILD, "broadcast", "--rate", "100"], env) as pub:
        pub.expect("ready", 30)
        rec = Child(urdftk_cmd("record", "-o", str(bag), "--flush-interval", "0.3"), env)
        try:
            rec.expect("recording", 30)
            pub.expect("first sent", 30)
            time.sleep(1.5)
        finally:
            rec.kill()  # SIGKILL: no chance to close anything
    messages = list(read_messages(bag))
    assert len(messages) >= 30  # everything up to the last flush (>= ~1.2 s at 100 Hz)
    recorded = _anyreader(bag)
    assert len(recorded) == len(messages)
    for _, _, ros, raw in recorded:
        assert len(_cdr.decode(TFMessage, raw).transforms) == len(ros.transforms) == 3


def test_bag_cli_errors_are_one_line(tmp_path: Path) -> None:
    env = child_env(unique_domain())
    missing = Child(urdftk_cmd("bag", "info", str(tmp_path / "nope")), env)
    assert missing.wait(60) == 2
    assert "".join(missing.stderr).count("\n") == 1
    (tmp_path / "exists").mkdir()
    (tmp_path / "exists" / "f").write_text("x")
    taken = Child(urdftk_cmd("record", "-o", str(tmp_path / "exists")), env)
    assert taken.wait(60) == 2 and "exists" in "".join(taken.stderr)
