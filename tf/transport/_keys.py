"""rmw_zenoh naming: topic key expressions, liveliness tokens, GIDs and the message attachment.

What a ROS 2 node running ``rmw_zenoh_cpp`` (Jazzy and later) uses, so that a bridge or a ROS 2
peer can later read what urdftk sends:

- data key: ``<domain>/<topic without leading slash>/<dds type>/<type hash>``, for example
  ``0/tf/tf2_msgs::msg::dds_::TFMessage_/RIHS01_e369…``;
- liveliness token of a node: ``@ros2_lv/<domain>/<zid>/<nid>/<nid>/NN/<enclave>/<namespace>/<node>``,
  of a publisher (``MP``) or subscription (``MS``): the same with the entity id, then
  ``/<topic>/<dds type>/<type hash>/<qos>``; ``/`` inside a name becomes ``%``;
- attachment of every sample (33 bytes, zenoh-ext serialization): int64 sequence number (from 1,
  per publisher), int64 source timestamp in ns since the epoch, LEB128 length ``0x10``, 16-byte GID.

The RIHS01 type hashes are the ROS 2 type-description hashes of the two messages (identical in
Humble, Jazzy and Rolling; rosbags' ``hash_rihs01`` computes the same values, which the tests check).
rmw_zenoh derives a GID from XXH3-128 of the liveliness key; we use BLAKE2b-128 of the same key
(no extra dependency): it is just as unique, and GIDs are opaque to receivers.
"""

from __future__ import annotations

import hashlib
import struct
from dataclasses import dataclass

from ..messages import JointState, TFMessage

__all__ = [
    "ADMIN_SPACE",
    "ATTACHMENT_SIZE",
    "Attachment",
    "EntityToken",
    "TypeInfo",
    "entity_token",
    "gid_of",
    "node_token",
    "pack_attachment",
    "parse_token",
    "qos_string",
    "topic_key",
    "type_info",
    "type_info_by_dds",
    "unpack_attachment",
]

ADMIN_SPACE = "@ros2_lv"
ATTACHMENT_SIZE = 33
_ATTACHMENT = struct.Struct("<qqB16s")
_FORBIDDEN_IN_TOPIC = frozenset("*$?#@ ")


@dataclass(frozen=True)
class TypeInfo:
    """How a message type is named on the wire."""

    ros_name: str
    dds_name: str
    type_hash: str


_TYPES: dict[type, TypeInfo] = {
    TFMessage: TypeInfo(
        "tf2_msgs/msg/TFMessage",
        "tf2_msgs::msg::dds_::TFMessage_",
        "RIHS01_e369d0f05a23ae52508854b66f6aa0437f3449d652e8cbf22d5abe85d020f087",
    ),
    JointState: TypeInfo(
        "sensor_msgs/msg/JointState",
        "sensor_msgs::msg::dds_::JointState_",
        "RIHS01_a13ee3a330e346c9d87b5aa18d24e11690752bd33a0350f11c5882bc9179260e",
    ),
}


def type_info(msg_type: type) -> TypeInfo:
    """Wire names of ``msg_type`` (TFMessage or JointState).

    Raises:
        ValueError: The type has no wire mapping.
    """
    info = _TYPES.get(msg_type)
    if info is None:
        names = ", ".join(sorted(t.__name__ for t in _TYPES))
        raise ValueError(
            f"{getattr(msg_type, '__name__', msg_type)} cannot travel over Zenoh; supported: {names}"
        )
    return info


def type_info_by_dds(dds_name: str) -> tuple[type, TypeInfo] | None:
    """The message class and wire names for a DDS type name, or None if it is not one of ours."""
    for msg_type, info in _TYPES.items():
        if info.dds_name == dds_name:
            return msg_type, info
    return None


def _check_topic(topic: str) -> str:
    name = topic.strip("/")
    if not name or "//" in name or any(c in _FORBIDDEN_IN_TOPIC for c in name):
        raise ValueError(f"{topic!r} is not a valid topic name (e.g. '/tf')")
    return name


def topic_key(domain_id: int, topic: str, info: TypeInfo) -> str:
    """The data key expression of ``topic`` (``/tf``) in ``domain_id`` for messages ``info``."""
    return f"{int(domain_id)}/{_check_topic(topic)}/{info.dds_name}/{info.type_hash}"


def _mangle(name: str) -> str:
    return name.replace("/", "%")


def qos_string(*, depth: int, transient_local: bool = False) -> str:
    """rmw_zenoh's compact QoS text: only the values that differ from its defaults.

    Defaults are reliable, volatile, keep-last 42. Durability transient-local is enum value 1.
    """
    durability = "1" if transient_local else ""
    keep = "" if depth == 42 else str(int(depth))
    return f":{durability}:,{keep}:,:,:,,"


def node_token(domain_id: int, zid: str, node_id: int, node_name: str, namespace: str = "/") -> str:
    """Liveliness key announcing a node."""
    nid = str(node_id)
    return f"{ADMIN_SPACE}/{int(domain_id)}/{zid}/{nid}/{nid}/NN/%/{_mangle(namespace)}/{_mangle(node_name)}"


def entity_token(
    domain_id: int,
    zid: str,
    node_id: int,
    entity_id: int,
    kind: str,
    node_name: str,
    topic: str,
    info: TypeInfo,
    qos: str,
    namespace: str = "/",
) -> str:
    """Liveliness key announcing a publisher (``kind="MP"``) or a subscription (``"MS"``)."""
    if kind not in ("MP", "MS"):
        raise ValueError(f"entity kind must be 'MP' or 'MS', got {kind!r}")
    _check_topic(topic)
    topic_name = topic if topic.startswith("/") else "/" + topic
    return (
        f"{ADMIN_SPACE}/{int(domain_id)}/{zid}/{node_id}/{entity_id}/{kind}/%/{_mangle(namespace)}/"
        f"{_mangle(node_name)}/{_mangle(topic_name)}/{info.dds_name}/{info.type_hash}/{qos}"
    )


@dataclass(frozen=True)
class EntityToken:
    """A parsed liveliness token (a node, publisher or subscription somewhere in the domain)."""

    domain_id: int
    zid: str
    node_id: str
    entity_id: str
    kind: str
    namespace: str
    node_name: str
    topic: str = ""
    dds_type: str = ""
    type_hash: str = ""
    qos: str = ""

    @property
    def gid(self) -> bytes:
        """The GID this entity stamps on its samples (for urdftk peers; opaque for others)."""
        return gid_of(str(self.key))

    @property
    def key(self) -> str:
        """The liveliness key expression this token was parsed from."""
        head = (
            f"{ADMIN_SPACE}/{self.domain_id}/{self.zid}/{self.node_id}/{self.entity_id}/{self.kind}/%/"
            f"{_mangle(self.namespace)}/{_mangle(self.node_name)}"
        )
        if self.kind == "NN":
            return head
        return f"{head}/{_mangle(self.topic)}/{self.dds_type}/{self.type_hash}/{self.qos}"


def parse_token(key: str) -> EntityToken | None:
    """Parse a liveliness key expression; None if it is not an rmw_zenoh entity token."""
    parts = key.split("/")
    if len(parts) < 9 or parts[0] != ADMIN_SPACE or parts[5] not in ("NN", "MP", "MS", "SS", "SC"):
        return None
    try:
        domain_id = int(parts[1])
    except ValueError:
        return None
    common = {
        "domain_id": domain_id,
        "zid": parts[2],
        "node_id": parts[3],
        "entity_id": parts[4],
        "kind": parts[5],
        "namespace": parts[7].replace("%", "/"),
        "node_name": parts[8].replace("%", "/"),
    }
    if parts[5] == "NN":
        return EntityToken(**common)
    if len(parts) < 13:
        return None
    return EntityToken(
        **common,
        topic=parts[9].replace("%", "/"),
        dds_type=parts[10],
        type_hash=parts[11],
        qos="/".join(parts[12:]),
    )


def gid_of(token_key: str) -> bytes:
    """The 16-byte GID of an entity, derived from its liveliness key."""
    return hashlib.blake2b(token_key.encode("utf-8"), digest_size=16).digest()


@dataclass(frozen=True)
class Attachment:
    """What rides along with each sample: sequence number, source time, publisher GID."""

    sequence_number: int
    source_timestamp_ns: int
    gid: bytes


def pack_attachment(sequence_number: int, source_timestamp_ns: int, gid: bytes) -> bytes:
    """The 33-byte attachment rmw_zenoh puts on every sample."""
    return _ATTACHMENT.pack(sequence_number, source_timestamp_ns, 16, gid)


def unpack_attachment(data: bytes | None) -> Attachment | None:
    """Parse an attachment; None when absent or not in rmw_zenoh's layout."""
    if data is None or len(data) != ATTACHMENT_SIZE:
        return None
    seq, stamp, length, gid = _ATTACHMENT.unpack(data)
    if length != 16:
        return None
    return Attachment(seq, stamp, gid)
