"""The buffer's fast paths (insert-time composition for time 0, inlined interpolation) against tf2.

The random generators of test_tf_differential shuffle inserts; here transforms arrive as a state
publisher sends them (parents first, one stamp per round for the whole tree), which is what the
insert-time composition serves, mixed with what must invalidate it: re-parenting, a late parent,
zero stamps, static overwrites, clear(), out-of-order data (kind switches differ between ROS 1
and ROS 2, rule 10, so they are left to test_tf_rules). Oracle: real tf2 (run_oracle).
"""

from __future__ import annotations

import random
from typing import Any

import pytest
from tf_oracle_client import agree


def _set(rng: random.Random, parent: str, child: str, ms: int, static: bool) -> dict[str, Any]:
    q = [rng.uniform(-1, 1) for _ in range(4)]
    n = sum(v * v for v in q) ** 0.5
    return {
        "op": "set",
        "parent": parent,
        "child": child,
        "stamp": [ms // 1000, (ms % 1000) * 1_000_000],
        "t": [rng.uniform(-1, 1) for _ in range(3)],
        "q": [v / n for v in q],
        "static": static,
        "authority": "fast",
    }


def _stream(seed: int, rounds: int) -> list[dict[str, Any]]:
    rng = random.Random(seed)
    ops: list[dict[str, Any]] = [{"op": "new"}]
    n = rng.randint(8, 30)
    names = [f"s{i}" for i in range(n)]
    parent = {names[i]: names[rng.randrange(max(0, i - 3), i)] for i in range(1, n)}
    static = {c for c in parent if rng.random() < 0.2}
    for c in static:
        ops.append(_set(rng, parent[c], c, 0, True))
    ms = 1000
    zeroed: set[str] = set()
    for _ in range(rounds):
        ms += rng.choice((10, 10, 10, 25))
        event = rng.random()
        order = [c for c in names[1:] if c not in static]
        if event < 0.1:
            rng.shuffle(order)  # children before parents: no composition, the walk answers
        for c in order:
            stamp = 0 if event > 0.97 and c == order[-1] and c not in zeroed else ms
            if not stamp:
                zeroed.add(c)  # a second zero stamp is "repeated data" in ROS 1 (rule 3)
            if event > 0.9 and c == order[0]:
                continue  # one link lags: mixed stamps, the common time is older
            ops.append(_set(rng, parent[c], c, stamp, False))
        if 0.1 < event < 0.14:
            c = rng.choice(names[2:])
            parent[c] = rng.choice([p for p in names if p != c and not p.startswith(c)])
            ops.append(_set(rng, parent[c], c, 0 if c in static else ms + 1, c in static))  # re-parent
        elif 0.14 < event < 0.17 and static:
            c = rng.choice(sorted(static))
            ops.append(_set(rng, parent[c], c, 0, True))  # a static value overwritten
        elif 0.17 < event < 0.19:
            ops.append({"op": "clear"})
        elif 0.19 < event < 0.22:
            ops.append(_set(rng, parent[names[1]], names[1], ms - 15, names[1] in static))  # older data
        for _ in range(rng.randint(2, 6)):
            target = names[0] if rng.random() < 0.5 else rng.choice(names)
            source = rng.choice(names)
            t: Any = 0 if rng.random() < 0.7 else [(ms - 5) // 1000, ((ms - 5) % 1000) * 1_000_000]
            ops.append({"op": "lookup", "target": target, "source": source, "time": t})
    return ops


@pytest.mark.timeout(300)
@pytest.mark.parametrize("seed", [11, 12, 13])
def test_state_publisher_streams_agree_with_tf2(seed: int) -> None:
    ops = _stream(seed, 150)
    ours = agree(ops)
    ok = sum(1 for r in ours if r["op"] == "lookup" and r["ok"])
    assert ok > 200, f"only {ok} successful lookups: the stream no longer exercises the fast paths"
