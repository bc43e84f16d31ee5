#!/usr/bin/env bash
# Writes the reference files the format tests read (tests/formats.rs), with tools
# nobody on the team wrote:
#   vdb/*.vdb      OpenVDB 10 through Debian's python3-openvdb (pyopenvdb),
#   binvox/*.binvox  the PyPI `binvox` package (a binvox-rw-py descendant) and trimesh's
#                  own writer, in a venv,
# plus a JSON file beside each set naming the analytic shapes the tests check against.
#   vox/*.vox      the sample files in the dot_vox crate's package (MagicaVoxel's),
#                  copied with the crate's licence from cargo's own copy of the package.
#
#   tests/data/make_reference_files.sh          # as root, or with the packages installed
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
"$here/install_reference_tools.sh"
/usr/bin/python3 "$here/make_reference_files.py" vdb "$here/vdb"
venv=$(mktemp -d)
trap 'rm -rf "$venv"' EXIT
"${PYTHON:-python3}" -m venv "$venv"
"$venv/bin/pip" install --quiet "binvox==0.1.6" "trimesh==5.2.0" "numpy>=2"
"$venv/bin/python" "$here/make_reference_files.py" binvox "$here/binvox"

# dot_vox is a dependency of the library: cargo has its package, wherever its registry is.
dot_vox=$(cd "$here/../.." && cargo metadata --format-version 1 --locked |
  python3 -c 'import json, os, sys
print(next(os.path.dirname(p["manifest_path"]) for p in json.read(sys.stdin)["packages"] if p["name"] == "dot_vox"))')
cp "$dot_vox"/src/resources/*.vox "$here/vox/"
cp "$dot_vox/LICENSE" "$here/vox/LICENSE-dot_vox"
