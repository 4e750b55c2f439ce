"""The README's first two commands work verbatim, and .ci/run runs exactly the second one.

The first command is run for real: in a copy of the repository (the files git would ship), with
a brand-new virtualenv, exactly as the README writes it.
"""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]


def _readme_commands() -> list[str]:
    text = (REPO / "README.md").read_text(encoding="utf-8")
    return [b.strip() for b in re.findall(r"```bash\n(.*?)```", text, flags=re.S)][:2]


def _python_blocks() -> list[str]:
    text = (REPO / "README.md").read_text(encoding="utf-8")
    return re.findall(r"```python\n(.*?)```", text, flags=re.S)


def test_readme_python_examples_run(tmp_path):
    """Every Python block of the README runs as written, from the repository root."""
    blocks = _python_blocks()
    assert len(blocks) >= 2
    env = dict(os.environ, ROS_DOMAIN_ID=str(150 + os.getpid() % 50))
    env.pop("URDFTK_TRANSPORT", None)
    for block in blocks:
        proc = subprocess.run(
            [sys.executable, "-c", block], cwd=REPO, env=env, capture_output=True, text=True, timeout=300
        )
        assert proc.returncode == 0, block + "\n" + proc.stderr[-3000:]


def test_ci_runs_exactly_the_readme_test_command():
    _, test_cmd = _readme_commands()
    lines = [
        ln.strip()
        for ln in (REPO / ".ci" / "run").read_text().splitlines()
        if ln.strip() and not ln.startswith("#")
    ]
    assert lines[-1] == test_cmd


def _shipped_files() -> list[str]:
    out = subprocess.run(
        ["git", "ls-files", "--cached", "--others", "--exclude-standard", "-z"],
        cwd=REPO,
        capture_output=True,
        check=True,
    ).stdout.decode()
    return [f for f in out.split("\0") if f and (REPO / f).is_file()]


def test_first_readme_command_in_a_fresh_venv(tmp_path):
    setup_cmd, _ = _readme_commands()
    assert setup_cmd.startswith("python3 -m venv .venv")
    clone = tmp_path / "urdftk"
    for rel in _shipped_files():
        dest = clone / rel
        dest.parent.mkdir(parents=True, exist_ok=True)
        shutil.copy2(REPO / rel, dest)
    env = {k: v for k, v in os.environ.items() if k not in ("VIRTUAL_ENV", "PYTHONPATH", "ROS_PACKAGE_PATH")}
    # "python3" as a user types it: the interpreter running these tests, first on PATH.
    shim = tmp_path / "bin"
    shim.mkdir()
    base_python = getattr(sys, "_base_executable", sys.executable)
    (shim / "python3").symlink_to(base_python)
    env["PATH"] = f"{shim}{os.pathsep}{env.get('PATH', '')}"
    proc = subprocess.run(
        ["bash", "-c", setup_cmd], cwd=clone, env=env, capture_output=True, text=True, timeout=900
    )
    assert proc.returncode == 0, proc.stdout[-2000:] + proc.stderr[-4000:]
    assert "robot name is: mobile_manipulator" in proc.stdout
    assert "Traceback" not in proc.stderr
