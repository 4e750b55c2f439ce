"""Copied next to stock xacro's test_xacro.py: ``import xacro`` gets urdftk's compatibility module."""

import sys

from urdftk.xacro import compat

assert "xacro" not in sys.modules, "stock xacro was imported before the compatibility module"
sys.modules["xacro"] = compat
sys.modules["xacro.cli"] = compat.cli
