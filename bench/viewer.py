"""Viewer benchmark on Talos (example-robot-data), in one run against viser's ViserUrdf and
Pinocchio's ViserVisualizer.

Measures:
1. time from the command until the robot is visible in headless Chromium (``urdftk view`` as a
   subprocess; the baselines as equivalent scripts), visible = Talos's dark grey pixels drawn;
2. Python time per joint update (one slider-sized change: one joint moved);
   urdftk: the whole path set_joint_positions -> /joint_states -> RobotStatePublisher -> /tf ->
   tf.Buffer -> scene update -> viser; ViserUrdf.update_cfg; ViserVisualizer.display;
3. bytes a connected browser receives per update (a real websocket client on viser's protocol).

Run: ``.venv/bin/python bench/viewer.py``
"""

from __future__ import annotations

import os
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parents[1]
# bench/ holds other areas' scripts (bench/tf.py): keep it off the import path, use tests/ helpers
sys.path[:] = [p for p in sys.path if Path(p or ".").resolve() != Path(__file__).resolve().parent]
sys.path.insert(0, str(REPO / "tests"))

from viewer_support import CHROMIUM, CHROMIUM_ARGS, SceneClient, free_port, png_array  # noqa: E402

N_UPDATES = 300


def talos_path() -> str:
    from urdftk.resources import PackageResolver

    return str(PackageResolver().find("example-robot-data") / "robots/talos_data/robots/talos_full_v2.urdf")


def _visible(png: bytes) -> bool:
    img = png_array(png)
    w = img.shape[1]
    img = img[:, : int(0.64 * w)]
    # Talos's dark parts; ViserUrdf's default camera shows the robot small, so the bar is low
    dark = (np.ptp(img, axis=2) < 20) & (img.max(axis=2) < 110)
    return int(dark.sum()) > 150


def time_to_visible(cmd: list[str], port: int, path: str = "/") -> float:
    """Seconds from starting ``cmd`` until Chromium shows the robot."""
    from playwright.sync_api import sync_playwright

    env = dict(os.environ, PYTHONPATH=str(REPO))
    with sync_playwright() as pw:
        browser = pw.chromium.launch(executable_path=CHROMIUM, args=CHROMIUM_ARGS)
        page = browser.new_page(viewport={"width": 1000, "height": 700})
        t0 = time.monotonic()
        proc = subprocess.Popen(cmd, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, cwd=REPO)
        try:
            while True:
                try:
                    page.goto(f"http://127.0.0.1:{port}{path}", timeout=2000)
                    break
                except Exception:
                    if proc.poll() is not None:
                        raise RuntimeError(f"{cmd} exited {proc.returncode}") from None
                    page.wait_for_timeout(100)
            page.add_style_tag(content=".mantine-Notifications-root { display: none !important; }")
            while not _visible(page.screenshot()):
                if time.monotonic() - t0 > 180:
                    return float("nan")
                page.wait_for_timeout(100)
            return time.monotonic() - t0
        finally:
            proc.terminate()
            proc.wait(timeout=20)
            browser.close()


def baseline_script(kind: str, path: str, port: int) -> list[str]:
    if kind == "viserurdf":
        body = f"""
            import threading, viser, yourdfpy
            from viser.extras import ViserUrdf
            from urdftk.resources import PackageResolver
            r = PackageResolver(source={path!r})
            h = lambda fname: str(r.resolve(fname.replace("package:///", "package://")))
            urdf = yourdfpy.URDF.load({path!r}, filename_handler=h)
            s = viser.ViserServer(host="127.0.0.1", port={port}, verbose=False)
            ViserUrdf(s, urdf)
            threading.Event().wait()
        """
    else:
        body = f"""
            import threading, viser, pinocchio as pin
            from pinocchio.visualize import ViserVisualizer
            from urdftk.resources import PackageResolver
            share = str(PackageResolver().find("example-robot-data").parent)
            model, cm, vm = pin.buildModelsFromUrdf({path!r}, package_dirs=[share])
            viz = ViserVisualizer(model, cm, vm)
            viz.initViewer(viewer=viser.ViserServer(host="127.0.0.1", port={port}, verbose=False))
            viz.loadViewerModel()
            viz.display(pin.neutral(model))
            threading.Event().wait()
        """
    return [sys.executable, "-c", textwrap.dedent(body)]


def _per_update(update, n: int = N_UPDATES) -> float:
    for i in range(20):
        update(i)
    t = time.perf_counter()
    for i in range(n):
        update(i)
    return (time.perf_counter() - t) / n


def _bytes_per_update(url: str, update, n: int = 100) -> float:
    client = SceneClient(url)
    time.sleep(2.0)  # initial scene
    start = client.bytes_received
    for i in range(n):
        update(i)
        time.sleep(0.02)  # let each update go out as its own websocket message
    time.sleep(1.0)
    sent = client.bytes_received - start
    client.close()
    return sent / n


def bench_urdftk(path: str) -> tuple[float, float]:
    import urdftk
    from urdftk.viewer import Viewer

    robot = urdftk.load(path)
    joint = "arm_left_4_joint"
    with Viewer(robot, port=0) as viewer:
        viewer.refresh()

        def update(i: int) -> None:
            viewer.set_joint_positions({joint: -0.5 + 0.4 * np.sin(0.05 * i)})
            viewer._refresh(viewer._take_edges(full=False))  # what the render thread does after a /tf

        # measure without the render thread racing us
        viewer._closed = True
        viewer._wake.set()
        viewer._thread.join()
        dt = _per_update(update)
        nbytes = _bytes_per_update(viewer.url, update)
        viewer._closed = False
    return dt, nbytes


def bench_viserurdf(path: str) -> tuple[float, float]:
    import viser
    import yourdfpy
    from viser.extras import ViserUrdf

    from urdftk.resources import PackageResolver

    r = PackageResolver(source=path)
    urdf = yourdfpy.URDF.load(
        path, filename_handler=lambda fname: str(r.resolve(fname.replace("package:///", "package://")))
    )
    server = viser.ViserServer(host="127.0.0.1", port=free_port(), verbose=False)
    vu = ViserUrdf(server, urdf)
    names = list(vu.get_actuated_joint_names())
    k = names.index("arm_left_4_joint")
    q = np.zeros(len(names))

    def update(i: int) -> None:
        q[k] = -0.5 + 0.4 * np.sin(0.05 * i)
        vu.update_cfg(q)

    dt = _per_update(update, 100)
    nbytes = _bytes_per_update(f"http://127.0.0.1:{server.get_port()}/", update)
    server.stop()
    return dt, nbytes


def bench_pinocchio(path: str) -> tuple[float, float]:
    import pinocchio as pin
    import viser
    from pinocchio.visualize import ViserVisualizer

    from urdftk.resources import PackageResolver

    share = str(PackageResolver().find("example-robot-data").parent)
    model, cm, vm = pin.buildModelsFromUrdf(path, package_dirs=[share])
    server = viser.ViserServer(host="127.0.0.1", port=free_port(), verbose=False)
    viz = ViserVisualizer(model, cm, vm)
    viz.initViewer(viewer=server)
    viz.loadViewerModel()
    q = pin.neutral(model)
    k = model.joints[model.getJointId("arm_left_4_joint")].idx_q

    def update(i: int) -> None:
        q[k] = -0.5 + 0.4 * np.sin(0.05 * i)
        viz.display(q)

    dt = _per_update(update, 100)
    nbytes = _bytes_per_update(f"http://127.0.0.1:{server.get_port()}/", update)
    server.stop()
    return dt, nbytes


def main() -> None:
    path = talos_path()
    rows = []
    for name, fn in (
        ("urdftk view", bench_urdftk),
        ("viser ViserUrdf", bench_viserurdf),
        ("pin ViserVisualizer", bench_pinocchio),
    ):
        dt, nbytes = fn(path)
        rows.append((name, dt, nbytes))
    port = free_port()
    t_ours = time_to_visible([sys.executable, "-m", "urdftk", "view", path, "--port", str(port)], port)
    port = free_port()
    t_vu = time_to_visible(baseline_script("viserurdf", path, port), port)
    port = free_port()
    t_pin = time_to_visible(baseline_script("pinocchio", path, port), port)
    visible = {"urdftk view": t_ours, "viser ViserUrdf": t_vu, "pin ViserVisualizer": t_pin}
    print(f"Talos ({path}), one joint (arm_left_4_joint) moved per update, {N_UPDATES} updates")
    print(f"{'':22s} {'ms/update':>10s} {'bytes/update':>13s} {'s to visible':>13s}")
    for name, dt, nbytes in rows:
        print(f"{name:22s} {dt * 1e3:10.3f} {nbytes:13.0f} {visible[name]:13.2f}")
    ours = rows[0]
    for name, dt, nbytes in rows[1:]:
        print(
            f"ratio {name} / urdftk: time per update x{dt / ours[1]:.1f}, "
            f"bytes per update x{nbytes / ours[2]:.1f}, "
            f"time to visible x{visible[name] / visible['urdftk view']:.2f}"
        )


if __name__ == "__main__":
    main()
