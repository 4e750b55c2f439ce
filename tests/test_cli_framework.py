"""The CLI dispatcher: every subcommand is reachable, and errors are one line with exit 2."""

from __future__ import annotations

import argparse
import importlib
import pkgutil
import subprocess
import sys

import urdftk.cli as cli


def _registered(module: str) -> set[str]:
    parser = argparse.ArgumentParser()
    sub = parser.add_subparsers()
    importlib.import_module(f"urdftk.cli.{module}").register(sub)
    return set(sub.choices)


def test_command_table_matches_the_cmd_modules():
    modules = sorted(m.name for m in pkgutil.iter_modules(cli.__path__) if m.name.startswith("cmd_"))
    from_modules = {cmd: m for m in modules for cmd in _registered(m)}
    assert from_modules == cli.COMMANDS


def test_help_lists_every_command():
    out = subprocess.run(
        [sys.executable, "-m", "urdftk", "--help"], capture_output=True, text=True, check=True
    )
    for cmd in cli.COMMANDS:
        assert cmd in out.stdout


def test_unknown_command_is_one_line_exit_2():
    proc = subprocess.run([sys.executable, "-m", "urdftk", "frobnicate"], capture_output=True, text=True)
    assert proc.returncode == 2
    assert "Traceback" not in proc.stderr
    assert len(proc.stderr.strip().splitlines()) == 1


def test_xacro_start_imports_only_its_module():
    code = (
        "import sys; from urdftk.cli import _build_parser; _build_parser('xacro'); "
        "print(sorted(m for m in sys.modules if m.startswith('urdftk.cli.cmd_')))"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.strip() == "['urdftk.cli.cmd_xacro']"
