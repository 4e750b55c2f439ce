"""``xacro.load_yaml`` builds plain documents in one pass: the result must be PyYAML's, exactly.

Oracle: PyYAML's own construction with the same loader class, on every yaml file of the xacro
corpus and on documents with the features the one-pass builder leaves to PyYAML (merge keys,
unit tags, sets, timestamps, complex keys, wrong node kinds, recursive aliases).
"""

from __future__ import annotations

import math
from pathlib import Path

import pytest

from urdftk.xacro._yaml import _loader_class, load_yaml_text

CORPUS = Path(__file__).resolve().parents[2] / "shared" / "corpus" / "xacro"

CRAFTED = [
    "",
    "a: 1",
    "- 1\n- 2.5\n- yes\n- ~\n- '3'\n- 0x1f\n- 1e3\n- 1.0e3\n- .inf\n- .nan\n- 1:20\n- 0o17\n- 017",
    "a: &x {b: 1, c: [1, 2]}\nd: *x\ne: *x",
    "<<: {a: 1}\nb: 2",
    "base: &b {x: 1}\nderived:\n  <<: *b\n  y: 2",
    "a: !degrees 90\nb: !millimeters 5",
    "? [1, 2]\n: x",
    "s: !!set {a, b}",
    "t: 2001-12-14",
    "a: !!str 1\nb: !!float 1\nc: !!int '7'",
    "k: {1: a, 1.5: b, true: c, null: d, '1': e}",
    "dup: 1\ndup: 2",
    "a: = \n",
]


def _evaluate(text: str) -> float:
    return eval(text, {"pi": math.pi, "__builtins__": {}})  # the test's own stand-in evaluator


def _pyyaml(text: str):
    loader = _loader_class()(text)
    loader.xacro_evaluate = _evaluate
    try:
        return loader.get_single_data()
    finally:
        loader.dispose()


def _outcome(fn, text: str):
    try:
        return "ok", fn(text)
    except Exception as e:  # the error itself is compared
        return "error", type(e).__name__, str(e).split(":")[-1].strip()


def _same(a, b) -> bool:
    if isinstance(a, dict) and isinstance(b, dict):
        return list(a) == list(b) and all(_same(a[k], b[k]) for k in a)
    if isinstance(a, list) and isinstance(b, list):
        return len(a) == len(b) and all(_same(x, y) for x, y in zip(a, b, strict=True))
    if isinstance(a, float) and math.isnan(a):
        return isinstance(b, float) and math.isnan(b)
    return type(a) is type(b) and a == b


def _documents() -> list[str]:
    files = sorted(CORPUS.rglob("*.yaml"))
    assert len(files) > 100, f"the xacro corpus is missing at {CORPUS}"
    return [f.read_text() for f in files] + CRAFTED


def test_load_yaml_gives_pyyaml_results():
    checked = 0
    for text in _documents():
        expected = _outcome(_pyyaml, text)
        got = _outcome(lambda t: load_yaml_text(t, _evaluate, "f.yaml"), text)
        if expected[0] == "error":
            assert got[0] == "error", text  # (ours wraps it in a XacroError naming the file)
            continue
        assert got[0] == "ok" and _same(got[1], expected[1]), text
        checked += 1
    assert checked > 100


@pytest.mark.parametrize("text", ["a: &r [*r]", "a: &m {x: *m}"])
def test_recursive_aliases_stay_shared(text: str):
    data = load_yaml_text(text, _evaluate, "f.yaml")
    inner = dict.__getitem__(data, "a")
    first = list.__getitem__(inner, 0) if isinstance(inner, list) else dict.__getitem__(inner, "x")
    assert first is inner
    assert _pyyaml(text)  # PyYAML accepts it too
