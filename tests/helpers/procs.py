"""Spawn real child processes for the Zenoh tests and read their output with timeouts.

Every child gets its own ROS domain id (so tests running at the same time never see each
other's data), reads stdin and exits when it closes, and is killed by the context manager.
"""

from __future__ import annotations

import contextlib
import os
import queue
import random
import re
import signal
import socket
import subprocess
import sys
import threading
import time
from collections.abc import Mapping, Sequence
from pathlib import Path

__all__ = ["CHILD", "REPO", "Child", "child_env", "free_port", "unique_domain", "urdftk_cmd"]

REPO = Path(__file__).resolve().parents[2]
CHILD = str(Path(__file__).with_name("zenoh_child.py"))
_ZENOH_VARS = ("URDFTK_ZENOH_CONNECT", "URDFTK_ZENOH_LISTEN", "URDFTK_ZENOH_CONFIG", "URDFTK_TRANSPORT")
_rng = random.Random()


def unique_domain() -> int:
    """A domain id no other test uses at the same time (random, large)."""
    return _rng.randrange(1_000, 2_000_000_000)


def free_port() -> int:
    """A TCP port on 127.0.0.1 that was free a moment ago."""
    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def child_env(domain: int, extra: Mapping[str, str] | None = None) -> dict[str, str]:
    """A clean environment for a child: our domain, no inherited Zenoh settings, unbuffered output."""
    env = {k: v for k, v in os.environ.items() if k not in _ZENOH_VARS}
    env["ROS_DOMAIN_ID"] = str(domain)
    env["PYTHONUNBUFFERED"] = "1"
    env["PYTHONPATH"] = os.pathsep.join(filter(None, [str(REPO), env.get("PYTHONPATH", "")]))
    env.update(extra or {})
    return env


def urdftk_cmd(*args: str) -> list[str]:
    """The command line running ``urdftk ARGS`` with this interpreter."""
    return [sys.executable, "-m", "urdftk", *args]


class Child:
    """A child process whose stdout lines are read in the background.

    Args:
        args: Command line.
        env: Environment (see :func:`child_env`).
    """

    def __init__(self, args: Sequence[str], env: Mapping[str, str]) -> None:
        self.args = list(args)
        self.started = time.monotonic()
        self.proc = subprocess.Popen(
            self.args,
            env=dict(env),
            stdin=subprocess.PIPE,
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            text=True,
            cwd=str(REPO),
        )
        self.lines: queue.Queue[str | None] = queue.Queue()
        self.stdout: list[str] = []
        self.stderr: list[str] = []
        self._threads = [
            threading.Thread(target=self._pump, args=(self.proc.stdout, self.stdout, True), daemon=True),
            threading.Thread(target=self._pump, args=(self.proc.stderr, self.stderr, False), daemon=True),
        ]
        for t in self._threads:
            t.start()

    def _pump(self, stream, store: list[str], to_queue: bool) -> None:
        for line in stream:
            store.append(line)
            if to_queue:
                self.lines.put(line.rstrip("\n"))
        if to_queue:
            self.lines.put(None)

    def expect(self, pattern: str, timeout: float) -> re.Match[str]:
        """Wait for a stdout line matching ``pattern`` (regex search); fail with the output so far."""
        deadline = time.monotonic() + timeout
        regex = re.compile(pattern)
        while True:
            remaining = deadline - time.monotonic()
            if remaining <= 0:
                raise AssertionError(f"no line matching {pattern!r} within {timeout}s; {self.describe()}")
            try:
                line = self.lines.get(timeout=remaining)
            except queue.Empty:
                continue
            if line is None:
                raise AssertionError(f"process ended before {pattern!r}; {self.describe()}")
            match = regex.search(line)
            if match:
                return match

    def wait(self, timeout: float) -> int:
        """Wait for exit (kills it on timeout and fails)."""
        try:
            return self.proc.wait(timeout)
        except subprocess.TimeoutExpired:
            self.kill()
            raise AssertionError(f"process did not exit within {timeout}s; {self.describe()}") from None

    def describe(self) -> str:
        """Command, exit status and output so far, for failure messages."""
        time.sleep(0.05)  # let the reader threads catch the last lines
        return (
            f"cmd={' '.join(self.args)} rc={self.proc.poll()}\n"
            f"--- stdout ---\n{''.join(self.stdout)[-3000:]}\n--- stderr ---\n{''.join(self.stderr)[-3000:]}"
        )

    def interrupt(self) -> None:
        """Send SIGINT (Ctrl-C)."""
        if self.proc.poll() is None:
            self.proc.send_signal(signal.SIGINT)

    def kill(self) -> None:
        """Kill the process (SIGKILL) and reap it."""
        if self.proc.poll() is None:
            self.proc.kill()
        with contextlib.suppress(subprocess.TimeoutExpired):
            self.proc.wait(10)
        for stream in (self.proc.stdin,):
            with contextlib.suppress(OSError):
                stream.close()

    def __enter__(self) -> Child:
        return self

    def __exit__(self, *exc: object) -> None:
        self.kill()
