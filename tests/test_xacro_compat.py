"""The stock-compatible API (``urdftk.xacro.compat``) and the public module surface."""

from __future__ import annotations

import importlib
import json
import os
from pathlib import Path

import pytest

import urdftk.xacro
from urdftk.xacro import compat

CORPUS = Path(__file__).resolve().parents[2] / "shared" / "corpus" / "xacro"
CASES = [c for c in json.loads((CORPUS / "manifest.json").read_text())["cases"] if not c["args"]][::40]


@pytest.mark.parametrize("case", CASES, ids=[c["id"] for c in CASES])
def test_process_file_document_prints_like_stock(case, monkeypatch):
    monkeypatch.chdir(CORPUS)
    monkeypatch.setenv("ROS_PACKAGE_PATH", str(CORPUS / case["input"].split("/")[0]))
    monkeypatch.delenv("AMENT_PREFIX_PATH", raising=False)
    expected = (CORPUS / case["expected"]).read_text().replace("{corpus}", str(CORPUS))
    with open(os.devnull, "w") as quiet:
        monkeypatch.setattr("sys.stderr", quiet)
        doc = compat.process_file(case["input"])
    assert doc.toprettyxml(indent="  ") == expected


def test_exception_messages_are_stock_like():
    with pytest.raises(compat.XacroException) as info:
        compat.process_doc(compat.parse('<a xmlns:xacro="x"><xacro:property name="__hidden"/></a>'))
    assert str(info.value) == "Property names must not start with double underscore:__hidden"


@pytest.mark.parametrize(
    "name",
    ["urdftk.xacro", "urdftk.xacro.compat", "urdftk.xacro.compat_cli", "urdftk.cli.cmd_xacro"]
    + [
        f"urdftk.xacro.{m}"
        for m in (
            "_context",
            "_eval",
            "_lexer",
            "_macros",
            "_output",
            "_processor",
            "_scope",
            "_subst",
            "_symbols",
            "_tags",
            "_tree",
            "_yaml",
        )
    ],
)
def test_all_is_complete_and_importable(name):
    module = importlib.import_module(name)
    assert len(set(module.__all__)) == len(module.__all__)  # order: ruff RUF022
    for attr in module.__all__:
        assert hasattr(module, attr), f"{name}.{attr}"


def test_public_api():
    assert urdftk.xacro.__all__ == ["Result", "expand", "process_file", "process_string"]
