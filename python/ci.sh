#!/usr/bin/env bash
# CI of the Python package (called from .ci/run after `cargo test --release`, whose
# `octsolid` binary in target/release the tests compare against): a virtual
# environment in target/python-venv (made once, then reused), the package built and
# installed as a user installs it (`pip install ./python`, its Rust build in the
# repository's target/, kept from run to run: the library's dependencies resolve to the
# same features as in the workspace, checked first, so it reuses that build of the
# library), the Python crate's lints (the root's `cargo fmt --check` formats it, a
# member), then pytest (python/tests, which also runs examples/python).
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD
venv=target/python-venv
if ! [ -x "$venv/bin/python" ]; then
  python3 -m venv "$venv"
fi
"$venv/bin/python" -m pip install --quiet --disable-pip-version-check "maturin>=1.5,<2" numpy pytest trimesh
# The library's dependencies must resolve to the same features here as in the root
# workspace (python/Cargo.toml and harness/Cargo.toml match them), or the build below
# compiles the library a second time (minutes of CI).
closure=$(cargo tree -p octsolid -e normal,build --prefix none -f '{p}' | sed 's/ (\*)$//' | sort -u)
features() {
  cargo tree "$@" -e normal,build,dev --prefix none -f '{p} {f}' | sed 's/ (\*)$//' | sort -u |
    awk 'NR == FNR { keep[$1 " " $2]; next } ($1 " " $2) in keep' <(printf '%s\n' "$closure") -
}
if ! diff <(features) <(features -p octsolid-python) >&2; then
  echo "python/ci.sh: the library's dependencies resolve to other features for the Python package (< the workspace, > octsolid-python); match them in python/Cargo.toml or harness/Cargo.toml" >&2
  exit 1
fi
export CARGO_TARGET_DIR="$root/target"
export PYO3_PYTHON="$root/$venv/bin/python"
# maturin is in the venv already (on PATH), so the build needs no isolated environment.
export PATH="$root/$venv/bin:$PATH"
"$venv/bin/python" -m pip install --quiet --disable-pip-version-check --no-build-isolation --force-reinstall --no-deps ./python
cargo clippy -p octsolid-python --all-targets -- -D warnings
OCTSOLID_BIN="$root/target/release/octsolid" "$venv/bin/python" -m pytest -q python/tests
