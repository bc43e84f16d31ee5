#!/usr/bin/env bash
# The classic part at depth 9 from Python against the Rust example (BENCHMARKS.md):
# examples/python/classic_part.py and examples/classic_csg.rs do the same work (voxelize,
# the .oct file without a surface section, the slice at z = 0.8 as a PNG) and write the
# same bytes (checked here); each is run N times (default 11), alternately, in a
# scratch folder, and the median wall time printed, with the median times Python takes
# to start bare and to start and import octsolid (constants the Rust binary does not
# pay; the script imports no numpy, octsolid imports it only when it makes an array);
# then the work alone, as each process timed it in the same runs (the Rust example
# with `--time`, std::time::Instant; the Python script with time.perf_counter: from
# the model to the PNG written, a fresh process's first and only run on both sides),
# so the work compares without the processes' start and exit; then the Python work
# repeated in one process, each run timed (warm: the thread pool started, the
# allocator's memory reused).
# Times are wall clock in milliseconds (`date +%s%N` around each command): at idle the
# whole run is under 0.1 s, where /usr/bin/time's 10 ms steps would be 13%.
# Needs: cargo build --release --example classic_csg, and python/ci.sh's venv.
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD
runs=${1:-11}
python="$root/target/python-venv/bin/python"
rust="$root/target/release/examples/classic_csg"
scratch=$(mktemp -d)
trap 'rm -rf "$scratch"' EXIT
cd "$scratch"
# The wall time of a command, its output kept in out.txt.
wall() {
  local start end
  start=$(date +%s%N)
  "$@" >out.txt
  end=$(date +%s%N)
  echo "scale=1; ($end - $start) / 1000000" | bc
}
median() { sort -n | awk '{a[NR] = $1} END {print a[int((NR + 1) / 2)]}'; }
# The work's time the last command printed (timed in its process), in milliseconds.
rust_work() { sed -n 's/^work \([0-9.]*\) ms.*/\1/p' out.txt; }
python_work() { sed -n 's/^voxelized and written in \([0-9.]*\) ms.*/\1/p' out.txt; }
: >rust.txt; : >python.txt; : >bare.txt; : >start.txt; : >rust-work.txt; : >python-work.txt
for _ in $(seq "$runs"); do
  wall "$rust" --time >>rust.txt
  rust_work >>rust-work.txt
  wall "$python" "$root/examples/python/classic_part.py" py >>python.txt
  python_work >>python-work.txt
  wall "$python" -c pass >>bare.txt
  wall "$python" -c "import octsolid" >>start.txt
done
cmp example-output/classic_csg/classic_csg.oct py/classic_part.oct
cmp example-output/classic_csg/classic_csg.png py/classic_part.png
echo "rust example   $(median <rust.txt) ms"
echo "python example $(median <python.txt) ms"
echo "python start   $(median <bare.txt) ms (the interpreter alone)"
echo "python import  $(median <start.txt) ms (the interpreter and import octsolid)"
echo "rust work      $(median <rust-work.txt) ms (timed in the process, same runs)"
echo "python work    $(median <python-work.txt) ms (timed in the process, same runs)"
echo "python, the work $runs times in one process:"
"$python" "$root/examples/python/classic_part.py" py --repeat "$runs" | grep '^run'

