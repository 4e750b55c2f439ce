"""Benchmark: urdftk's xacro expander against stock xacro 2.1.1 on the real-robot corpus.

Usage: python bench/xacro.py [--repeat N] [--only SUBSTRING] [--no-cli]

1. In-process CPU time (``time.process_time``) per case, stock's ``process_file`` +
   ``toprettyxml`` against ``urdftk.xacro.expand``: N rounds of 3 runs of each side in turn,
   the median of the 3N runs; also the first (cold) run of each. Each side pays for reclaiming
   its own garbage, and only its own (see ``batch``).
2. Whole-process CPU time (child rusage) of the ``urdftk xacro`` command against the stock
   ``xacro`` command, per case (median of 2N+1 runs each, the two commands alternating).

Stock resolves ``$(find)`` through ament_index_python: it gets a temporary ament prefix with the
corpus packages; ours gets ROS_PACKAGE_PATH, as in the corpus checker. Ours must reproduce the
expected output of every case (checked). Ratios are ours / stock, measured in this run.
"""

from __future__ import annotations

import argparse
import contextlib
import gc
import io
import json
import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

CORPUS = Path(__file__).resolve().parents[2] / "shared" / "corpus" / "xacro"
BIN = Path(sys.executable).parent


def ament_prefix(root: Path, packages: dict[str, str]) -> Path:
    index = root / "share" / "ament_index" / "resource_index" / "packages"
    index.mkdir(parents=True, exist_ok=True)
    for name, rel in packages.items():
        (index / name).write_text("")
        link = root / "share" / name
        if not link.exists():
            link.symlink_to(CORPUS / rel, target_is_directory=True)
    return root


def batch(fn, env: dict[str, str | None], runs: int) -> tuple[list[float], float, int]:
    """``runs`` runs of ``fn`` in a row, with ``env`` applied, from a clean heap.

    A full collection (not timed) comes first, so that no side pays for collecting garbage the
    other left behind. What the collector does during the runs is in their times; after them,
    one more full collection finds the garbage they left (the cyclic garbage of the last runs)
    and a second one, on the clean heap, gives the cost of a collection that finds none.

    Returns:
        The CPU time (ms) of each run; the extra CPU time (ms) of the first collection over the
        second; the number of unreachable objects the first collection found.
    """
    for k, v in env.items():
        if v is None:
            os.environ.pop(k, None)
        else:
            os.environ[k] = v
    gc.collect()
    times = []
    for _ in range(runs):
        t = time.process_time()
        fn()
        times.append((time.process_time() - t) * 1000)
    t = time.process_time()
    found = gc.collect()
    left = time.process_time() - t
    t = time.process_time()
    gc.collect()
    clean = time.process_time() - t
    return times, (left - clean) * 1000, found


def paired(stock, ours, rounds: int, runs: int = 3) -> tuple[float, float, float, float]:
    """(stock first, stock median, ours first, ours median) in ms: batches of each side in turn.

    Alternating batches spreads machine drift over both sides; the first run of each side is
    its cold one (caches empty). Each side pays for reclaiming its own garbage, and only its
    own: a batch that left garbage gets the extra cost of collecting it shared out over its
    runs. That extra cost also includes emptying the allocator's free lists, which every full
    collection does after activity; it is measured on the batches that left no garbage and
    taken off, so that only the reclamation of garbage is charged.
    """
    s: list[list[float]] = []
    o: list[list[float]] = []
    extra: list[tuple[list[float], float, int]] = []
    for _ in range(rounds):
        for side, out in ((stock, s), (ours, o)):
            times, more, found = batch(*side, runs)
            out.append(times)
            extra.append((times, more, found))
    baseline = [more for _, more, found in extra if found == 0]
    freelists = statistics.median(baseline) if baseline else 0.0
    for times, more, found in extra:
        if found:
            share = max(0.0, more - freelists) / runs
            times[:] = [x + share for x in times]
    s_all = [x for b in s for x in b]
    o_all = [x for b in o for x in b]
    return s_all[0], statistics.median(s_all), o_all[0], statistics.median(o_all)


def child_cpu(cmd: list[str], env: dict[str, str]) -> float:
    """CPU time (user + system) of one run of ``cmd``, in ms."""
    r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
    run = subprocess.run(cmd, cwd=CORPUS, env=env, capture_output=True, timeout=300)
    r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    if run.returncode != 0:
        raise RuntimeError(f"{cmd} failed: {run.stderr.decode()[-500:]}")
    return (r1.ru_utime + r1.ru_stime - r0.ru_utime - r0.ru_stime) * 1000


def cli_pair(stock: tuple[list[str], dict[str, str]], ours: tuple[list[str], dict[str, str]], repeat: int):
    """Median CPU of each command over ``repeat`` runs, alternating them (load drifts hit both)."""
    s, o = [], []
    for _ in range(repeat):
        s.append(child_cpu(*stock))
        o.append(child_cpu(*ours))
    return statistics.median(s), statistics.median(o)


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--only", default="")
    ap.add_argument("--no-cli", action="store_true")
    a = ap.parse_args()

    here = Path(__file__).resolve().parent
    sys.path[:] = [p for p in sys.path if Path(p or ".").resolve() != here]  # this file is named xacro.py
    import xacro  # stock, the reference

    from urdftk.xacro import expand

    cases = [c for c in json.loads((CORPUS / "manifest.json").read_text())["cases"] if a.only in c["id"]]
    tmp = Path(tempfile.mkdtemp(prefix="xacro-bench-"))
    os.chdir(CORPUS)
    rows = []
    for c in cases:
        repo = c["input"].split("/")[0]
        prefix = ament_prefix(tmp / repo, c["packages"])
        args = [x.replace("{corpus}", str(CORPUS)) for x in c["args"]]
        mappings = dict(x.split(":=", 1) for x in args)
        expected = (CORPUS / c["expected"]).read_text().replace("{corpus}", str(CORPUS))
        env_ours = {k: v for k, v in os.environ.items() if k != "AMENT_PREFIX_PATH"}
        env_ours["ROS_PACKAGE_PATH"] = str(CORPUS / repo)
        env_stock = {k: v for k, v in os.environ.items() if k != "ROS_PACKAGE_PATH"}
        env_stock["AMENT_PREFIX_PATH"] = str(prefix)

        def run_stock(c=c, mappings=mappings) -> None:
            xacro.all_includes = []
            with contextlib.redirect_stderr(io.StringIO()):
                doc = xacro.process_file(c["input"], mappings=dict(mappings))
                doc.toprettyxml(indent="  ")

        def run_ours(c=c, mappings=mappings) -> str:
            return expand(c["input"], mappings, stderr=io.StringIO()).text

        s_cold, s_med, o_cold, o_med = paired(
            (run_stock, {"ROS_PACKAGE_PATH": None, "AMENT_PREFIX_PATH": str(prefix)}),
            (run_ours, {"AMENT_PREFIX_PATH": None, "ROS_PACKAGE_PATH": str(CORPUS / repo)}),
            a.repeat,
        )
        assert run_ours() == expected, f"ours differs from stock on {c['id']}"
        row = {"id": c["id"], "stock": s_med, "ours": o_med, "stock_cold": s_cold, "ours_cold": o_cold}
        if not a.no_cli:
            row["cli_stock"], row["cli_ours"] = cli_pair(
                ([str(BIN / "xacro"), c["input"], *args], env_stock),
                ([str(BIN / "urdftk"), "xacro", c["input"], *args], env_ours),
                2 * a.repeat + 1,  # (a start-up costs tens of ms, measured in scheduler ticks: more runs)
            )
        rows.append(row)
        print(
            f"{c['id'][:70]:70s} stock {s_med:7.1f} ms  ours {o_med:6.1f} ms  ratio {o_med / s_med:5.3f}"
            + (f"   cli {row['cli_ours']:5.0f}/{row['cli_stock']:5.0f} ms" if not a.no_cli else ""),
            flush=True,
        )

    print("\n== in-process CPU, median of", 3 * a.repeat, "runs per case (ours / stock)")
    ratios = [r["ours"] / r["stock"] for r in rows]
    print(
        f"cases {len(rows)}  median ratio {statistics.median(ratios):.3f}  "
        f"worst {max(ratios):.3f}  best {min(ratios):.3f}"
    )
    cold = [r["ours_cold"] / r["stock_cold"] for r in rows]
    print(f"first (cold) run: median ratio {statistics.median(cold):.3f}")
    print("three largest (by stock CPU):")
    for r in sorted(rows, key=lambda r: -r["stock"])[:3]:
        print(
            f"  {r['id']}: stock {r['stock']:.1f} ms, ours {r['ours']:.1f} ms,"
            f" ratio {r['ours'] / r['stock']:.3f}"
            f" (cold {r['ours_cold']:.1f}/{r['stock_cold']:.1f} ms)"
        )
    if not a.no_cli:
        faster = sum(r["cli_ours"] < r["cli_stock"] for r in rows)
        cli = [r["cli_ours"] / r["cli_stock"] for r in rows]
        print(
            f"\n== whole-process CPU (urdftk xacro / stock xacro): faster on {faster}/{len(rows)} cases, "
            f"median ratio {statistics.median(cli):.3f}, worst {max(cli):.3f}"
        )
        print(
            f"   total: ours {sum(r['cli_ours'] for r in rows) / 1000:.2f} s, "
            f"stock {sum(r['cli_stock'] for r in rows) / 1000:.2f} s"
        )


if __name__ == "__main__":
    main()
