"""Our expander against stock xacro 2.1.1 on 142 real robot descriptions (../shared/corpus/xacro).

The expected files are what stock xacro printed; every case must be byte-identical, in process
(through the public API) and through the ``urdftk xacro`` command line (the corpus checker).
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

from urdftk.xacro import expand

CORPUS = Path(__file__).resolve().parents[2] / "shared" / "corpus" / "xacro"
MANIFEST = json.loads((CORPUS / "manifest.json").read_text())
CASES = MANIFEST["cases"]
URDFTK = Path(sys.executable).with_name("urdftk")


def _env(case: dict) -> dict[str, str]:
    env = {k: v for k, v in os.environ.items() if k != "AMENT_PREFIX_PATH"}
    env["ROS_PACKAGE_PATH"] = str(CORPUS / case["input"].split("/")[0])
    return env


def _args(case: dict) -> list[str]:
    return [a.replace("{corpus}", str(CORPUS)) for a in case["args"]]


def _expected(case: dict) -> str:
    return (CORPUS / case["expected"]).read_text().replace("{corpus}", str(CORPUS))


def test_corpus_is_complete():
    assert len(CASES) == 142


@pytest.mark.parametrize("case", CASES, ids=[c["id"] for c in CASES])
def test_in_process_identical(case, monkeypatch):
    monkeypatch.chdir(CORPUS)
    monkeypatch.setenv("ROS_PACKAGE_PATH", _env(case)["ROS_PACKAGE_PATH"])
    monkeypatch.delenv("AMENT_PREFIX_PATH", raising=False)
    mappings = dict(a.split(":=", 1) for a in _args(case))
    with open(os.devnull, "w") as quiet:
        result = expand(case["input"], mappings, stderr=quiet)
    assert result.text == _expected(case)
    # every package the expansion resolved is one of the case's packages, at its folder
    for name, folder in result.packages.items():
        assert folder == CORPUS / case["packages"][name]


@pytest.mark.parametrize("case", CASES[::35], ids=[c["id"] for c in CASES[::35]])
def test_cli_identical(case):
    run = subprocess.run(
        [str(URDFTK), "xacro", case["input"], *_args(case)],
        cwd=CORPUS,
        env=_env(case),
        capture_output=True,
        text=True,
        timeout=60,
    )
    assert run.returncode == 0, run.stderr
    assert run.stdout == _expected(case)


@pytest.mark.timeout(300)
def test_corpus_checker_reports_all_identical():
    """The corpus's own checker, driving the installed ``urdftk xacro`` command on every case."""
    run = subprocess.run(
        [sys.executable, str(CORPUS / "check.py"), "--cmd", f"{URDFTK} xacro"],
        capture_output=True,
        text=True,
        timeout=290,
    )
    assert run.returncode == 0, run.stdout[-3000:] + run.stderr[-2000:]
    assert "cases 142  identical 142  equivalent 142  failed 0" in run.stdout
