"""Load-time benchmark: urdftk.load vs raw Pinocchio, yourdfpy and check_urdf, measured in the same run.

Run: ``python bench/load.py``. Robots: Panda, Talos (example-robot-data) and a generated 1000-link
revolute chain. ``urdftk.load`` = safe XML parse + structure checks + yourdfpy (no meshes) + Pinocchio.
check_urdf (urdfdom's tool; Debian package liburdfdom-tools) is timed as a subprocess when installed.
"""

from __future__ import annotations

import io
import shutil
import subprocess
import tempfile
import time
import warnings
from pathlib import Path

import pinocchio as pin
import yourdfpy

import urdftk
from urdftk.resources import PackageResolver


def best_of(fn, repeat: int = 5) -> float:
    best = float("inf")
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - t0)
    return best


def chain_text(n: int) -> str:
    links = "".join(f'<link name="l{i}"/>' for i in range(n + 1))
    joints = "".join(
        f'<joint name="j{i}" type="revolute"><parent link="l{i}"/><child link="l{i + 1}"/>'
        f'<origin xyz="0 0 0.1"/><axis xyz="0 1 0"/>'
        f'<limit lower="-1" upper="1" effort="1" velocity="1"/></joint>'
        for i in range(n)
    )
    return f'<robot name="chain{n}">{links}{joints}</robot>'


def main() -> None:
    warnings.simplefilter("ignore")
    robots = PackageResolver().find("example-robot-data") / "robots"
    check_urdf = shutil.which("check_urdf")
    with tempfile.TemporaryDirectory() as tmp:
        chain = Path(tmp) / "chain1000.urdf"
        chain.write_text(chain_text(1000))
        cases = [
            ("Panda", robots / "panda_description/urdf/panda.urdf"),
            ("Talos", robots / "talos_data/robots/talos_full_v2.urdf"),
            ("chain1000", chain),
        ]
        print(
            f"{'robot':10s} {'urdftk.load':>12s} {'pin.buildModelFromUrdf':>23s} "
            f"{'yourdfpy':>10s} {'check_urdf':>11s}  ratio"
        )
        for name, path in cases:
            data = path.read_bytes()
            # Best of 20 for both sides of the ratio: single runs swing 2x on a shared 2-core machine.
            t_load = best_of(lambda p=path: urdftk.load(p), 20)
            t_pin = best_of(lambda p=path: pin.buildModelFromUrdf(str(p)), 20)
            t_ydf = best_of(
                lambda d=data: yourdfpy.URDF.load(
                    io.BytesIO(d), build_scene_graph=False, load_meshes=False, load_collision_meshes=False
                ),
                3,
            )
            if check_urdf:
                t_chk = best_of(
                    lambda p=path: subprocess.run([check_urdf, str(p)], capture_output=True, check=False), 3
                )
                chk = f"{t_chk * 1e3:9.1f}ms"
            else:
                chk = "  (absent)"
            print(
                f"{name:10s} {t_load * 1e3:10.1f}ms {t_pin * 1e3:21.1f}ms {t_ydf * 1e3:8.1f}ms {chk}  "
                f"urdftk/pin {t_load / t_pin:5.1f}x, yourdfpy/pin {t_ydf / t_pin:5.1f}x"
            )
    if not check_urdf:
        print(
            "check_urdf not found: it ships with ROS or Debian's liburdfdom-tools "
            "(apt install liburdfdom-tools)"
        )


if __name__ == "__main__":
    main()
