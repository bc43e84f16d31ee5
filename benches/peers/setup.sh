#!/usr/bin/env bash
# Installs the peer tools octsolid is measured against, when they are missing:
#   Debian: povray (POV-Ray 3.7), libembree-dev (Embree 3), python3-openvdb, openscad
#   a Python venv in target/peers-venv with manifold3d, embreex (Embree 4),
#   trimesh, numpy, fast-simplification, scipy, pillow and edt, pinned in requirements.txt.
# Idempotent: a second run installs nothing and only prints the versions.
#
#   benches/peers/setup.sh            # everything
#   PEERS_NO_APT=1 benches/peers/setup.sh   # only the venv (no root needed)
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
venv="${PEERS_VENV:-$root/target/peers-venv}"

if [ -z "${PEERS_NO_APT:-}" ]; then
    apt_packages=(povray libembree-dev python3-openvdb openscad python3-venv)
    missing=()
    for p in "${apt_packages[@]}"; do
        dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
    done
    if [ ${#missing[@]} -gt 0 ]; then
        sudo=""
        [ "$(id -u)" -eq 0 ] || sudo="sudo"
        echo "apt: installing ${missing[*]}"
        $sudo env DEBIAN_FRONTEND=noninteractive apt-get -o DPkg::Lock::Timeout=900 update -qq
        $sudo env DEBIAN_FRONTEND=noninteractive apt-get -o DPkg::Lock::Timeout=900 install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
    fi
fi

# The venv takes whichever python3 is first on PATH (3.9 or newer).
python=${PYTHON:-python3}
if [ ! -x "$venv/bin/python" ]; then
    echo "venv: creating $venv"
    "$python" -m venv "$venv"
fi
stamp="$venv/.requirements.sha256"
want=$(sha256sum "$here/requirements.txt" | cut -d' ' -f1)
if [ ! -f "$stamp" ] || [ "$(cat "$stamp")" != "$want" ]; then
    echo "venv: installing benches/peers/requirements.txt"
    "$venv/bin/python" -m pip install -q --disable-pip-version-check -r "$here/requirements.txt"
    echo "$want" >"$stamp"
fi

# What is there now.
echo "versions:"
command -v povray >/dev/null && echo "  povray: $(povray --version 2>&1 | grep -m1 -oE 'POV-Ray [0-9.]*[0-9]' || true)"
dpkg-query -W -f='  libembree-dev: ${Version}\n' libembree-dev 2>/dev/null || echo "  libembree-dev: missing"
dpkg-query -W -f='  python3-openvdb: ${Version}\n' python3-openvdb 2>/dev/null || echo "  python3-openvdb: missing"
# Debian's binding is built for Debian's python3, not the venv's: run it as /usr/bin/python3.
[ -x /usr/bin/python3 ] && /usr/bin/python3 -c 'import pyopenvdb as v; print("  pyopenvdb (/usr/bin/python3): %d.%d.%d" % v.LIBRARY_VERSION)' 2>/dev/null || true
command -v openscad >/dev/null && echo "  openscad: $(openscad --version 2>&1 | head -1)"
"$venv/bin/python" - <<'EOF'
from importlib.metadata import version
for name in ("manifold3d", "embreex", "trimesh", "numpy", "fast-simplification", "scipy", "pillow", "edt"):
    print(f"  {name}: {version(name)}")
EOF
echo "venv: $venv/bin/python"
