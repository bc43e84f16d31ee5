#!/usr/bin/env bash
# Installs what the format tests need beyond cargo: Debian's python3-openvdb (OpenVDB
# 10's Python module), which tests/formats.rs uses as an independent reader of the
# .vdb files octsolid writes (tests/data/vdb_probe.py). Idempotent; needs root (apt).
set -euo pipefail
if /usr/bin/python3 -c "import pyopenvdb, numpy" 2>/dev/null; then
  exit 0
fi
export DEBIAN_FRONTEND=noninteractive
apt-get update -qq
apt-get install -y -qq python3-openvdb python3-numpy >/dev/null
