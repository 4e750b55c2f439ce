"""What the tf command-line tools print and draw: tf2_echo text, view_frames graphs, static transforms.

Pure functions (no network): the ``urdftk tf`` subcommands feed them from a live buffer.
"""

from __future__ import annotations

import math
import subprocess
from collections.abc import Sequence

import numpy as np

from tf.messages import Header, Quaternion, Time, Transform, TransformStamped, Vector3
from tf.transformations import euler_from_quaternion, quaternion_from_euler, quaternion_matrix

__all__ = ["format_echo", "frames_dot", "parse_static_args", "render_dot"]


def format_echo(transform: TransformStamped) -> str:
    """``transform`` as ``ros2 run tf2_ros tf2_echo`` prints it (3 decimals, matrix last).

    The stamp's nanoseconds are zero-padded to 9 digits (tf2_echo forgets the padding).
    """
    stamp = transform.header.stamp
    v, q = transform.transform.translation, transform.transform.rotation
    roll, pitch, yaw = euler_from_quaternion([q.x, q.y, q.z, q.w])
    deg = 180.0 / math.pi
    M = quaternion_matrix([q.x, q.y, q.z, q.w])
    M[:3, 3] = (v.x, v.y, v.z)
    lines = [
        f"At time {stamp.sec}.{stamp.nanosec:09d}",
        f"- Translation: [{v.x:.3f}, {v.y:.3f}, {v.z:.3f}]",
        f"- Rotation: in Quaternion [{q.x:.3f}, {q.y:.3f}, {q.z:.3f}, {q.w:.3f}]",
        f"- Rotation: in RPY (radian) [{roll:.3f}, {pitch:.3f}, {yaw:.3f}]",
        f"- Rotation: in RPY (degree) [{roll * deg:.3f}, {pitch * deg:.3f}, {yaw * deg:.3f}]",
        "- Matrix:",
    ]
    lines += ["".join(f" {value:6.3f}" for value in row) for row in M]
    return "\n".join(lines)


def frames_dot(frames: dict[str, dict], recorded_at: Time) -> str:
    """A view_frames graph (graphviz dot) from ``Buffer.all_frames_as_yaml()`` parsed as a dict.

    Each edge parent -> child is labelled with the broadcaster, the average rate, the buffer
    length and the most recent and oldest stamps.
    """

    def quoted(text: str) -> str:
        return '"' + str(text).replace("\\", "\\\\").replace('"', '\\"') + '"'

    lines = ["digraph G {"]
    roots = set()
    children = set(frames)
    for child in sorted(frames):
        info = frames[child]
        parent = str(info["parent"])
        if parent not in children:
            roots.add(parent)
        label = (
            f" Broadcaster: {info['broadcaster']}\\n"
            f"Average rate: {float(info['rate']):.3f}\\n"
            f"Buffer length: {float(info['buffer_length']):.3f}\\n"
            f"Most recent transform: {float(info['most_recent_transform']):.6f}\\n"
            f"Oldest transform: {float(info['oldest_transform']):.6f}\\n"
        )
        lines.append(f'{quoted(parent)} -> {quoted(child)}[label="{label.replace(chr(34), chr(39))}"];')
    lines.append("edge [style=invis];")
    lines.append(' subgraph cluster_legend { style=bold; color=black; label ="view_frames Result";')
    lines.append(f'"Recorded at time: {recorded_at.to_sec():.6f}"[ shape=plaintext ] ;')
    lines.append(" }" + "".join(f"->{quoted(r)}" for r in sorted(roots)[:1]) + ";")
    lines.append("}")
    return "\n".join(lines) + "\n"


def render_dot(dot: str, fmt: str) -> bytes:
    """Render dot text to ``fmt`` (``pdf``, ``png``, ``svg``) with graphviz's ``dot``.

    Raises:
        OSError: graphviz is missing or fails.
    """
    try:
        proc = subprocess.run(["dot", f"-T{fmt}"], input=dot.encode("utf-8"), capture_output=True, timeout=60)
    except FileNotFoundError:
        raise OSError(
            "graphviz 'dot' is not installed (apt install graphviz); write a .gv file instead"
        ) from None
    except subprocess.TimeoutExpired:
        raise OSError("graphviz 'dot' took more than 60 s") from None
    if proc.returncode != 0:
        raise OSError(f"graphviz 'dot' failed: {proc.stderr.decode(errors='replace').strip()}")
    return proc.stdout


def _floats(values: Sequence[str], what: str) -> list[float]:
    try:
        out = [float(v) for v in values]
    except ValueError:
        raise ValueError(f"{what}: expected numbers, got {' '.join(values)}") from None
    if not all(math.isfinite(v) for v in out):
        raise ValueError(f"{what}: values must be finite")
    return out


def parse_static_args(
    positional: Sequence[str],
    *,
    xyz: Sequence[float | None] = (None, None, None),
    rpy: Sequence[float | None] = (None, None, None),
    quaternion: Sequence[float | None] = (None, None, None, None),
    frame_id: str | None = None,
    child_frame_id: str | None = None,
) -> TransformStamped:
    """The transform of ``static_transform_publisher``'s arguments.

    Positional forms: ``x y z yaw pitch roll PARENT CHILD`` and ``x y z qx qy qz qw PARENT CHILD``
    (ROS 1 order, radians); or ROS 2 flags (``--x --y --z --roll --pitch --yaw | --qx --qy --qz
    --qw --frame-id --child-frame-id``), where missing values default to 0 / identity.

    Raises:
        ValueError: Wrong count, not numbers, both rotation forms, a zero quaternion, or missing frames.
    """
    if positional:
        if len(positional) == 8:
            x, y, z, yaw, pitch, roll = _floats(positional[:6], "x y z yaw pitch roll")
            qx, qy, qz, qw = (float(v) for v in quaternion_from_euler(roll, pitch, yaw))
        elif len(positional) == 9:
            x, y, z, qx, qy, qz, qw = _floats(positional[:7], "x y z qx qy qz qw")
        else:
            raise ValueError(
                f"expected 'x y z yaw pitch roll PARENT CHILD' or 'x y z qx qy qz qw PARENT CHILD', "
                f"got {len(positional)} arguments"
            )
        parent, child = positional[-2], positional[-1]
    else:
        x, y, z = (0.0 if v is None else float(v) for v in xyz)
        if any(v is not None for v in quaternion) and any(v is not None for v in rpy):
            raise ValueError(
                "give the rotation either as --roll/--pitch/--yaw or as --qx/--qy/--qz/--qw, not both"
            )
        if any(v is not None for v in quaternion):
            qx, qy, qz, qw = (
                d if v is None else float(v) for v, d in zip(quaternion, (0, 0, 0, 1), strict=True)
            )
        else:
            roll, pitch, yaw = (0.0 if v is None else float(v) for v in rpy)
            qx, qy, qz, qw = (float(v) for v in quaternion_from_euler(roll, pitch, yaw))
        if not frame_id or not child_frame_id:
            raise ValueError("--frame-id and --child-frame-id are required")
        parent, child = frame_id, child_frame_id
    norm = float(np.linalg.norm([qx, qy, qz, qw]))
    if not norm > 1e-9:
        raise ValueError("the quaternion is zero")
    qx, qy, qz, qw = qx / norm, qy / norm, qz / norm, qw / norm
    if not parent or not child or parent == child:
        raise ValueError(f"parent and child frames must be two different names, got {parent!r} and {child!r}")
    return TransformStamped(
        Header(Time.now(), parent), child, Transform(Vector3(x, y, z), Quaternion(qx, qy, qz, qw))
    )
