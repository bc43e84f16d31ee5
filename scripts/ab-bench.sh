#!/usr/bin/env bash
# A/B of criterion benches between two checkouts in one sitting: runs each bench of
# the old tree, then the new, then both again, and prints every median.
#
#   scripts/ab-bench.sh OLD_CHECKOUT NEW_CHECKOUT BENCH [FILTER]...
#
# BENCH is a bench target (traverse, raster, ...); FILTER a criterion filter.
set -euo pipefail
old=${1:?old checkout}; new=${2:?new checkout}; bench=${3:?bench}; shift 3
for round in 1 2; do
  for side in old new; do
    dir=$([ "$side" = old ] && echo "$old" || echo "$new")
    (cd "$dir" && cargo bench --quiet --bench "$bench" -- --noplot "$@" 2>/dev/null) \
      | grep -E "^[a-z_/0-9]+ +time:|^[a-z][a-z_0-9/]*$|time:" \
      | sed "s/^/$side $round: /"
  done
done
