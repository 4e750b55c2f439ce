"""The Zenoh transport between real processes on 127.0.0.1 (no mocks).

Each test uses its own ROS domain id, so tests running at the same time never see each other.
"""

from __future__ import annotations

import json
import logging
import os
import subprocess
import sys
import threading
import time

import pytest
from helpers.procs import CHILD, Child, child_env, free_port, unique_domain, urdftk_cmd

import tf
from tf.messages import Header, TFMessage, Time, Transform, TransformStamped, Vector3
from tf.transport.zenoh import MessageInfo, ZenohTransport

pytestmark = pytest.mark.timeout(120)
CLEAN_ENV = {k: v for k, v in os.environ.items() if not k.startswith("URDFTK_ZENOH")}


def _child(role: str, domain: int, *args: str, extra: dict[str, str] | None = None) -> Child:
    return Child([sys.executable, CHILD, role, *args], child_env(domain, extra))


def test_broadcaster_to_listener_lookup_zero_config() -> None:
    domain = unique_domain()
    with (
        _child("broadcast", domain, "--rate", "50", "--frames", "3") as pub,
        ZenohTransport(domain_id=domain, environ=CLEAN_ENV) as bus,
    ):
        buffer = tf.Buffer()
        tf.TransformListener(buffer, bus)
        pub.expect("ready", 30)
        t = buffer.lookup_transform("world", "f2", Time(), timeout=15.0)
        assert t.header.frame_id == "world" and t.child_frame_id == "f2"
        # world->f0->f1->f2: x translations 1, 2, 3 composed through small rotations about z.
        assert 5.0 < t.transform.translation.x < 6.01
        assert abs(t.transform.translation.z - 1.5) < 1e-9
        latest = buffer.get_latest_common_time("world", "f2")
        assert abs(latest.to_sec() - time.time()) < 5.0


def test_other_domain_sees_nothing() -> None:
    domain = unique_domain()
    got: list[TFMessage] = []
    with (
        _child("broadcast", domain, "--rate", "100") as pub,
        ZenohTransport(domain_id=domain + 1, environ=CLEAN_ENV) as other,
        ZenohTransport(domain_id=domain, environ=CLEAN_ENV) as same,
    ):
        seen = threading.Event()
        other.subscribe("/tf", TFMessage, got.append)
        same.subscribe("/tf", TFMessage, lambda _m: seen.set())
        pub.expect("ready", 30)
        assert seen.wait(15), pub.describe()
        time.sleep(0.3)
    assert got == []


def test_late_static_subscriber_gets_every_static() -> None:
    domain = unique_domain()
    with _child("static", domain, "--frames", "4") as pub:
        pub.expect("sent", 30)
        time.sleep(5.0)  # the listener starts 5 s after the static broadcaster
        with ZenohTransport(domain_id=domain, environ=CLEAN_ENV) as bus:
            buffer = tf.Buffer()
            tf.TransformListener(buffer, bus, static_only=True)
            t = buffer.lookup_transform("world", "s3", Time(), timeout=10.0)
            assert t.transform.translation.x == pytest.approx(1.0 + 2.0 + 3.0 + 4.0)
            assert sorted(buffer.frames()) == ["s0", "s1", "s2", "s3", "world"]


def test_garbage_on_tf_key_is_dropped_with_warning(caplog: pytest.LogCaptureFixture) -> None:
    domain = unique_domain()
    got: list[TFMessage] = []
    done = threading.Event()

    def on_tf(msg: TFMessage) -> None:
        got.append(msg)
        done.set()

    with (
        caplog.at_level(logging.WARNING, logger="tf.transport"),
        ZenohTransport(domain_id=domain, environ=CLEAN_ENV) as bus,
    ):
        bus.subscribe("/tf", TFMessage, on_tf)
        with _child("garbage", domain) as pub:
            pub.expect("sent", 30)
            assert done.wait(15), pub.describe()
    assert len(got) == 1 and got[0].transforms[0].header.stamp == Time(7, 0)
    drops = [r for r in caplog.records if "dropped a bad payload" in r.getMessage()]
    assert 1 <= len(drops) <= 2  # rate-limited: five bad payloads, at most one line per 5 s (+1 summary)


def test_reliability_1khz_30_transforms_no_loss() -> None:
    seconds = float(os.environ.get("URDFTK_RELIABILITY_SECONDS", "10"))
    count = int(1000 * seconds)
    domain = unique_domain()
    sequences: list[int] = []
    gids: set[bytes] = set()
    sizes: set[int] = set()
    finished = threading.Event()

    def on_tf(msg: TFMessage, info: MessageInfo) -> None:
        assert info.attachment is not None
        sequences.append(info.attachment.sequence_number)
        gids.add(info.attachment.gid)
        sizes.add(len(msg.transforms))
        if len(sequences) >= count:
            finished.set()

    with ZenohTransport(domain_id=domain, environ=CLEAN_ENV) as bus:
        bus.subscribe_info("/tf", TFMessage, on_tf)
        with _child("flood", domain, "--rate", "1000", "--frames", "30", "--count", str(count)) as pub:
            pub.expect("ready", 30)
            done = pub.expect(r"done (\d+)", seconds * 3 + 30)
            assert int(done.group(1)) == count
            finished.wait(10)
    assert sizes == {30}
    assert len(gids) == 1
    assert len(sequences) == count, f"lost {count - len(sequences)} of {count}"
    assert sequences == list(range(1, count + 1))  # in order, none lost, none duplicated


def test_kill_and_restart_publisher_resumes_within_2s() -> None:
    domain = unique_domain()
    arrivals: list[tuple[float, bytes]] = []
    cond = threading.Condition()

    def on_tf(_msg: TFMessage, info: MessageInfo) -> None:
        with cond:
            assert info.attachment is not None
            arrivals.append((time.monotonic(), info.attachment.gid))
            cond.notify_all()

    with ZenohTransport(domain_id=domain, environ=CLEAN_ENV) as bus:
        buffer = tf.Buffer()
        tf.TransformListener(buffer, bus)
        bus.subscribe_info("/tf", TFMessage, on_tf)
        first = _child("broadcast", domain, "--rate", "100")
        try:
            first.expect("ready", 30)
            with cond:
                assert cond.wait_for(lambda: len(arrivals) > 10, 15), first.describe()
        finally:
            first.kill()
        killed_at = time.monotonic()
        with cond:
            before = len(arrivals)
        second = _child("broadcast", domain, "--rate", "100")
        try:
            second.expect("ready", 30)
            ready_at = time.monotonic()
            with cond:
                resumed = cond.wait_for(lambda: len(arrivals) > before and arrivals[-1][0] > killed_at, 10)
            assert resumed, second.describe()
            with cond:
                first_new = next(t for t, _ in arrivals[before:])
            assert first_new - ready_at < 2.0, (
                f"resumed {first_new - ready_at:.2f}s after the new publisher was ready"
            )
            assert len({gid for _, gid in arrivals}) == 2  # a new publisher, same listener
            t = buffer.lookup_transform("world", "f2", Time(), timeout=5.0)
            assert abs(t.header.stamp.to_sec() - time.time()) < 5.0
        finally:
            second.kill()


def test_explicit_endpoints_via_router_without_multicast(tmp_path) -> None:
    """``urdftk router`` + URDFTK_ZENOH_CONFIG (multicast off) + URDFTK_ZENOH_CONNECT."""
    domain = unique_domain()
    port = free_port()
    config = tmp_path / "no_multicast.json5"
    config.write_text(
        json.dumps(
            {
                "mode": "peer",
                "listen": {"endpoints": ["tcp/127.0.0.1:0"]},
                "scouting": {"multicast": {"enabled": False}, "gossip": {"enabled": True}},
            }
        )
    )
    extra = {"URDFTK_ZENOH_CONFIG": str(config), "URDFTK_ZENOH_CONNECT": f"tcp/127.0.0.1:{port}"}
    router = Child(
        urdftk_cmd("router", "--listen", f"tcp/127.0.0.1:{port}", "--no-multicast"), child_env(domain)
    )
    try:
        router.expect("listening", 30)
        with _child("broadcast", domain, extra=extra) as pub, _child("listen", domain, extra=extra) as sub:
            pub.expect("ready", 30)
            pose = sub.expect(r"pose (\S+) (\S+) (\S+)", 30)
            assert 5.0 < float(pose.group(1)) < 6.01
    finally:
        router.interrupt()
        try:
            router.wait(10)
        finally:
            router.kill()


def test_publishing_checks_type_and_closed_transport_is_inert() -> None:
    domain = unique_domain()
    bus = ZenohTransport(domain_id=domain, environ=CLEAN_ENV)
    pub = bus.publisher("/tf", TFMessage)
    with pytest.raises(TypeError):
        pub.publish(TransformStamped())  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="supported"):
        bus.publisher("/tf", Header)
    tokens = {(t.kind, t.topic) for t in bus.graph(timeout=1.0) if t.zid == bus.zid}
    assert ("MP", "/tf") in tokens and ("NN", "") in tokens
    bus.close()
    pub.publish(TFMessage([TransformStamped(Header(Time(1, 0), "a"), "b", Transform(Vector3()))]))  # no-op
    bus.close()
    with pytest.raises(ValueError, match="closed"):
        bus.subscribe("/tf", TFMessage, print)
    with pytest.raises(ValueError, match="ROS_DOMAIN_ID"):
        ZenohTransport(environ={"ROS_DOMAIN_ID": "abc"})


def test_process_that_never_closes_its_transport_exits_promptly() -> None:
    """No Zenoh callback may run on a non-daemon thread: Python joins those before atexit runs."""
    code = (
        "import sys\n"
        "from tf.messages import TFMessage\n"
        "from tf.transport.zenoh import ZenohTransport\n"
        f"bus = ZenohTransport(domain_id={unique_domain()}, environ={{}})\n"
        "pub = bus.publisher('/tf', TFMessage)\n"
        "sub = bus.subscribe('/tf', TFMessage, print)\n"
        "print('matched', pub.wait_for_subscribers(10), flush=True)\n"
        "pub.publish(TFMessage(()))\n"
    )
    start = time.monotonic()
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60)
    assert done.returncode == 0, done.stderr[-2000:]
    assert "matched True" in done.stdout
    assert time.monotonic() - start < 30
