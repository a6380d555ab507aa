#!/usr/bin/env bash
# The figures of the speed table in docs/results.md: instruction counts (callgrind, the same on
# every run of one binary) and median CPU times (this host's wall time varies by ±40 %).
#
#     scripts/speed.sh [--quick]      (--quick: no 8- and 16-frame or suite counts, 3 timing repeats)
#
# Prints one line per figure. Needs valgrind for the counts (skipped without it).
set -euo pipefail
cd "$(dirname "$0")/.."
quick=0
[ "${1:-}" = "--quick" ] && quick=1
cargo build --release --quiet --bin deckspin --example run_cost --example frames_cost
bin=target/release/deckspin
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
repeat=11
[ $quick = 1 ] && repeat=3
frames="2 4 8 16"
[ $quick = 1 ] && frames="2 4"

# instructions of a command under callgrind (only the integration with --integration; the
# function's exact name: a pattern ending in * would also match a closure inside it, where
# callgrind toggles collection off)
count() {
    local toggle=()
    if [ "$1" = "--integration" ]; then
        toggle=(--toggle-collect='deckspin_core::simulate::integrate')
        shift
    fi
    valgrind --tool=callgrind --callgrind-out-file="$tmp/cg" "${toggle[@]}" "$@" 2>&1 >/dev/null \
        | sed -n 's/.*Collected : \([0-9]*\).*/\1/p'
}

# median CPU time (user + sys, from the kernel's accounting of the child) of a command over
# $repeat runs
cpu_median() {
    local ts=() TIMEFORMAT='%3U %3S'
    for _ in $(seq "$repeat"); do
        ts+=("$( { time "$@" >/dev/null 2>&1; } 2>&1 | awk '{print $1 + $2}')")
    done
    printf '%s\n' "${ts[@]}" | sort -g | awk '{a[NR]=$1} END {printf "%.1f ms", 1000 * a[int((NR + 1) / 2)]}'
}

if command -v valgrind >/dev/null 2>&1; then
    echo "default run, no history, integration: $(count --integration target/release/examples/run_cost) instructions"
    echo "README command (run models/four-span.toml --out), whole process: $(count $bin run models/four-span.toml --out "$tmp/out") instructions"
    echo "mu x runs sweep (56 runs), whole process: $(count $bin sweep models/four-span.toml --set contacts.mu=0,0.1,0.2,0.3,0.4,0.5,0.6,0.7 --set excitation.run=1,2,3,4,5,6,7 --out "$tmp/sweep.csv") instructions"
    for n in $frames; do
        echo "$n frames in series (examples/frames_cost, 10 s), integration: $(count --integration target/release/examples/frames_cost "$n" solver.t_end=10) instructions"
        echo "$n frames in series by islands (solver.islands=true, 10 s), integration: $(count --integration target/release/examples/frames_cost "$n" solver.t_end=10 solver.islands=true) instructions"
    done
    if [ $quick = 0 ]; then
        # the far-field pairs at 0.5, 1.0 and 1.5 g (57 runs), whole process on one thread
        total=$(RAYON_NUM_THREADS=1 count $bin suite models/four-span.toml --records excitations/far-field \
            --measure pga --levels 0.5,1.0,1.5 --out "$tmp/suite.csv")
        echo "record suite (far-field pairs at 0.5, 1.0, 1.5 g), whole process: $total instructions, $((total / 57)) a run"
    fi
else
    echo "valgrind not found: no instruction counts"
fi
echo "README command, median CPU of $repeat: $(cpu_median $bin run models/four-span.toml --out "$tmp/out")"
echo "mu x runs sweep, median CPU of $repeat (both threads): $(cpu_median $bin sweep models/four-span.toml --set contacts.mu=0,0.1,0.2,0.3,0.4,0.5,0.6,0.7 --set excitation.run=1,2,3,4,5,6,7 --out "$tmp/sweep.csv")"
$bin bench --repeat "$((4 * repeat - 3))" --sweeps "$repeat"
