"""Render a viewer page in headless Chromium (Playwright, Debian's ``/usr/bin/chromium``) to a PNG.

WebGL runs on SwiftShader (``--use-angle=swiftshader --enable-unsafe-swiftshader``), so no GPU
or display is needed. The page is captured once the canvas is drawn and two consecutive frames
are identical (the scene has finished arriving), or when the timeout is reached.
"""

from __future__ import annotations

import os
import shutil
import tempfile
import time
from pathlib import Path

__all__ = ["CHROMIUM_ARGS", "chromium_path", "save_screenshot", "screenshot"]

CHROMIUM_ARGS = (
    "--headless=new",
    "--use-angle=swiftshader",
    "--enable-unsafe-swiftshader",
    "--no-sandbox",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
    "--no-first-run",
)
"""Chromium flags for headless WebGL without a GPU and without any outside network traffic."""

_HIDE_TOASTS = ".mantine-Notifications-root { display: none !important; }"


def chromium_path() -> str:
    """The Chromium executable: ``$URDFTK_CHROMIUM``, else ``chromium`` on PATH.

    Raises:
        FileNotFoundError: With the install hint.
    """
    found = os.environ.get("URDFTK_CHROMIUM") or shutil.which("chromium") or shutil.which("chromium-browser")
    if not found:
        raise FileNotFoundError(
            "no chromium found for --screenshot; install it (Debian: apt install chromium)"
        )
    return found


def screenshot(
    url: str,
    *,
    width: int = 1280,
    height: int = 800,
    timeout: float = 60.0,
    settle: float = 0.5,
    min_wait: float = 2.0,
) -> bytes:
    """Open ``url`` in headless Chromium and return a PNG of the page.

    Args:
        url: The viewer address.
        width: Viewport width in pixels.
        height: Viewport height in pixels.
        timeout: Seconds to wait for the page to become stable.
        settle: Seconds between the frames compared for stability.
        min_wait: Seconds to let the scene arrive before comparing frames.

    Returns:
        The PNG bytes.
    """
    try:
        from playwright.sync_api import sync_playwright
    except ImportError:
        raise FileNotFoundError(
            "--screenshot needs Playwright: pip install playwright (no browser download)"
        ) from None

    with tempfile.TemporaryDirectory(prefix="urdftk-chromium-") as profile, sync_playwright() as pw:
        context = pw.chromium.launch_persistent_context(
            profile,
            executable_path=chromium_path(),
            args=list(CHROMIUM_ARGS),
            headless=True,
            viewport={"width": width, "height": height},
        )
        try:
            page = context.new_page()
            page.goto(url, wait_until="load", timeout=timeout * 1000)
            page.add_style_tag(content=_HIDE_TOASTS)
            page.wait_for_selector("canvas", timeout=timeout * 1000)
            deadline = time.monotonic() + timeout
            page.wait_for_timeout(min_wait * 1000)
            previous = page.screenshot()
            while True:
                page.wait_for_timeout(settle * 1000)
                current = page.screenshot()
                if current == previous or time.monotonic() > deadline:
                    return current
                previous = current
        finally:
            context.close()


def save_screenshot(url: str, path: str | os.PathLike[str], **kwargs: object) -> Path:
    """Write :func:`screenshot` of ``url`` to ``path`` atomically."""
    from urdftk._atomic import write_atomic

    data = screenshot(url, **kwargs)  # type: ignore[arg-type]
    write_atomic(path, data)
    return Path(path)
