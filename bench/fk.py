"""Kinematics benchmark: urdftk vs raw Pinocchio and pytorch_kinematics, measured in the same run.

Run: ``python bench/fk.py [--n 100000]``. Prints, for Panda and Talos (example-robot-data):

* ``frame_pose`` (one frame, numpy 4x4) vs raw Pinocchio (forwardKinematics + updateFramePlacement
  + ``.homogeneous``, and framesForwardKinematics + ``oMf[i].homogeneous``);
* ``fk`` (every link, one (n, 4, 4) array) vs raw ``framesForwardKinematics`` (compute only) and vs
  collecting every link through ``.homogeneous``;
* ``fk_batch`` throughput (numba and numpy backends, float64 and float32) vs the Pinocchio Python loop
  (compute only) and pytorch_kinematics on CPU with one thread.

Times are the best of several rounds of process CPU time (``time.process_time``): everything measured
is single-threaded, and CPU time does not count the time a loaded machine keeps the process waiting,
so ratios measured in the same run stay meaningful on a shared machine.
"""

from __future__ import annotations

import argparse
import time
import warnings
from pathlib import Path

import numpy as np
import pinocchio as pin

import urdftk
from urdftk.resources import PackageResolver


def best_of(fn, repeat: int = 5, number: int = 1) -> float:
    """Best CPU time per call (seconds) over ``repeat`` rounds of ``number`` calls."""
    best = float("inf")
    for _ in range(repeat):
        t0 = time.process_time()
        for _ in range(number):
            fn()
        best = min(best, (time.process_time() - t0) / number)
    return best


def bench_single(robot, q) -> None:
    model, data = robot.model, robot.model.createData()
    pq = robot._engine.pinmap().to_pin(q)  # the Pinocchio q of the same configuration
    link = robot.link_names[-1]
    fid = model.getFrameId(link, pin.BODY)
    body_ids = [model.getFrameId(n, pin.BODY) for n in robot.link_names]
    n = 20000
    t_ffk = best_of(lambda: pin.framesForwardKinematics(model, data, pq), number=n)
    t_raw_one = best_of(
        lambda: (
            pin.updateFramePlacement(model, data, fid).homogeneous
            if pin.forwardKinematics(model, data, pq) is None
            else None
        ),
        number=n,
    )
    t_raw_one_ffk = best_of(
        lambda: (pin.framesForwardKinematics(model, data, pq), data.oMf[fid].homogeneous), number=n
    )
    t_fp = best_of(lambda: robot.frame_pose(link, q), number=n)
    t_raw_all = best_of(
        lambda: (
            pin.framesForwardKinematics(model, data, pq),
            np.array([data.oMf[i].homogeneous for i in body_ids]),
        ),
        number=n // 10,
    )
    t_fk = best_of(lambda: robot.fk(q), number=n)
    us = 1e6
    print(
        f"  frame_pose          {t_fp * us:7.2f} us | raw fk+updateFramePlacement+homogeneous "
        f"{t_raw_one * us:6.2f} us "
        f"(overhead {(t_fp - t_raw_one) * us:+.2f} us) | raw ffk+oMf.homogeneous {t_raw_one_ffk * us:6.2f} us"
    )
    print(
        f"  fk (all {len(robot.link_names)} links) {t_fk * us:7.2f} us | "
        f"raw framesForwardKinematics {t_ffk * us:6.2f} us "
        f"(ratio {t_fk / t_ffk:.2f}x) | raw ffk + every .homogeneous {t_raw_all * us:6.2f} us"
    )


def bench_batch(robot, path, n: int) -> None:
    rng = np.random.default_rng(0)
    Q = np.array([robot.random(rng) for _ in range(min(n, 20000))])
    Q = np.resize(Q, (n, robot.dof))
    model, data = robot.model, robot.model.createData()
    pqs = [robot._engine.pinmap().to_pin(q) for q in Q[:20000]]

    def pin_loop():
        for pq in pqs:
            pin.framesForwardKinematics(model, data, pq)

    pin_rate = len(pqs) / best_of(pin_loop, repeat=5)
    print(
        f"  pinocchio python loop (framesForwardKinematics, compute only): {pin_rate / 1e3:8.0f} k configs/s"
    )
    robot.fk_batch(Q[:8], dtype=np.float32)
    robot.fk_batch(Q[:8])
    rates = {}
    for backend in ("numba", "numpy"):
        for dt in (np.float64, np.float32):
            out = np.zeros((n, len(robot.link_names), 4, 4), dtype=dt)
            t = best_of(
                lambda dt=dt, out=out, be=backend: robot.fk_batch(Q, dtype=dt, out=out, backend=be),
                repeat=5 if backend == "numba" else 2,
            )
            rates[(backend, dt)] = n / t
            print(
                f"  fk_batch {backend:5s} {np.dtype(dt).name:7s} N={n}: {n / t / 1e3:8.0f} k configs/s "
                f"= {n / t / pin_rate:5.2f}x pinocchio loop"
            )
    try:
        import pytorch_kinematics as pk
        import torch
    except ImportError as exc:
        print(f"  pytorch_kinematics: not installed ({exc}); pip install pytorch-kinematics torch==2.13.0")
        return
    torch.set_num_threads(1)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        chain = pk.build_chain_from_urdf(Path(path).read_bytes()).to(dtype=torch.float64)
    n_pk = min(n, 20000)
    th = torch.as_tensor(rng.uniform(-1, 1, size=(n_pk, len(chain.get_joint_parameter_names()))))
    chain.forward_kinematics(th[:8])
    t = best_of(lambda: chain.forward_kinematics(th), repeat=2)
    pk_rate = n_pk / t
    best = rates[("numba", np.float64)]
    print(
        f"  pytorch_kinematics CPU 1 thread float64 N={n_pk}: {pk_rate / 1e3:8.0f} k configs/s; "
        f"fk_batch numba f64 is {best / pk_rate:5.1f}x faster"
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n", type=int, default=100_000, help="batch size for fk_batch (default 100000)")
    args = parser.parse_args()
    robots = PackageResolver().find("example-robot-data") / "robots"
    for name, rel in [
        ("Panda", "panda_description/urdf/panda.urdf"),
        ("Talos", "talos_data/robots/talos_full_v2.urdf"),
    ]:
        path = robots / rel
        robot = urdftk.load(path)
        print(
            f"{name}: {len(robot.link_names)} links, dof {robot.dof} (+{len(robot.mimic)} mimic), "
            f"pin nq {robot.model.nq}"
        )
        q = robot.random(1)
        robot.fk(q)
        bench_single(robot, q)
        bench_batch(robot, path, args.n)


if __name__ == "__main__":
    main()
