#!/usr/bin/env bash
# Installs what the tests need beyond cargo, from Debian's packages:
# - python3-openvdb (OpenVDB 10's Python module), which tests/formats.rs uses as an
#   independent reader of the .vdb files octsolid writes (tests/data/vdb_probe.py);
# - libembree-dev (Embree 3), the system library the harness's `embree` feature links
#   (tests/embree.rs, benches/embree.rs, `octsolid bench` with `--features embree`).
# - chromium, the headless browser tests/view_browser.rs drives over the DevTools
#   protocol (the viewer's page: orbit, section, screenshot);
# - python3-venv, when python3 cannot make a venv: distributed/install_ray.sh puts Ray
#   in one (tests/distributed.rs).
# Idempotent: installs only what is missing, and nothing when all is there. Needs root (apt).
set -euo pipefail
missing=()
if ! /usr/bin/python3 -c "import pyopenvdb, numpy" 2>/dev/null; then
  missing+=(python3-openvdb python3-numpy)
fi
if ! dpkg-query -W -f='${Status}' libembree-dev 2>/dev/null | grep -q "install ok installed"; then
  missing+=(libembree-dev)
fi
if ! [ -x /usr/bin/chromium ]; then
  missing+=(chromium)
fi
if ! python3 -c "import ensurepip, venv" 2>/dev/null; then
  missing+=(python3-venv)
fi
if [ ${#missing[@]} -eq 0 ]; then
  exit 0
fi
export DEBIAN_FRONTEND=noninteractive
apt-get update -qq
apt-get install -y -qq "${missing[@]}" >/dev/null
