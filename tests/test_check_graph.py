"""``urdftk graph``: urdf_to_graphviz's picture, checked by Graphviz itself.

The .gv text is read back by ``dot -Tjson0`` (the oracle for what the DOT text means): every link
must be a box node, every joint an ellipse, and every parent -> joint edge labelled with the joint
origin. A robot name carrying shell and DOT syntax must execute nothing and come back verbatim.
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
from lxml import etree

from urdftk.graph import dot_string, to_dot
from urdftk.lint._base import parse_numbers
from urdftk.resources import PackageResolver
from urdftk.tree import read_tree
from urdftk.xmlsafe import parse_xml

ROBOT0 = (
    Path(__file__).resolve().parents[1]
    / "examples"
    / "robots"
    / "robot0_description"
    / "urdf"
    / "robot0.urdf"
)
PANDA = PackageResolver().find("example-robot-data") / "robots" / "panda_description" / "urdf" / "panda.urdf"
DOT = shutil.which("dot")


def _cli(*argv: str, cwd: Path, env: dict | None = None) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, "-m", "urdftk", "graph", *argv],
        capture_output=True,
        text=True,
        cwd=cwd,
        env=env,
        timeout=60,
    )


def _graphviz_json(gv: str) -> dict:
    assert DOT, "Graphviz `dot` is required (apt-get install graphviz)"
    proc = subprocess.run([DOT, "-Tjson0"], input=gv, capture_output=True, text=True, timeout=60, check=True)
    return json.loads(proc.stdout)


def _unescape(label: str) -> str:
    out, i = [], 0
    while i < len(label):
        if label[i] == "\\" and i + 1 < len(label):
            nxt = label[i + 1]
            out.append({"n": "\n", "\\": "\\"}.get(nxt, "\\" + nxt))
            i += 2
        else:
            out.append(label[i])
            i += 1
    return "".join(out)


def _check_picture(urdf: Path, gv: str) -> None:
    tree = read_tree(parse_xml(urdf.read_bytes(), str(urdf)))
    graph = _graphviz_json(gv)
    nodes = {o["_gvid"]: o for o in graph["objects"]}
    boxes = {_unescape(o["label"]): o for o in nodes.values() if o["shape"] == "box"}
    ellipses = {_unescape(o["label"]): o for o in nodes.values() if o["shape"] == "ellipse"}
    assert set(boxes) == {link.name for link in tree.links}
    assert set(ellipses) == {j.name for j in tree.joints}
    assert len(nodes) == len(tree.links) + len(tree.joints)
    edges = {(e["tail"], e["head"]): e for e in graph["edges"]}
    assert len(edges) == 2 * len(tree.joints)
    for j in tree.joints:
        jid, pid, cid = ellipses[j.name]["_gvid"], boxes[j.parent]["_gvid"], boxes[j.child]["_gvid"]
        assert (jid, cid) in edges
        label = _unescape(edges[(pid, jid)]["label"])
        xyz_line, rpy_line = label.split("\n")
        origin = j.element.find("origin")
        want_xyz = parse_numbers(origin.get("xyz", "0 0 0")) if origin is not None else [0, 0, 0]
        want_rpy = parse_numbers(origin.get("rpy", "0 0 0")) if origin is not None else [0, 0, 0]
        assert xyz_line.startswith("xyz: ") and rpy_line.startswith("rpy: ")
        assert [float(v) for v in xyz_line[5:].split()] == pytest.approx(want_xyz, rel=1e-5, abs=1e-12)
        assert [float(v) for v in rpy_line[5:].split()] == pytest.approx(want_rpy, rel=1e-5, abs=1e-12)


@pytest.mark.parametrize("urdf", [ROBOT0, PANDA], ids=["robot0", "panda"])
def test_gv_has_links_as_boxes_joints_as_ellipses_and_origin_labels(urdf, tmp_path):
    proc = _cli(str(urdf), "-o", "out.gv", cwd=tmp_path)
    assert proc.returncode == 0, proc.stderr
    _check_picture(urdf, (tmp_path / "out.gv").read_text())


def test_stdout_without_output_option(tmp_path):
    proc = _cli(str(ROBOT0), cwd=tmp_path)
    assert proc.returncode == 0 and proc.stdout.startswith("digraph G {")
    _check_picture(ROBOT0, proc.stdout)
    assert list(tmp_path.iterdir()) == []


def test_svg_png_pdf_are_rendered(tmp_path):
    for suffix in ("svg", "png", "pdf"):
        proc = _cli(str(PANDA), "-o", f"panda.{suffix}", cwd=tmp_path)
        assert proc.returncode == 0, proc.stderr
    parser = etree.XMLParser(resolve_entities=False, no_network=True, load_dtd=False)
    svg = etree.parse(str(tmp_path / "panda.svg"), parser).getroot()
    assert svg.tag == "{http://www.w3.org/2000/svg}svg"
    texts = {t.text for t in svg.iter("{http://www.w3.org/2000/svg}text")}
    assert {"panda_link0", "panda_joint1", "panda_hand_tcp"} <= texts
    assert (tmp_path / "panda.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert (tmp_path / "panda.pdf").read_bytes()[:5] == b"%PDF-"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["panda.pdf", "panda.png", "panda.svg"]


EVIL = 'x"; touch PWNED1; $(touch PWNED2) `touch PWNED3` \\N \\" \' & < > -> y [label="z"]; }\n digraph { "'


def test_malicious_robot_name_executes_nothing_and_round_trips(tmp_path):
    name_attr = EVIL.replace("&", "&amp;").replace("<", "&lt;").replace('"', "&quot;").replace("\n", "&#10;")
    urdf = tmp_path / "evil.urdf"
    urdf.write_text(
        f'<robot name="{name_attr}"><link name="{name_attr}"/><link name="b"/>'
        f'<joint name="$(touch PWNED4)" type="fixed"><parent link="{name_attr}"/>'
        '<child link="b"/></joint></robot>'
    )
    for out in ("evil.gv", "evil.svg", "evil.pdf"):
        proc = _cli(str(urdf), "-o", out, cwd=tmp_path)
        assert proc.returncode == 0, proc.stderr
    assert not list(tmp_path.glob("PWNED*"))
    graph = _graphviz_json((tmp_path / "evil.gv").read_text())
    assert _unescape(graph["label"]) == EVIL
    labels = sorted(_unescape(o["label"]) for o in graph["objects"])
    assert labels == sorted([EVIL, "b", "$(touch PWNED4)"])
    parser = etree.XMLParser(resolve_entities=False, no_network=True, load_dtd=False)
    assert etree.parse(str(tmp_path / "evil.svg"), parser).getroot().tag.endswith("svg")


def test_dot_string_escapes_quotes_backslashes_and_newlines():
    assert dot_string('a"b') == '"a\\"b"'
    assert dot_string("a\\b") == '"a\\\\b"'
    assert dot_string("a\nb\r\nc") == '"a\\nb\\nc"'


def test_missing_dot_gives_one_line_with_install_hint(tmp_path):
    env = {**os.environ, "PATH": str(tmp_path / "empty_bin")}
    proc = _cli(str(ROBOT0), "-o", "r.svg", cwd=tmp_path, env=env)
    assert proc.returncode == 2
    assert len(proc.stderr.strip().splitlines()) == 1 and "Traceback" not in proc.stderr
    assert "apt-get install graphviz" in proc.stderr
    assert list(tmp_path.iterdir()) == []  # nothing half-written
    proc = _cli(str(ROBOT0), "-o", "r.gv", cwd=tmp_path, env=env)
    assert proc.returncode == 0 and (tmp_path / "r.gv").read_text().startswith("digraph G {")


def test_bad_suffix_and_unreadable_input_exit_2(tmp_path):
    proc = _cli(str(ROBOT0), "-o", "r.jpg", cwd=tmp_path)
    assert proc.returncode == 2 and "unknown output format '.jpg'" in proc.stderr
    bad = Path(__file__).resolve().parent / "data" / "bad"
    for name in ("billion_laughs.urdf", "malformed.urdf", "not_robot.urdf", "missing.urdf"):
        proc = _cli(str(bad / name), "-o", "x.gv", cwd=tmp_path)
        assert proc.returncode == 2 and "Traceback" not in proc.stderr
        assert len(proc.stderr.strip().splitlines()) == 1
    assert list(tmp_path.iterdir()) == []


def test_broken_structure_is_drawn_with_a_warning(tmp_path):
    bad = Path(__file__).resolve().parent / "data" / "bad"
    proc = _cli(str(bad / "dangling_child.urdf"), "-o", "d.gv", cwd=tmp_path)
    assert proc.returncode == 0 and "structural problem" in proc.stderr
    graph = _graphviz_json((tmp_path / "d.gv").read_text())
    ghost = next(o for o in graph["objects"] if o["label"].startswith("ghost"))
    assert ghost["shape"] == "box" and ghost["style"] == "dashed"


def test_to_dot_is_deterministic_and_follows_urdfdom_order():
    tree = read_tree(parse_xml(PANDA.read_bytes()))
    text = to_dot(tree)
    assert text == to_dot(tree)
    labels = [line.split('label="')[1].split('"')[0] for line in text.splitlines() if line.startswith("link")]
    assert labels[:3] == ["panda_link0", "panda_link1", "panda_link2"]
