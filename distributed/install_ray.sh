#!/usr/bin/env bash
# Installs Ray, the engine distributed/octsolid_ray.py runs sharded jobs on, into a
# virtual environment of its own: .venv-ray/ at the repository's top (gitignored),
# from PyPI at a pinned version. The driver script and tests/distributed.rs use
# .venv-ray/bin/python. Idempotent: does nothing when that version is there.
# Every machine of a cluster needs the same Ray version (and Python minor version).
set -euo pipefail
RAY_VERSION=2.60.0
cd "$(dirname "$0")/.."
venv=.venv-ray
if [ -x "$venv/bin/python" ] &&
  "$venv/bin/python" -c "import ray, sys; sys.exit(ray.__version__ != '$RAY_VERSION')" 2>/dev/null; then
  exit 0
fi
python3 -m venv "$venv"
"$venv/bin/python" -m pip install --quiet --disable-pip-version-check "ray==$RAY_VERSION"
"$venv/bin/python" -c "import ray; print('Ray', ray.__version__, 'in $venv')"
