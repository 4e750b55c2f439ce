#!/usr/bin/env bash
# Set up everything the test suite needs, then run it. This is the README's test command and what
# .ci/run runs. It is safe to run again: each step is skipped when already done.
#   1. a virtualenv in .venv with urdftk and its test extras (pip);
#   2. Debian packages the oracle and browser tests need: chromium (viewer tests), python3-tf2-ros
#      and python3-geometry-msgs (the real tf2 oracle), graphviz (`dot` for graph/frames output);
#   3. pytest over tests/. Extra arguments go to pytest.
# A missing prerequisite is an error, never a skipped test.
set -euo pipefail
cd "$(dirname "$0")/.."

PY=${PYTHON:-python3}
if [ ! -x .venv/bin/python ]; then
  "$PY" -m venv .venv
fi
.venv/bin/python -m pip install --quiet --upgrade pip
.venv/bin/python -m pip install --quiet -e '.[test]'
# An editable install has no bytecode; compile it once so that CLI start-up timings (and every
# subprocess the tests start) do not recompile the sources when PYTHONDONTWRITEBYTECODE is set.
.venv/bin/python -m compileall -q urdftk tf >/dev/null

need=()
[ -x /usr/bin/chromium ] || need+=(chromium)
command -v dot >/dev/null 2>&1 || need+=(graphviz)
/usr/bin/python3 -c 'import tf2_ros, geometry_msgs' >/dev/null 2>&1 || need+=(python3-tf2-ros python3-geometry-msgs)
if [ ${#need[@]} -gt 0 ]; then
  if [ "$(id -u)" = 0 ] && command -v apt-get >/dev/null 2>&1; then
    echo "tests/run.sh: installing Debian packages: ${need[*]}"
    apt-get update -qq
    DEBIAN_FRONTEND=noninteractive apt-get install -y -qq "${need[@]}" >/dev/null
  elif command -v sudo >/dev/null 2>&1 && command -v apt-get >/dev/null 2>&1; then
    echo "tests/run.sh: installing Debian packages with sudo: ${need[*]}"
    sudo apt-get update -qq
    sudo DEBIAN_FRONTEND=noninteractive apt-get install -y -qq "${need[@]}" >/dev/null
  else
    echo "tests/run.sh: error: these Debian packages are needed and cannot be installed here: ${need[*]}" >&2
    exit 2
  fi
fi

exec .venv/bin/python -m pytest -q "$@"
