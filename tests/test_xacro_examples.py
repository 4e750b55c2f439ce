"""examples/robots/**/*.xacro expand byte-identically with stock xacro 2.1.1 and with ours.

Stock resolves ``$(find pkg)`` only through ament_index_python, so it gets a real ament prefix
pointing at the example packages; ours finds them by crawling ``-p examples/robots``.
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest
from lxml import etree

from urdftk.xacro import expand

REPO = Path(__file__).resolve().parents[1]
EXAMPLES = REPO / "examples" / "robots"
STOCK = Path(sys.executable).with_name("xacro")
FILES = sorted(EXAMPLES.rglob("*.xacro"))
SAFE = etree.XMLParser(resolve_entities=False, no_network=True, load_dtd=False)


def test_examples_found():
    assert FILES, f"no .xacro files under {EXAMPLES}"


@pytest.fixture(scope="module")
def ament_prefix(tmp_path_factory: pytest.TempPathFactory) -> Path:
    prefix = tmp_path_factory.mktemp("ament")
    index = prefix / "share" / "ament_index" / "resource_index" / "packages"
    index.mkdir(parents=True)
    for manifest in EXAMPLES.rglob("package.xml"):
        name = etree.parse(str(manifest), SAFE).findtext("name").strip()
        (index / name).write_text("")
        (prefix / "share" / name).symlink_to(manifest.parent, target_is_directory=True)
    return prefix


@pytest.mark.parametrize("path", FILES, ids=[str(p.relative_to(EXAMPLES)) for p in FILES])
def test_example_identical_to_stock(path: Path, ament_prefix: Path):
    rel = str(path.relative_to(REPO))
    env = {k: v for k, v in os.environ.items() if k not in ("ROS_PACKAGE_PATH", "AMENT_PREFIX_PATH")}
    env["AMENT_PREFIX_PATH"] = str(ament_prefix)
    stock = subprocess.run([str(STOCK), rel], cwd=REPO, env=env, capture_output=True, text=True, timeout=60)
    assert stock.returncode == 0, stock.stderr
    cwd = os.getcwd()
    os.chdir(REPO)
    try:
        with open(os.devnull, "w") as quiet:
            ours = expand(rel, package_paths=[EXAMPLES], stderr=quiet)
    finally:
        os.chdir(cwd)
    # $(find) resolves to the package folder: stock's goes through the ament prefix's symlink
    text = stock.stdout.replace(str(ament_prefix / "share") + "/", "")
    ours_text = ours.text
    for name, folder in ours.packages.items():
        ours_text = ours_text.replace(str(folder), name)
    assert ours_text == text
