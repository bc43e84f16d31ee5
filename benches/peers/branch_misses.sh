#!/usr/bin/env bash
# Mispredicted branches and instructions a ray of each contender on issue 41's ray sets
# (primary, bounce, hit-shadow: harness/src/secondary_rays.rs), counted by `perf stat`
# around `walk_one` tracing one set through one contender on one thread. The counters
# run only while rays are traced: perf starts with them off (--delay=-1) and walk_one
# turns them on and off through perf's control fifos (harness/src/perf_window.rs).
#
#   benches/peers/branch_misses.sh MODEL DEPTH SIZE SEED CONTENDER...
#   benches/peers/branch_misses.sh models/bunny-watertight.obj 10 1024 41 octree embree-mesh
#
# Prints one line a contender and set: `CONTENDER SET RAYS BRANCH_MISSES INSTRUCTIONS`
# (SET primary, bounce or shadow; the counts divided by RAYS; `n/a` when perf cannot
# count them, e.g. in a virtual machine without hardware counters), and lines starting
# with `#` saying why. SEED must be the harness's (secondary_rays::SEED, 41); walk_one
# makes its rays with it. Builds walk_one (release, with `--features embree` when
# Debian's libembree3 is installed). Installs Debian's `linux-perf` when `perf` is missing
# (as setup.sh installs Debian packages); without root or apt, every count is `n/a`.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
if [ $# -lt 5 ]; then
    echo "usage: $0 MODEL DEPTH SIZE SEED CONTENDER..." >&2
    exit 2
fi
model=$1 depth=$2 size=$3 seed=$4
shift 4
if [ "$seed" != 41 ]; then
    echo "branch_misses.sh: walk_one makes its rays with seed 41, not $seed" >&2
    exit 2
fi

if ! command -v perf >/dev/null; then
    sudo=""
    [ "$(id -u)" -eq 0 ] || sudo="sudo -n"
    echo "# apt: installing linux-perf" >&2
    $sudo env DEBIAN_FRONTEND=noninteractive apt-get -o DPkg::Lock::Timeout=900 install -y -qq --no-install-recommends linux-perf >/dev/null 2>&1 || true
fi

# Without hardware counters (many virtual machines) perf says <not supported>: report
# n/a at once rather than build and run walk_one for nothing.
sets=(primary bounce shadow)
probe=$(command -v perf >/dev/null && perf stat -x, -e branch-misses true 2>&1 >/dev/null | awk -F, '/branch-misses/{print $1}' || true)
if ! [[ "$probe" =~ ^[0-9]+$ ]]; then
    if command -v perf >/dev/null; then
        echo "# perf stat cannot count branch-misses here (${probe:-no output}): no hardware counters"
    else
        echo "# no perf (Debian's linux-perf) and it could not be installed"
    fi
    for contender in "$@"; do
        for set in "${sets[@]}"; do echo "$contender $set n/a n/a n/a"; done
    done
    exit 0
fi

features=()
if ldconfig -p 2>/dev/null | grep -q libembree3; then
    features=(--features embree)
fi
(cd "$root" && cargo build --release -q -p octsolid-harness "${features[@]}" --example walk_one) >&2
walk_one="$root/target/release/examples/walk_one"

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkfifo "$work/ctl" "$work/ack"

for contender in "$@"; do
    for set in primary bounce hit-shadow; do
        name=$set
        [ "$set" = hit-shadow ] && name=shadow
        # perf -x, writes CSV lines VALUE,UNIT,EVENT,... to -o; walk_one prints
        # "KIND: HITS of RAYS" on stdout.
        if ! out=$(cd "$root" && SIZE=$size CONTENDER=$contender PERF_CTL_FIFO="$work/ctl" PERF_ACK_FIFO="$work/ack" \
            perf stat -x, -o "$work/stat" --delay=-1 --control "fifo:$work/ctl,$work/ack" \
            -e branch-misses,instructions -- "$walk_one" "$model" "$depth" "$set" 0 2>"$work/err"); then
            echo "# $contender $set: $(tail -1 "$work/err")"
            echo "$contender $name n/a n/a n/a"
            continue
        fi
        rays=$(echo "$out" | awk '/ of /{print $NF}')
        count() {
            awk -F, -v ev="$1" -v n="$rays" '$3 ~ "^"ev {
                if ($1 ~ /^[0-9.]+$/ && n > 0) printf "%.2f", $1 / n; else printf "n/a" }' "$work/stat"
        }
        misses=$(count branch-misses)
        instructions=$(count instructions)
        if [ "$misses" = n/a ]; then
            echo "# $contender $set: perf stat: $(awk -F, '$3 ~ /^branch-misses/{print $1}' "$work/stat")"
        fi
        echo "$contender $name $rays ${misses:-n/a} ${instructions:-n/a}"
    done
done
