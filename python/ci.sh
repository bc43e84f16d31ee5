#!/usr/bin/env bash
# CI of the Python package (called from .ci/run after `cargo test --release`, whose
# `octsolid` binary in target/release the tests compare against): a virtual
# environment in target/python-venv (made once, then reused), the package built and
# installed as a user installs it (`pip install ./python`, its Rust build in the
# repository's target/, kept from run to run; the library is compiled once more for it,
# since the module's dependencies unify to other features than the workspace's), the
# Python crate's formatting and lints, then pytest (python/tests, which also runs
# examples/python).
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD
venv=target/python-venv
if ! [ -x "$venv/bin/python" ]; then
  python3 -m venv "$venv"
fi
"$venv/bin/python" -m pip install --quiet --disable-pip-version-check "maturin>=1.5,<2" numpy pytest trimesh
export CARGO_TARGET_DIR="$root/target"
export PYO3_PYTHON="$root/$venv/bin/python"
# maturin is in the venv already (on PATH), so the build needs no isolated environment.
export PATH="$root/$venv/bin:$PATH"
"$venv/bin/python" -m pip install --quiet --disable-pip-version-check --no-build-isolation --force-reinstall --no-deps ./python
cargo fmt --check --manifest-path python/Cargo.toml
cargo clippy --manifest-path python/Cargo.toml --all-targets -- -D warnings
OCTSOLID_BIN="$root/target/release/octsolid" "$venv/bin/python" -m pytest -q python/tests
