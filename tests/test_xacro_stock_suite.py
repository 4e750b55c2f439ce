"""Stock xacro 2.1.1's own test suite (145 cases) against ``urdftk.xacro.compat``.

The sdist is fetched from PyPI with pip at test time into a cache folder (checked by sha256);
if it cannot be downloaded the test fails. A conftest maps ``import xacro`` to our compatibility
module and a ``xacro`` command on PATH runs our compatibility ``main`` (the suite calls it for
its command-line cases). ``$(find xacro)`` is resolved by urdftk through ROS_PACKAGE_PATH.
"""

from __future__ import annotations

import hashlib
import os
import shutil
import subprocess
import sys
import tarfile
from pathlib import Path
from xml.etree import ElementTree

import pytest

SDIST = "xacro-2.1.1.tar.gz"
SHA256 = "3e7adf33cdd90d9fbe8ca0d07d9118acf770a2ad8bf575977019a5c8a60d4d1b"
TEMPLATE = Path(__file__).resolve().parent / "xacro_stock_suite" / "conftest_template.py"
CACHE = Path(os.environ.get("XDG_CACHE_HOME", Path.home() / ".cache")) / "urdftk-tests" / "xacro-sdist"
EXPECTED_CASES = 145


def _sdist() -> Path:
    path = CACHE / SDIST
    if not (path.is_file() and hashlib.sha256(path.read_bytes()).hexdigest() == SHA256):
        CACHE.mkdir(parents=True, exist_ok=True)
        run = subprocess.run(
            [
                sys.executable,
                "-m",
                "pip",
                "download",
                "xacro==2.1.1",
                "--no-binary",
                ":all:",
                "--no-deps",
                "-d",
                str(CACHE),
            ],
            capture_output=True,
            text=True,
            timeout=240,
        )
        assert run.returncode == 0 and path.is_file(), (
            f"cannot download the xacro sdist:\n{run.stderr[-2000:]}"
        )
    assert hashlib.sha256(path.read_bytes()).hexdigest() == SHA256, "xacro sdist checksum mismatch"
    return path


@pytest.mark.timeout(400)
def test_stock_suite_passes_against_compat(tmp_path):
    with tarfile.open(_sdist()) as tar:
        tar.extractall(tmp_path, filter="data")
    src = tmp_path / "xacro-2.1.1"
    tests = src / "test"
    shutil.copy(TEMPLATE, tests / "conftest.py")
    (tests / "pytest.ini").write_text("[pytest]\n")
    bindir = tmp_path / "bin"
    bindir.mkdir()
    shim = bindir / "xacro"
    shim.write_text(f"#!{sys.executable}\nfrom urdftk.xacro.compat import main\nmain()\n")
    shim.chmod(0o755)
    env = {k: v for k, v in os.environ.items() if k != "AMENT_PREFIX_PATH"}
    env["PATH"] = f"{bindir}{os.pathsep}{env.get('PATH', '')}"
    env["ROS_PACKAGE_PATH"] = str(src)
    report = tmp_path / "report.xml"
    run = subprocess.run(
        [
            sys.executable,
            "-m",
            "pytest",
            "-p",
            "no:cacheprovider",
            "-q",
            f"--junitxml={report}",
            "test_xacro.py",
        ],
        cwd=tests,
        env=env,
        capture_output=True,
        text=True,
        timeout=380,
    )
    assert report.is_file(), run.stdout[-3000:] + run.stderr[-3000:]
    cases = list(ElementTree.parse(report).getroot().iter("testcase"))
    bad = [
        f"{c.get('classname')}.{c.get('name')}: {child.tag}: {(child.get('message') or '')[:300]}"
        for c in cases
        for child in c
        if child.tag in ("failure", "error", "skipped")
    ]
    assert not bad, "\n".join(bad) + "\n" + run.stdout[-3000:]
    assert len(cases) == EXPECTED_CASES, f"ran {len(cases)} cases, expected {EXPECTED_CASES}"
    assert run.returncode == 0, run.stdout[-3000:]
