"""``urdftk check`` on the adversarial files in tests/data/bad.

Each file marks what it must produce with comments on the line of the faulty element, e.g.
``<joint ...> <!-- expect error:missing-limit -->``; the findings must be exactly those (code,
severity and line). Files that cannot be read at all are listed in ``UNREADABLE``. urdfdom itself
(bundled in Pinocchio's wheel) is the oracle for "this file is broken": whenever urdfdom refuses a
file, ``check`` must report an error too.
"""

from __future__ import annotations

import re
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

from urdftk.check import check
from urdftk.cli import main
from urdftk.errors import UrdftkError

BAD = Path(__file__).resolve().parent / "data" / "bad"
EXPECT = re.compile(r"<!--\s*expect\s+([^>]*?)\s*-->")
UNREADABLE = {
    "billion_laughs.urdf": "DOCTYPE",
    "external_entity.urdf": "DOCTYPE",
    "utf16_entity.urdf": "entity",
    "utf16_internal_entity.urdf": "DOCTYPE",
    "malformed.urdf": "malformed XML",
    "empty.urdf": "malformed XML",
    "binary_garbage.urdf": "malformed XML",
}
CLEAN = {"zero_mass_fixed_ok.urdf"}
ALL_FILES = sorted(p.name for p in BAD.glob("*.urdf"))


def _expected(path: Path) -> set[tuple[str, str, int]]:
    out = set()
    for lineno, line in enumerate(path.read_text(encoding="utf-8").splitlines(), start=1):
        for match in EXPECT.finditer(line):
            for item in match.group(1).split():
                severity, code = item.split(":")
                out.add((severity, code, lineno))
    return out


def _expected_list(path: Path) -> list[tuple[str, str, int]]:
    out = []
    for lineno, line in enumerate(path.read_text(encoding="utf-8").splitlines(), start=1):
        for match in EXPECT.finditer(line):
            out.extend((*item.split(":"), lineno) for item in match.group(1).split())
    return sorted(out)


def test_every_bad_file_is_classified():
    assert len(ALL_FILES) >= 40
    for name in ALL_FILES:
        if name in UNREADABLE or name in CLEAN:
            continue
        assert _expected(BAD / name), f"{name} has no '<!-- expect ... -->' annotation"


@pytest.mark.parametrize("name", [n for n in ALL_FILES if n not in UNREADABLE])
def test_findings_match_annotations(name):
    report = check(BAD / name)
    got = sorted((f.severity, f.code, f.line) for f in report.findings)
    assert got == _expected_list(BAD / name), "\n".join(
        f"{f.line}: {f.severity} [{f.code}] {f.element}: {f.message}" for f in report.findings
    )
    for f in report.findings:
        assert f.element and f.message and f.line is not None
    assert report.ok == all(sev != "error" for sev, _, _ in got)


@pytest.mark.parametrize("name", sorted(UNREADABLE))
def test_unreadable_files_raise_with_location(name):
    with pytest.raises(UrdftkError) as info:
        check(BAD / name)
    text = str(info.value)
    assert UNREADABLE[name].lower() in text.lower()
    assert name in text


_URDFDOM_CHILD = textwrap.dedent(
    """
    import sys, pinocchio as pin
    for path in sys.argv[1:]:
        try:
            pin.buildModelFromXML(open(path, "rb").read().decode("utf-8"))
            verdict = "accept"
        except Exception:
            verdict = "refuse"
        print(verdict, path, flush=True)
    """
)


def _urdfdom_verdicts(paths: list[Path]) -> dict[str, bool]:
    """Ask urdfdom (inside Pinocchio), in child processes, which files it refuses (True = refused).

    urdfdom hangs or crashes on some inputs (a joint that is its own parent): the file a child was
    on when it died or timed out counts as refused, and a new child takes the rest.
    """
    verdicts: dict[str, bool] = {}
    todo = [str(p) for p in paths]
    while todo:
        try:
            proc = subprocess.run(
                [sys.executable, "-c", _URDFDOM_CHILD, *todo], capture_output=True, text=True, timeout=30
            )
            out = proc.stdout
        except subprocess.TimeoutExpired as exc:
            out = exc.stdout.decode() if isinstance(exc.stdout, bytes) else (exc.stdout or "")
        for line in out.splitlines():
            verdict, path = line.split(" ", 1)
            verdicts[Path(path).name] = verdict == "refuse"
        done = {Path(p).name for p in todo} & set(verdicts)
        rest = [p for p in todo if Path(p).name not in done]
        if rest:
            verdicts[Path(rest[0]).name] = True  # the child died or hung on this one
            rest = rest[1:]
        todo = rest
    return verdicts


@pytest.fixture(scope="module")
def urdfdom_refuses() -> dict[str, bool]:
    return _urdfdom_verdicts([BAD / n for n in ALL_FILES])


@pytest.mark.parametrize("name", ALL_FILES)
def test_what_urdfdom_refuses_is_an_error(name, urdfdom_refuses):
    if not urdfdom_refuses[name]:
        return
    try:
        report = check(BAD / name)
    except UrdftkError:
        return  # refused outright (exit 2)
    assert not report.ok, f"urdfdom refuses {name} but check reports {report.codes()}"


def test_urdfdom_oracle_refuses_some_and_accepts_some(urdfdom_refuses):
    assert urdfdom_refuses["two_roots.urdf"] and urdfdom_refuses["missing_limit.urdf"]
    assert not urdfdom_refuses["zero_mass_fixed_ok.urdf"]
    assert sum(urdfdom_refuses.values()) >= 15


def test_package_not_found_lists_every_search_place(tmp_path, monkeypatch):
    ros = tmp_path / "ros_ws"
    ros.mkdir()
    monkeypatch.setenv("ROS_PACKAGE_PATH", str(ros))
    report = check(BAD / "mesh_missing_package.urdf", package_paths=[tmp_path])
    (finding,) = report.findings
    assert finding.code == "package-not-found"
    assert "no_such_description_pkg" in finding.message
    assert f"-p {tmp_path.resolve()}" in finding.message
    assert f"ROS_PACKAGE_PATH {ros}" in finding.message
    assert "installed packages in" in finding.message


def test_missing_package_reported_once_in_full(tmp_path):
    text = (
        "<robot name='r'><link name='base'>"
        + "".join(
            f"\n<visual><geometry><mesh filename='package://nopkg_xyz/m{i}.stl'/></geometry></visual>"
            for i in range(3)
        )
        + "\n</link></robot>"
    )
    report = check(text)
    assert [f.code for f in report.findings] == ["package-not-found"] * 3
    assert "Searched:" in report.findings[0].message
    assert all("see line 2" in f.message for f in report.findings[1:])


def test_no_meshes_skips_loading_but_not_existence():
    report = check(BAD / "mesh_unloadable.urdf", load_meshes=False)
    assert report.findings == []
    report = check(BAD / "mesh_missing_file.urdf", load_meshes=False)
    assert report.codes() == ["mesh-not-found", "mesh-not-found"]


def test_bad_uri_three_slashes_says_how_to_fix():
    report = check(BAD / "bad_uri.urdf")
    by_code = {f.code: f for f in report.findings if f.line == 5}
    assert by_code["bad-uri"].severity == "warning"
    assert "write 'package://pkg/meshes/a.stl'" in by_code["bad-uri"].message
    assert "'pkg' not found" in by_code["package-not-found"].message
    assert any("http://" in f.message for f in report.findings if f.line == 6)


# --- the command line -----------------------------------------------------------------------------


def _cli(*argv: str, timeout: float = 60) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, "-m", "urdftk", *argv], capture_output=True, text=True, timeout=timeout, cwd=BAD
    )


@pytest.mark.parametrize(
    ("name", "status"),
    [
        ("cycle.urdf", 1),
        ("two_roots.urdf", 1),
        ("nan_anywhere.urdf", 1),
        ("mesh_unloadable.urdf", 1),
        ("mimic_chain.urdf", 0),
        ("non_unit_axis.urdf", 0),
        ("zero_mass_fixed_ok.urdf", 0),
        ("not_robot.urdf", 1),
        ("billion_laughs.urdf", 2),
        ("external_entity.urdf", 2),
        ("malformed.urdf", 2),
        ("empty.urdf", 2),
        ("binary_garbage.urdf", 2),
        ("utf16_internal_entity.urdf", 2),
        ("no_such_file.urdf", 2),
    ],
)
def test_cli_exit_status_and_no_traceback(name, status):
    proc = _cli("check", name)
    assert proc.returncode == status, proc.stdout + proc.stderr
    assert "Traceback" not in proc.stderr and "Traceback" not in proc.stdout
    if status == 2:
        assert proc.stdout == ""
        assert len(proc.stderr.strip().splitlines()) == 1
        assert proc.stderr.startswith("urdftk check: error: ")
    else:
        assert proc.stderr == ""
        lines = proc.stdout.splitlines()
        assert lines[-1].startswith(f"{name}: ")
        for sev, code, line in _expected(BAD / name):
            assert any(ln.startswith(f"{name}:{line}: {sev}: [{code}] ") for ln in lines), (code, line)


def test_cli_json_is_stable_schema():
    import json

    proc = _cli("check", "missing_limit.urdf", "--format", "json")
    assert proc.returncode == 1
    data = json.loads(proc.stdout)
    assert set(data) == {
        "schema",
        "file",
        "expanded",
        "robot",
        "root",
        "roots",
        "tree",
        "findings",
        "counts",
        "ok",
    }
    assert data["schema"] == "urdftk-check/1"
    assert data["robot"] == "missing_limit" and data["root"] == "base" and data["ok"] is False
    assert data["tree"][0] == {"link": "base", "parent": None, "joint": None, "depth": 0}
    assert [e["link"] for e in data["tree"]] == ["base", "a", "b", "c"]
    assert data["counts"] == {"error": 4, "warning": 0}
    for f in data["findings"]:
        assert set(f) == {"severity", "code", "element", "line", "message"}
        assert f["severity"] in ("error", "warning") and isinstance(f["line"], int)
    assert [f["code"] for f in data["findings"]] == [
        "missing-limit",
        "missing-limit",
        "missing-limit-attribute",
        "missing-limit-attribute",
    ]


def test_cli_rejects_stray_arguments(capsys):
    assert main(["check", str(BAD / "cycle.urdf"), "extra"]) == 2
    assert "name:=value" in capsys.readouterr().err


# --- hostile inputs: entities, FIFOs, deep chains ------------------------------------------------


def test_external_entity_is_never_read(tmp_path):
    marker = (BAD / "secret_marker.txt").read_text().strip()
    proc = _cli("check", "external_entity.urdf", "--format", "json")
    assert proc.returncode == 2
    assert marker not in proc.stdout + proc.stderr
    assert "DOCTYPE" in proc.stderr


@pytest.mark.timeout(30)
def test_external_entity_pointing_at_a_fifo_returns_at_once(tmp_path):
    import os
    import time

    fifo = tmp_path / "pipe"
    os.mkfifo(fifo)
    robot = tmp_path / "fifo.urdf"
    robot.write_text(
        f'<?xml version="1.0"?>\n<!DOCTYPE robot [<!ENTITY x SYSTEM "file://{fifo}">]>\n'
        '<robot name="r"><link name="&x;"/></robot>\n'
    )
    start = time.monotonic()
    proc = subprocess.run(
        [sys.executable, "-m", "urdftk", "check", str(robot)], capture_output=True, text=True, timeout=20
    )
    assert time.monotonic() - start < 10  # reading the FIFO would block until the timeout
    assert proc.returncode == 2 and "DOCTYPE" in proc.stderr


@pytest.mark.timeout(30)
def test_billion_laughs_is_rejected_fast():
    import time

    start = time.monotonic()
    with pytest.raises(UrdftkError, match="DOCTYPE"):
        check(BAD / "billion_laughs.urdf")
    assert time.monotonic() - start < 2


def _chain(n: int) -> str:
    parts = ['<robot name="chain">', '<link name="l0"/>']
    for i in range(1, n):
        parts.append(f'<link name="l{i}"/>')
        parts.append(
            f'<joint name="j{i}" type="fixed"><parent link="l{i - 1}"/><child link="l{i}"/>'
            '<origin xyz="0 0 0.01"/></joint>'
        )
    parts.append("</robot>")
    return "\n".join(parts)


@pytest.mark.timeout(60)
def test_ten_thousand_link_chain_is_rejected_quickly(tmp_path):
    import time

    path = tmp_path / "chain.urdf"
    path.write_text(_chain(10_000))
    start = time.monotonic()
    proc = subprocess.run(
        [sys.executable, "-m", "urdftk", "check", str(path), "--format", "json"],
        capture_output=True,
        text=True,
        timeout=30,
    )
    assert time.monotonic() - start < 5
    assert proc.returncode == 1 and "Traceback" not in proc.stderr
    import json

    data = json.loads(proc.stdout)
    assert [f["code"] for f in data["findings"]] == ["too-deep"]
    assert data["root"] == "l0" and data["tree"] == []


def test_chain_within_the_limit_prints_its_whole_tree():
    report = check(_chain(500))
    assert report.ok and len(report.tree) == 500
    assert report.tree[-1] == type(report.tree[-1])("l499", "l498", "j499", 499)


@pytest.mark.parametrize("name", [n for n in ALL_FILES if n not in UNREADABLE and n != "not_robot.urdf"])
def test_what_the_loader_refuses_is_an_error(name):
    from urdftk.description import structure_errors
    from urdftk.tree import read_tree
    from urdftk.xmlsafe import parse_xml

    root = parse_xml((BAD / name).read_bytes(), name)
    if structure_errors(root, read_tree(root)):
        assert not check(BAD / name).well_formed


def test_public_names_are_importable():
    import importlib

    for module in (
        "urdftk.check",
        "urdftk.graph",
        "urdftk._read",
        "urdftk.lint",
        "urdftk.lint._base",
        "urdftk.lint.structure",
        "urdftk.lint.numbers",
        "urdftk.lint.limits",
        "urdftk.lint.mimic",
        "urdftk.lint.physics",
        "urdftk.lint.geometry",
        "urdftk.lint.materials",
        "urdftk.lint.meshes",
        "urdftk.cli.cmd_check",
        "urdftk.cli.cmd_graph",
    ):
        mod = importlib.import_module(module)
        assert len(set(mod.__all__)) == len(mod.__all__), module  # order: ruff RUF022
        for name in mod.__all__:
            assert hasattr(mod, name), (module, name)
