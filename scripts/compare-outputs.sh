#!/usr/bin/env bash
# Compares the outputs of this checkout with those of a base revision, job by job
# (scripts/outputs.sh): event-driven outputs must be byte-identical; for the others the largest
# relative difference between corresponding numbers is printed.
# usage: scripts/compare-outputs.sh [BASE_REV]   (default: HEAD; run from the repository root)
set -euo pipefail
base=${1:-HEAD}
root=$(pwd)
work="$root/target/compare"
mkdir -p "$work"
rev=$(git rev-parse "$base")
if [ ! -x "$work/bin-$rev" ]; then
  rm -rf "$work/tree"; git worktree prune
  git worktree add --detach "$work/tree" "$rev" >/dev/null
  (cd "$work/tree" && CARGO_TARGET_DIR="$work/target-base" cargo build --release --locked --quiet)
  cp "$work/target-base/release/deckspin" "$work/bin-$rev"
  git worktree remove --force "$work/tree"
fi
cargo build --release --locked --quiet
scripts/outputs.sh "$work/bin-$rev" "$work/base" >/dev/null
scripts/outputs.sh target/release/deckspin "$work/head" >/dev/null

# largest relative difference between the numbers of two text files of the same shape
numdiff() {
  awk 'function isnum(x){return x ~ /^[-+]?([0-9]+\.?[0-9]*|\.[0-9]+)([eE][-+]?[0-9]+)?$/}
       function abs(x){return x<0?-x:x}
       NR==FNR {a[FNR]=$0; n=FNR; next}
       { if (!(FNR in a)) {shape="lines differ"; next}
         na=split(a[FNR],x,/[ ,:\t\[\]{}"()]+/); nb=split($0,y,/[ ,:\t\[\]{}"()]+/)
         if (na!=nb) {shape="line " FNR " differs in shape"; next}
         for (i=1;i<=na;i++) {
           if (x[i]==y[i]) continue
           if (isnum(x[i]) && isnum(y[i])) {
             d=abs(x[i]-y[i]); s=abs(x[i])>abs(y[i])?abs(x[i]):abs(y[i]); r=(s>0)?d/s:0
             if (r>worst) {worst=r; at="line " FNR ": " x[i] " vs " y[i]}
           } else {shape="line " FNR ": " x[i] " vs " y[i]}
         } m=FNR }
       END { if (m!=n) shape="line counts " n " vs " m
             if (shape!="") print "  text differs: " shape; else printf "  max relative difference %.3e (%s)\n", worst, at }' "$1" "$2"
}
status=0
for dir in "$work/base"/*/; do
  job=$(basename "$dir")
  if diff -rq "$work/base/$job" "$work/head/$job" >/dev/null; then
    echo "identical  $job"
  else
    echo "DIFFERENT  $job"
    case $job in *-event|run-at|run-restitution-1|run-bilinear|sweep|study-*|modes|excitation) status=1 ;; esac
    { diff -rq "$work/base/$job" "$work/head/$job" || true; } | while read -r _ a _ b _; do
      echo " $(realpath --relative-to="$work/base" "$a")"; numdiff "$a" "$b"
    done
  fi
done
[ "$status" = 0 ] && echo "event-driven outputs byte-identical" || echo "event-driven outputs differ"
exit $status
