"""CDR codec and rmw_zenoh naming, checked against rosbags (the oracle) field by field."""

from __future__ import annotations

import dataclasses
import math
import random
import struct

import numpy as np
import pytest
from rosbags.typesys import Stores, get_typestore

from tf.messages import Header, JointState, Quaternion, TFMessage, Time, Transform, TransformStamped, Vector3
from tf.transport import _cdr, _keys

STORE = get_typestore(Stores.ROS2_JAZZY)
T = STORE.types
TF_TYPE = "tf2_msgs/msg/TFMessage"
JS_TYPE = "sensor_msgs/msg/JointState"
NAMES = [
    "",
    "a",
    "ab",
    "abc",
    "abcd",
    "base_link",
    "wrist_3_link",
    "ünïcödé_λ",
    "日本語",
    "emoji_🤖",
    "x" * 61,
]
EDGE_FLOATS = [0.0, -0.0, 1.0, -1.5, 1e-300, -1e300, 5e-324, math.pi, math.inf, -math.inf]


def _ros_time(t: Time):
    return T["builtin_interfaces/msg/Time"](sec=t.sec, nanosec=t.nanosec)


def _ros_header(h: Header):
    return T["std_msgs/msg/Header"](stamp=_ros_time(h.stamp), frame_id=h.frame_id)


def _ros_tf(msg: TFMessage):
    items = []
    for t in msg.transforms:
        v, q = t.transform.translation, t.transform.rotation
        items.append(
            T["geometry_msgs/msg/TransformStamped"](
                header=_ros_header(t.header),
                child_frame_id=t.child_frame_id,
                transform=T["geometry_msgs/msg/Transform"](
                    translation=T["geometry_msgs/msg/Vector3"](x=v.x, y=v.y, z=v.z),
                    rotation=T["geometry_msgs/msg/Quaternion"](x=q.x, y=q.y, z=q.z, w=q.w),
                ),
            )
        )
    return T[TF_TYPE](transforms=items)


def _ros_js(msg: JointState):
    return T[JS_TYPE](
        header=_ros_header(msg.header),
        name=list(msg.name),
        position=np.array(msg.position, dtype=np.float64),
        velocity=np.array(msg.velocity, dtype=np.float64),
        effort=np.array(msg.effort, dtype=np.float64),
    )


def _same_float(a: float, b: float) -> bool:
    return struct.pack("<d", a) == struct.pack("<d", b)


def _check_tf_fields(ours: TFMessage, ros) -> None:
    assert len(ours.transforms) == len(ros.transforms)
    for a, b in zip(ours.transforms, ros.transforms, strict=True):
        assert (a.header.stamp.sec, a.header.stamp.nanosec) == (b.header.stamp.sec, b.header.stamp.nanosec)
        assert a.header.frame_id == b.header.frame_id
        assert a.child_frame_id == b.child_frame_id
        va, vb = a.transform.translation, b.transform.translation
        qa, qb = a.transform.rotation, b.transform.rotation
        for x, y in [
            (va.x, vb.x),
            (va.y, vb.y),
            (va.z, vb.z),
            (qa.x, qb.x),
            (qa.y, qb.y),
            (qa.z, qb.z),
            (qa.w, qb.w),
        ]:
            assert _same_float(x, y), (x, y)


def _check_js_fields(ours: JointState, ros) -> None:
    assert (ours.header.stamp.sec, ours.header.stamp.nanosec) == (
        ros.header.stamp.sec,
        ros.header.stamp.nanosec,
    )
    assert ours.header.frame_id == ros.header.frame_id
    assert list(ours.name) == list(ros.name)
    for field in ("position", "velocity", "effort"):
        a, b = getattr(ours, field), getattr(ros, field)
        assert len(a) == len(b)
        assert all(_same_float(x, float(y)) for x, y in zip(a, b, strict=True))


def _rand_float(rng: random.Random) -> float:
    if rng.random() < 0.2:
        return rng.choice(EDGE_FLOATS)
    return rng.uniform(-1e3, 1e3)


def _rand_time(rng: random.Random) -> Time:
    return Time(rng.choice([0, 1, rng.randrange(2**31)]), rng.choice([0, 999_999_999, rng.randrange(10**9)]))


def _rand_tf(rng: random.Random) -> TFMessage:
    out = []
    for _ in range(rng.choice([0, 1, 2, rng.randrange(60)])):
        out.append(
            TransformStamped(
                Header(_rand_time(rng), rng.choice(NAMES)),
                rng.choice(NAMES),
                Transform(
                    Vector3(*(_rand_float(rng) for _ in range(3))),
                    Quaternion(*(_rand_float(rng) for _ in range(4))),
                ),
            )
        )
    return TFMessage(out)


def _rand_js(rng: random.Random) -> JointState:
    n = rng.choice([0, 1, rng.randrange(20)])

    def arr() -> list[float]:
        return [_rand_float(rng) for _ in range(rng.choice([0, n, rng.randrange(5)]))]

    return JointState(
        Header(_rand_time(rng), rng.choice(NAMES)), [rng.choice(NAMES) for _ in range(n)], arr(), arr(), arr()
    )


@pytest.mark.parametrize("seed", range(4))
def test_tf_message_bytes_match_rosbags(seed: int) -> None:
    rng = random.Random(seed)
    for _ in range(150):
        msg = _rand_tf(rng)
        ours = _cdr.encode(msg)
        assert ours == STORE.serialize_cdr(_ros_tf(msg), TF_TYPE)
        _check_tf_fields(msg, STORE.deserialize_cdr(ours, TF_TYPE))
        back = _cdr.decode(TFMessage, ours)
        _check_tf_fields(back, STORE.deserialize_cdr(ours, TF_TYPE))
        assert _cdr.encode(back) == ours
        back_again = _cdr.decode(TFMessage, ours)  # second decode takes the cached-layout path
        assert _cdr.encode(back_again) == ours


@pytest.mark.parametrize("seed", range(4))
def test_joint_state_bytes_match_rosbags(seed: int) -> None:
    rng = random.Random(100 + seed)
    for _ in range(150):
        msg = _rand_js(rng)
        ours = _cdr.encode(msg)
        assert ours == STORE.serialize_cdr(_ros_js(msg), JS_TYPE)
        _check_js_fields(msg, STORE.deserialize_cdr(ours, JS_TYPE))
        back = _cdr.decode(JointState, ours)
        _check_js_fields(back, STORE.deserialize_cdr(ours, JS_TYPE))
        assert _cdr.encode(back) == ours


def test_edge_cases_empty_unicode_and_extremes() -> None:
    cases_tf = [
        TFMessage(),
        TFMessage([TransformStamped()]),  # empty names, zero time, identity
        TFMessage([TransformStamped(Header(Time(2**31 - 1, 999_999_999), "wörld"), "子", Transform())]),
    ]
    for msg in cases_tf:
        data = _cdr.encode(msg)
        assert data == STORE.serialize_cdr(_ros_tf(msg), TF_TYPE)
        assert _cdr.decode(TFMessage, data) == msg
    cases_js = [
        JointState(),
        JointState(Header(Time(0, 1), ""), ["é"], [], [], []),
        JointState(Header(Time(3, 0), "f"), ["a", "b"], [1.0, 2.0], [], [3.0, 4.0]),
    ]
    for msg in cases_js:
        data = _cdr.encode(msg)
        assert data == STORE.serialize_cdr(_ros_js(msg), JS_TYPE)
        assert _cdr.decode(JointState, data) == msg
    nan = JointState(Header(), ["j"], [math.nan])
    data = _cdr.encode(nan)
    assert data == STORE.serialize_cdr(_ros_js(nan), JS_TYPE)
    assert math.isnan(_cdr.decode(JointState, data).position[0])


def test_negative_time_from_rosbags_is_rejected_not_crashing() -> None:
    # builtin_interfaces/Time.sec is int32 and may be negative in ROS; tf.Time cannot be.
    ros = _ros_tf(TFMessage([TransformStamped(Header(Time(1, 0), "a"), "b", Transform())]))
    ros.transforms[0].header.stamp.sec = -5
    data = STORE.serialize_cdr(ros, TF_TYPE)
    with pytest.raises(_cdr.CdrError, match="stamp"):
        _cdr.decode(TFMessage, data)
    js = _ros_js(JointState(Header(Time(1, 0), "a")))
    js.header.stamp.sec = -1
    with pytest.raises(_cdr.CdrError, match="stamp"):
        _cdr.decode(JointState, STORE.serialize_cdr(js, JS_TYPE))
    with pytest.raises(_cdr.CdrError):
        _cdr.encode(TFMessage([TransformStamped(Header(Time(2**31, 0), "a"), "b")]))


def test_garbage_is_a_cdr_error() -> None:
    rng = random.Random(7)
    good_tf = _cdr.encode(_rand_tf(random.Random(1)))
    good_js = _cdr.encode(_rand_js(random.Random(2)))
    invalid = [
        b"",
        b"\x00",
        b"\x00\x01\x00\x00",
        b"\x01\x00\x00\x00" + good_tf[4:],
        b"\x00\x01\x00\x00\xff\xff\xff\xff",
    ]
    invalid += [good_tf[:n] for n in range(4, len(good_tf), 13)] + [good_tf + b"junk!!!!!"]
    for payload in invalid:
        with pytest.raises(_cdr.CdrError):
            _cdr.decode(TFMessage, payload)
    for payload in [good_js[:n] for n in range(4, len(good_js), 7)] + [good_js + b"\x01"]:
        with pytest.raises(_cdr.CdrError):
            _cdr.decode(JointState, payload)
    # Random bytes: a CdrError or (rarely) a well-formed message, never any other exception.
    decoded = 0
    for _ in range(500):
        payload = bytes(rng.randrange(256) for _ in range(rng.randrange(1, 400)))
        for msg_type in (TFMessage, JointState):
            try:
                msg = _cdr.decode(msg_type, payload)
            except _cdr.CdrError:
                continue
            assert isinstance(msg, msg_type)
            decoded += 1
    assert decoded < 5
    bad_utf8 = bytearray(_cdr.encode(JointState(Header(Time(1, 0), "ab"))))
    bad_utf8[16] = 0xFF
    with pytest.raises(_cdr.CdrError, match="UTF-8"):
        _cdr.decode(JointState, bytes(bad_utf8))


def test_type_hashes_are_the_ros2_ones() -> None:
    for msg_type, name in ((TFMessage, TF_TYPE), (JointState, JS_TYPE)):
        info = _keys.type_info(msg_type)
        assert info.ros_name == name
        assert info.type_hash == STORE.hash_rihs01(name)
        pkg, _, short = name.split("/")
        assert info.dds_name == f"{pkg}::msg::dds_::{short}_"
    with pytest.raises(ValueError, match="supported"):
        _keys.type_info(Header)


def test_keys_tokens_and_attachment() -> None:
    info = _keys.type_info(TFMessage)
    assert _keys.topic_key(0, "/tf", info) == f"0/tf/tf2_msgs::msg::dds_::TFMessage_/{info.type_hash}"
    assert _keys.topic_key(42, "/robot1/tf_static", info).startswith("42/robot1/tf_static/")
    for bad in ("", "/", "a//b", "tf*", "a b"):
        with pytest.raises(ValueError):
            _keys.topic_key(0, bad, info)
    assert _keys.qos_string(depth=100) == "::,100:,:,:,,"
    assert _keys.qos_string(depth=1, transient_local=True) == ":1:,1:,:,:,,"
    token = _keys.entity_token(3, "abc123", 0, 5, "MP", "rsp", "/tf", info, _keys.qos_string(depth=100))
    assert token == (
        f"@ros2_lv/3/abc123/0/5/MP/%/%/rsp/%tf/tf2_msgs::msg::dds_::TFMessage_/{info.type_hash}/::,100:,:,:,,"
    )
    parsed = _keys.parse_token(token)
    assert parsed is not None
    assert (parsed.domain_id, parsed.kind, parsed.node_name, parsed.topic) == (3, "MP", "rsp", "/tf")
    assert parsed.key == token and parsed.gid == _keys.gid_of(token) and len(parsed.gid) == 16
    node = _keys.parse_token(_keys.node_token(3, "abc123", 0, "rsp"))
    assert node is not None and node.kind == "NN" and node.key == _keys.node_token(3, "abc123", 0, "rsp")
    assert _keys.parse_token("@ros2_lv/x/y") is None and _keys.parse_token("0/tf/x/y") is None
    gid = bytes(range(16))
    raw = _keys.pack_attachment(12, 1_700_000_000_123_456_789, gid)
    assert len(raw) == 33 and raw[16] == 0x10 and raw[17:] == gid
    assert raw[:8] == (12).to_bytes(8, "little") and raw[8:16] == (1_700_000_000_123_456_789).to_bytes(
        8, "little"
    )
    att = _keys.unpack_attachment(raw)
    assert att == _keys.Attachment(12, 1_700_000_000_123_456_789, gid)
    assert _keys.unpack_attachment(raw[:-1]) is None and _keys.unpack_attachment(None) is None


def _assert_plain_instance(got: TransformStamped, want: TransformStamped) -> None:
    assert type(got) is TransformStamped and type(got.header) is Header and type(got.header.stamp) is Time
    assert type(got.transform) is Transform
    assert type(got.transform.translation) is Vector3 and type(got.transform.rotation) is Quaternion
    assert got == want and hash(got) == hash(want) and repr(got) == repr(want)
    with pytest.raises(dataclasses.FrozenInstanceError):
        got.transform.rotation.w = 0.5  # type: ignore[misc]
    assert dataclasses.replace(got, child_frame_id="other").transform is got.transform


def test_decoded_messages_are_ordinary_instances_and_check_agrees_with_decode() -> None:
    rng = random.Random(11)
    for _ in range(60):
        msg = _rand_tf(rng)
        data = _cdr.encode(msg)
        for _path in ("field by field", "cached layout"):
            back = _cdr.decode(TFMessage, data)
            assert type(back) is TFMessage and type(back.transforms) is tuple
            for got, want in zip(back.transforms, msg.transforms, strict=True):
                _assert_plain_instance(got, want)
            assert _cdr.check(TFMessage, data) is None
    # Payloads that decode rejects, also on the cached-layout path, are rejected by check too.
    msg = TFMessage([TransformStamped(Header(Time(5, 6), "a"), "b", Transform()) for _ in range(3)])
    data = _cdr.encode(msg)
    _cdr.decode(TFMessage, data)  # caches the layout
    negative = bytearray(data)
    negative[8:12] = struct.pack("<i", -3)
    big_ns = bytearray(data)
    big_ns[12:16] = struct.pack("<I", 1_000_000_000)
    renamed = data.replace(b"a\x00", b"c\x00")
    bad_pad = bytearray(data)
    bad_pad[8 + 8 + 4 + 2] = 7  # padding after "a\0": ignored by the field-by-field parser
    for payload in (bytes(negative), bytes(big_ns), renamed, bytes(bad_pad), data[:-8], data + b"\x01"):
        try:
            expected = _cdr.decode(TFMessage, payload)
        except _cdr.CdrError:
            with pytest.raises(_cdr.CdrError):
                _cdr.check(TFMessage, payload)
            with pytest.raises(_cdr.CdrError):
                _cdr.check(TFMessage, payload)  # and again once a layout may be cached
        else:
            assert _cdr.check(TFMessage, payload) is None
            assert _cdr.decode(TFMessage, payload) == expected
    assert _cdr.decode(TFMessage, renamed).transforms[0].header.frame_id == "c"
    with pytest.raises(_cdr.CdrError):
        _cdr.check(JointState, b"\x00\x01\x00\x00junk")
