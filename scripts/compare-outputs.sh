#!/usr/bin/env bash
# Compares the outputs of this checkout with those of a base revision, job by job
# (scripts/outputs.sh): event-driven outputs must be byte-identical; for the others the largest
# relative difference between corresponding numbers is printed. A history.csv of a base written
# with 13 significant digits matches when this checkout's numbers round to them.
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
# history.csv written with `{:.12e}` (13 significant digits, revisions before the shortest
# round-trip numbers) against one written later: equal when every number of the later one
# rounds to the earlier one's 13 digits and every other field is the same text
same13() {
  awk -F, 'function fixed(x,  m){ if (x !~ /^-?[0-9]\.[0-9]+e-?[0-9]+$/) return 0
                                   split(x, m, /[.e]/); return length(m[2]) == 12 }
       NR==FNR {a[FNR]=$0; n=FNR; next}
       { if (!(FNR in a)) {bad=1; exit}
         na=split(a[FNR],x,","); nb=split($0,y,",")
         if (na!=nb) {bad=1; exit}
         for (i=1;i<=na;i++) {
           if (x[i]==y[i]) continue
           if (!(fixed(x[i]) && sprintf("%.12e", x[i]) == sprintf("%.12e", y[i]))) {bad=1; exit}
         } m=FNR }
       END { exit (bad || m!=n) }' "$1" "$2"
}
# the files of a job that differ, a history.csv equal to 13 digits left out
differing() {
  { diff -rq "$work/base/$1" "$work/head/$1" || true; } | while read -r _ a _ b _; do
    if [ "$(basename "$a")" = history.csv ] && same13 "$a" "$b"; then continue; fi
    echo "$a $b"
  done
}
status=0
for dir in "$work/base"/*/; do
  job=$(basename "$dir")
  if diff -rq "$work/base/$job" "$work/head/$job" >/dev/null; then
    echo "identical  $job"
  elif [ -z "$(differing "$job")" ]; then
    echo "identical  $job (history.csv: the base's 13-digit numbers)"
  else
    echo "DIFFERENT  $job"
    case $job in *-event|run-at|run-restitution-1|run-bilinear|sweep|study-*|modes|excitation) status=1 ;; esac
    differing "$job" | while read -r a b; do
      echo " $(realpath --relative-to="$work/base" "$a")"; numdiff "$a" "$b"
    done
  fi
done
[ "$status" = 0 ] && echo "event-driven outputs byte-identical" || echo "event-driven outputs differ"
exit $status
