#!/usr/bin/env bash
# How many of the meshes other tools open does octsolid open? Runs `octsolid
# mesh-info` on every .obj, .stl and .ply of Debian's assimp-testmodels package
# (`apt-get install assimp-testmodels`) and prints one line a file, then the counts.
# The models are only read where the package put them, never copied here (their
# licences differ from ours).
#
#   tests/data/assimp_survey.sh [OCTSOLID]   # default: target/release/octsolid
#   ASSIMP_MODELS=DIR tests/data/assimp_survey.sh   # another folder of models
#
# A line is `ok` (with how many warnings it printed), `refused` (an error: its first
# line follows) or `timeout` (more than 60 s). Files in a folder named `invalid` are meant to be refused; they are
# counted apart.
set -uo pipefail
here=$(cd "$(dirname "$0")" && pwd)
octsolid=${1:-$here/../../target/release/octsolid}
if [[ ! -x $octsolid ]]; then
  echo "no octsolid binary at $octsolid (cargo build --release -p octsolid-cli)" >&2
  exit 2
fi
if [[ -n ${ASSIMP_MODELS:-} ]]; then
  files=$(find "$ASSIMP_MODELS" -type f)
elif dpkg -s assimp-testmodels >/dev/null 2>&1; then
  files=$(dpkg -L assimp-testmodels)
else
  echo "assimp-testmodels is not installed (apt-get install assimp-testmodels); nothing to survey" >&2
  exit 0
fi
files=$(grep -iE '\.(obj|stl|ply)$' <<<"$files" | while read -r f; do [[ -f $f ]] && echo "$f"; done | sort)

opened=0 total=0 invalid_refused=0 invalid_total=0
while read -r file; do
  [[ -z $file ]] && continue
  err=$(timeout 60 "$octsolid" mesh-info "$file" 2>&1 >/dev/null)
  rc=$?
  if [[ $file == */invalid/* ]]; then
    invalid_total=$((invalid_total + 1))
    [[ $rc -ne 0 ]] && invalid_refused=$((invalid_refused + 1))
  else
    total=$((total + 1))
    [[ $rc -eq 0 ]] && opened=$((opened + 1))
  fi
  case $rc in
    0) warned=$(grep -c '^warning: ' <<<"$err")
       echo "ok       $file$([[ $warned -gt 0 ]] && echo "  (warnings: $warned)")" ;;
    124) echo "timeout  $file" ;;
    *) echo "refused  $file: $(head -n 1 <<<"$err")" ;;
  esac
done <<<"$files"
echo "opened $opened of $total meshes; refused $invalid_refused of $invalid_total invalid ones"
