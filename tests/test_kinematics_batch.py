"""Batched FK: both backends, both dtypes, link subsets, ``out=``, errors; the kernel's sin/cos."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest
from _kinematics_oracle import erd_urdfs, raw_pin_poses

import urdftk
from urdftk._fk_numba import sincos
from urdftk.errors import ConfigurationError, LinkNotFound


@pytest.fixture(scope="module")
def talos():
    return urdftk.load(next(p for p in erd_urdfs() if p.name == "talos_full_v2.urdf"))


@pytest.mark.parametrize("backend", ["numba", "numpy"])
def test_batch_agrees_with_pinocchio_f64_and_f32(talos, backend):
    rng = np.random.default_rng(0)
    Q = np.array([talos.random(rng) for _ in range(300)])
    expected = np.array([raw_pin_poses(talos, q) for q in Q[:30]])
    f64 = talos.fk_batch(Q, backend=backend)
    f32 = talos.fk_batch(Q, dtype=np.float32, backend=backend)
    assert f64.shape == (300, len(talos.link_names), 4, 4) and f32.dtype == np.float32
    assert np.abs(f64[:30, :, :3, 3] - expected[:, :, :3, 3]).max() < 1e-12
    np.testing.assert_allclose(f64[:30], expected, atol=1e-12, rtol=0)
    assert np.abs(f32[:30, :, :3, 3] - expected[:, :, :3, 3]).max() < 1e-5
    np.testing.assert_allclose(f32, f64, atol=1e-5, rtol=0)


@pytest.mark.parametrize("backend", ["numba", "numpy"])
def test_links_subset_and_out(talos, backend):
    Q = np.array([talos.random(s) for s in range(50)])
    links = ["gripper_left_fingertip_3_link", "base_link", "arm_right_7_link"]
    out = np.full((50, 3, 4, 4), np.nan, dtype=np.float32)
    res = talos.fk_batch(Q, links=links, dtype=np.float32, out=out, backend=backend)
    assert res is out
    full = talos.fk_batch(Q)
    idx = [talos.link_names.index(n) for n in links]
    np.testing.assert_allclose(out, full[:, idx], atol=1e-5)


def test_empty_batch_and_bad_inputs(talos):
    assert talos.fk_batch(np.zeros((0, talos.dof))).shape == (0, len(talos.link_names), 4, 4)
    bad = [
        (lambda: talos.fk_batch(np.zeros((3, talos.dof + 1))), ConfigurationError, "shape"),
        (lambda: talos.fk_batch(np.full((3, talos.dof), np.nan)), ConfigurationError, "NaN"),
        (lambda: talos.fk_batch(np.zeros((3, talos.dof)), dtype=np.int32), ConfigurationError, "dtype"),
        (
            lambda: talos.fk_batch(np.zeros((3, talos.dof)), out=np.zeros((3, 1, 4, 4))),
            ConfigurationError,
            "out",
        ),
        (
            lambda: talos.fk_batch(np.zeros((3, talos.dof)), links=["base_link", "base_link"]),
            ConfigurationError,
            "once",
        ),
        (lambda: talos.fk_batch(np.zeros((3, talos.dof)), links=["base_lnk"]), LinkNotFound, "base_link"),
        (lambda: talos.fk_batch(np.zeros((3, talos.dof)), backend="gpu"), ValueError, "backend"),
    ]
    for call, exc, match in bad:
        with pytest.raises(exc, match=match):
            call()


def test_sincos_kernel_matches_libm():
    rng = np.random.default_rng(0)
    x = np.concatenate(
        [rng.uniform(-7, 7, 200_000), rng.uniform(-1e5, 1e5, 100_000), [1e16, -1e9, 0.0, -0.0]]
    )
    x = np.concatenate([x, np.arange(-64, 65) * np.pi / 4])
    s, c = np.empty_like(x), np.empty_like(x)
    sincos(x, s, c, len(x))
    assert np.abs(s - np.sin(x)).max() < 1e-15 and np.abs(c - np.cos(x)).max() < 1e-15


def test_pin_model_is_built_without_mimic(talos):
    assert talos.model.nq == talos.dof + len(talos.mimic)
    assert isinstance(talos.model, pin.Model)
