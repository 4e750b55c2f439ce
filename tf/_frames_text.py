"""tf2's text views of the frame tree: allFramesAsString, allFramesAsYAML (ROS 2), allFramesAsDot."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

__all__ = ["as_dot", "as_string", "as_yaml"]


def _sec(ns: int) -> float:
    sec, nsec = divmod(ns, 1_000_000_000)
    return sec + nsec * 1e-9


def _fmt(ns: int) -> str:
    return f"{_sec(ns):.6f}"


def as_string(names: Sequence[str], caches: Sequence[Any]) -> str:
    """One "Frame C exists with parent P." line per child frame, in first-seen order."""
    lines = []
    for fid in range(1, len(caches)):
        cache = caches[fid]
        if cache is None:
            continue
        latest = cache.latest
        parent = latest[1] if latest is not None else 0
        lines.append(f"Frame {names[fid]} exists with parent {names[parent]}.\n")
    return "".join(lines)


def _stats(cache: Any) -> tuple[int, int, int, float]:
    newest = 0 if cache.static else cache.latest[0]
    oldest = cache.oldest_stamp()
    span = newest - oldest
    rate = len(cache) * 1e9 / (span if span > 100_000 else 100_000)
    return newest, oldest, span, rate


def as_yaml(names: Sequence[str], caches: Sequence[Any], authority: dict[int, str], now_ns: int) -> str:
    """ROS 2 allFramesAsYAML; "[]" when no frame is known, frames with no data are skipped."""
    out = ["[]"] if len(caches) == 1 else []
    for fid in range(1, len(caches)):
        cache = caches[fid]
        if cache is None or cache.latest is None:
            continue
        newest, oldest, span, rate = _stats(cache)
        out.append(f"{names[fid]}: \n")
        out.append(f"  parent: '{names[cache.latest[1]]}'\n")
        out.append(f"  broadcaster: '{authority.get(fid, 'no recorded authority')}'\n")
        out.append(f"  rate: {rate:.3f}\n")
        out.append(f"  most_recent_transform: {_fmt(newest)}\n")
        out.append(f"  oldest_transform: {_fmt(oldest)}\n")
        if now_ns:
            out.append(f"  transform_delay: {_sec(now_ns - newest):.3f}\n")
        out.append(f"  buffer_length: {_sec(span):.3f}\n")
    return "".join(out)


def as_dot(names: Sequence[str], caches: Sequence[Any], authority: dict[int, str], now_ns: int) -> str:
    """tf2 _allFramesAsDot: a graphviz digraph of parent -> child edges with broadcaster and rates."""
    out = ["digraph G {\n"]
    if len(caches) == 1:
        out.append('"no tf data recieved"')
    for fid in range(1, len(caches)):
        cache = caches[fid]
        if cache is None or cache.latest is None:
            continue
        newest, _oldest, span, rate = _stats(cache)
        age = f"( {_sec(now_ns - newest):.3f} sec old)" if now_ns else ""
        out.append(
            f'"{names[cache.latest[1]]}" -> "{names[fid]}"[label="'
            f"Broadcaster: {authority.get(fid, 'no recorded authority')}\\n"
            f"Average rate: {rate:.3f} Hz\\n"
            f"Most recent transform: {_fmt(newest)} {age}\\n"
            f'Buffer length: {_sec(span):.3f} sec\\n"];\n'
        )
    for fid in range(1, len(caches)):
        cache = caches[fid]
        if cache is None:
            if now_ns:
                out.append("edge [style=invis];\n")
                out.append(
                    ' subgraph cluster_legend { style=bold; color=black; label ="view_frames Result";\n'
                )
                out.append(f'"Recorded at time: {_fmt(now_ns)}"[ shape=plaintext ] ;\n }}->"{names[fid]}";\n')
            continue
        if cache.latest is None or cache.latest[1] == 0:
            out.append("edge [style=invis];\n")
            out.append(' subgraph cluster_legend { style=bold; color=black; label ="view_frames Result";\n')
            if now_ns:
                out.append(f'"Recorded at time: {_fmt(now_ns)}"[ shape=plaintext ] ;\n ')
            out.append(f'}}->"{names[fid]}";\n')
    out.append("}")
    return "".join(out)
