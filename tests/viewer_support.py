"""Support for the viewer tests: a real ``urdftk view`` process, a real headless Chromium, a real
websocket client decoding what viser sends, and pixel helpers.

Nothing is mocked: the viewer runs as a subprocess, the page renders in Debian's Chromium with
SwiftShader WebGL, and the scene transforms are read off viser's own wire format.
"""

from __future__ import annotations

import io
import os
import queue
import re
import socket
import subprocess
import sys
import threading
import time
from collections.abc import Sequence
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parents[1]
CHROMIUM = "/usr/bin/chromium"
CHROMIUM_ARGS = [
    "--headless=new",
    "--use-angle=swiftshader",
    "--enable-unsafe-swiftshader",
    "--no-sandbox",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
    "--no-first-run",
]
HIDE_TOASTS = ".mantine-Notifications-root { display: none !important; }"
_ZENOH_VARS = ("URDFTK_ZENOH_CONNECT", "URDFTK_ZENOH_LISTEN", "URDFTK_ZENOH_CONFIG", "URDFTK_TRANSPORT")


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def example_robot_data() -> Path:
    from urdftk.resources import PackageResolver

    return PackageResolver().find("example-robot-data")


class ViewProcess:
    """``urdftk view ARGS`` in a subprocess; waits for its URL line."""

    def __init__(
        self, args: Sequence[str], *, domain: int | None = None, zenoh_port: int | None = None
    ) -> None:
        env = {k: v for k, v in os.environ.items() if k not in _ZENOH_VARS}
        env["PYTHONUNBUFFERED"] = "1"
        env["PYTHONPATH"] = os.pathsep.join(filter(None, [str(REPO), env.get("PYTHONPATH", "")]))
        if domain is not None:
            env["ROS_DOMAIN_ID"] = str(domain)
        if zenoh_port is not None:
            env["URDFTK_ZENOH_LISTEN"] = f"tcp/127.0.0.1:{zenoh_port}"
        self.port = free_port()
        self.args = [sys.executable, "-m", "urdftk", "view", *args, "--port", str(self.port)]
        self.proc = subprocess.Popen(
            self.args, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, cwd=str(REPO)
        )
        self.lines: queue.Queue[str] = queue.Queue()
        self.stderr: list[str] = []
        threading.Thread(target=self._read, args=(self.proc.stdout, True), daemon=True).start()
        threading.Thread(target=self._read, args=(self.proc.stderr, False), daemon=True).start()
        self.url = self.wait_line(r"at (http://\S+)", 60).group(1)

    def _read(self, stream: io.TextIOBase, out: bool) -> None:
        for line in stream:
            if out:
                self.lines.put(line)
            else:
                self.stderr.append(line)

    def wait_line(self, pattern: str, timeout: float) -> re.Match[str]:
        deadline = time.monotonic() + timeout
        while True:
            left = deadline - time.monotonic()
            if left <= 0:
                raise AssertionError(f"no line matching {pattern!r}; stderr: {''.join(self.stderr)[-3000:]}")
            try:
                line = self.lines.get(timeout=min(left, 1.0))
            except queue.Empty:
                if self.proc.poll() is not None:
                    raise AssertionError(
                        f"urdftk view exited {self.proc.returncode}: {''.join(self.stderr)[-3000:]}"
                    ) from None
                continue
            m = re.search(pattern, line)
            if m:
                return m

    def close(self) -> None:
        if self.proc.poll() is None:
            self.proc.terminate()
            try:
                self.proc.wait(timeout=10)
            except subprocess.TimeoutExpired:
                self.proc.kill()
                self.proc.wait()

    def __enter__(self) -> ViewProcess:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


class SceneClient:
    """A websocket client speaking viser's protocol; keeps every node's last pose and visibility."""

    def __init__(self, url: str) -> None:
        import viser
        from websockets.sync.client import connect

        ws_url = url.replace("http://", "ws://").rstrip("/")
        self._ws = connect(ws_url, subprotocols=[f"viser-v{viser.__version__}"], max_size=None)
        self.positions: dict[str, np.ndarray] = {}
        self.wxyz: dict[str, np.ndarray] = {}
        self.visible: dict[str, bool] = {}
        self.created: dict[str, dict] = {}
        self.times: dict[str, float] = {}
        self.bytes_received = 0
        self._lock = threading.RLock()
        self._changed = threading.Condition(self._lock)
        self._thread = threading.Thread(target=self._run, daemon=True)
        self._thread.start()

    @staticmethod
    def decode(data: bytes) -> list[dict]:
        import msgspec
        import zstandard

        size = int.from_bytes(data[0:8], "little")
        csize = int.from_bytes(data[8:16], "little")
        inner = zstandard.ZstdDecompressor().decompress(data[16 : 16 + csize], max_output_size=size)
        return list(msgspec.msgpack.decode(inner)["messages"])

    def _run(self) -> None:
        try:
            for data in self._ws:
                if isinstance(data, str):
                    continue
                messages = self.decode(data)
                now = time.monotonic()
                with self._changed:
                    self.bytes_received += len(data)
                    for m in messages:
                        self._apply(m, now)
                    self._changed.notify_all()
        except Exception:
            return

    def _apply(self, m: dict, now: float) -> None:
        kind, name = m.get("type", ""), m.get("name")
        if name is None:
            return
        if kind == "SetPositionMessage":
            self.positions[name] = np.asarray(m["position"], dtype=float)
        elif kind == "SetOrientationMessage":
            self.wxyz[name] = np.asarray(m["wxyz"], dtype=float)
        elif kind == "SetSceneNodeVisibilityMessage":
            self.visible[name] = bool(m["visible"])
        elif kind == "RemoveSceneNodeMessage":
            for d in (self.positions, self.wxyz, self.visible, self.created):
                for k in [k for k in d if k == name or k.startswith(name + "/")]:
                    del d[k]
        elif kind.endswith("Message") and "props" in m:
            self.created[name] = m
            self.times[name] = now
            self.positions.setdefault(name, np.zeros(3))
            self.wxyz.setdefault(name, np.array([1.0, 0, 0, 0]))

    def wait(self, predicate, timeout: float = 10.0):
        deadline = time.monotonic() + timeout
        with self._changed:
            while True:
                value = predicate(self)
                if value is not None and value is not False:
                    return value
                left = deadline - time.monotonic()
                if left <= 0:
                    raise AssertionError("scene never reached the expected state")
                self._changed.wait(left)

    def pose(self, name: str) -> np.ndarray:
        """T_parent_node as a 4x4 matrix (wxyz read off the wire, converted here)."""
        with self._lock:
            w, x, y, z = self.wxyz[name]
            p = self.positions[name]
        from urdftk.viewer._poses import xyzw_to_matrix

        return xyzw_to_matrix(p, np.array([x, y, z, w]))

    def close(self) -> None:
        self._ws.close()


def png_array(png: bytes) -> np.ndarray:
    from PIL import Image

    return np.asarray(Image.open(io.BytesIO(png)).convert("RGB")).astype(np.int16)


def colour_mask(img: np.ndarray, rgb: Sequence[int], tol: int = 40) -> np.ndarray:
    """Pixels whose hue matches ``rgb`` after lighting: compare normalised chromaticity and darkness."""
    target = np.asarray(rgb, dtype=float)
    pix = img.astype(float)
    s_t, s_p = target.sum() + 1e-6, pix.sum(axis=2) + 1e-6
    chroma = np.abs(pix / s_p[..., None] - target / s_t).max(axis=2)
    return chroma < tol / 255.0


SCENE = (0.0, 0.0, 0.64, 1.0)
"""The part of a 1000-pixel-wide page not covered by viser's control panel."""


def scene_only(mask: np.ndarray) -> np.ndarray:
    """``mask`` with the control-panel side (right of :data:`SCENE`) cleared."""
    out = mask.copy()
    out[:, int(SCENE[2] * mask.shape[1]) :] = False
    return out


def count_in(mask: np.ndarray, box: tuple[float, float, float, float]) -> int:
    """Pixels set in the box given as fractions (x0, y0, x1, y1) of the image."""
    h, w = mask.shape
    x0, y0, x1, y1 = box
    return int(mask[int(y0 * h) : int(y1 * h), int(x0 * w) : int(x1 * w)].sum())


class Browser:
    """A headless Chromium page on a viewer URL (Playwright sync API, Debian's chromium)."""

    def __init__(self, url: str, *, width: int = 1000, height: int = 700) -> None:
        from playwright.sync_api import sync_playwright

        self._pw = sync_playwright().start()
        self._browser = self._pw.chromium.launch(executable_path=CHROMIUM, args=CHROMIUM_ARGS)
        self.page = self._browser.new_page(viewport={"width": width, "height": height})
        self.page.goto(url)
        self.page.add_style_tag(content=HIDE_TOASTS)
        self.page.wait_for_selector("canvas", timeout=60_000)

    def shot(self, settle_ms: int = 600) -> np.ndarray:
        """A screenshot once two consecutive frames agree."""
        prev = self.page.screenshot()
        for _ in range(20):
            self.page.wait_for_timeout(settle_ms)
            cur = self.page.screenshot()
            if cur == prev:
                break
            prev = cur
        return png_array(cur)

    def label(self, text: str):
        return self.page.locator("label").filter(has_text=re.compile(rf"^{re.escape(text)}$")).first

    def set_slider(self, name: str, value: float) -> None:
        row = self.label(name).locator("xpath=ancestor::div[contains(@class,'mantine-Flex-root')][1]")
        box = row.locator("input:not([type=hidden])").first
        box.fill(f"{value:.4f}")
        box.press("Enter")

    def tab(self, name: str) -> None:
        self.page.get_by_role("tab", name=name).click()

    def click_checkbox(self, name: str) -> None:
        self.label(name).click()

    def choose(self, label: str, option: str) -> None:
        self.page.get_by_label(label).first.click()
        self.page.get_by_role("option", name=option, exact=True).click()

    def close(self) -> None:
        self._browser.close()
        self._pw.stop()

    def __enter__(self) -> Browser:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()
