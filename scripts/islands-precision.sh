#!/usr/bin/env bash
# Islands against the whole scene at equal accuracy, not only at equal tolerance: for N frames
# in series (examples/frames_cost), the integration's instructions (callgrind) and the largest
# error of the printed peak rotations against a converged run (rtol 1e-10, atol 1e-13, no
# branch window), relative to the largest peak, at several rtol (atol = rtol × 1e-3).
#
#     scripts/islands-precision.sh [N …]        (default: 1 3 5 8)
#     RTOLS="3e-4 3e-5 3e-6" scripts/islands-precision.sh    (other tolerances; default
#                                                   1e-3 1e-4 1e-5 1e-6)
#
# Then the work–precision rows of `deckspin precision --methods event` (CPU time, peak and
# history errors) for the three-frame bridge and the specimen, both ways. Needs valgrind for
# the counts (errors only without it).
set -euo pipefail
cd "$(dirname "$0")/.."
cargo build --release --quiet --bin deckspin --example frames_cost
frames=target/release/examples/frames_cost
bin=target/release/deckspin
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
ns=("$@")
[ ${#ns[@]} = 0 ] && ns=(1 3 5 8)

# peak lines "  name value at t" of a frames_cost run, as "name value"
peaks() { "$frames" "$@" | awk 'NR > 1 { print $1, $2 }'; }

count() {
    if command -v valgrind >/dev/null 2>&1; then
        valgrind --tool=callgrind --callgrind-out-file="$tmp/cg" \
            --toggle-collect='deckspin_core::simulate::integrate' "$frames" "$@" 2>&1 >/dev/null \
            | sed -n 's/.*Collected : \([0-9]*\).*/\1/p' | awk '{printf "%.1f M", $1 / 1e6}'
    else
        echo "-"
    fi
}

for n in "${ns[@]}"; do
    peaks "$n" solver.rtol=1e-10 solver.atol=1e-13 solver.branch_window=0 >"$tmp/ref"
    for rtol in ${RTOLS:-1e-3 1e-4 1e-5 1e-6}; do
        atol=$(awk -v r="$rtol" 'BEGIN { printf "%g", r * 1e-3 }')
        for islands in false true; do
            set -- "$n" "solver.rtol=$rtol" "solver.atol=$atol" "solver.islands=$islands"
            peaks "$@" >"$tmp/run"
            err=$(awk 'NR == FNR { ref[$1] = $2; if ($2 > m) m = $2; next }
                       { d = $2 - ref[$1]; if (d < 0) d = -d; if (d > e) e = d }
                       END { printf "%.2e", e / m }' "$tmp/ref" "$tmp/run")
            printf '%s frames  rtol %-5s islands %-5s  %10s  peak error %s\n' \
                "$n" "$rtol" "$islands" "$(count "$@")" "$err"
        done
    done
done

[ -n "${RTOLS:-}" ] && exit 0
for model in models/three-frame.toml models/four-span.toml; do
    for islands in false true; do
        echo "deckspin precision $model --methods event --set solver.islands=$islands"
        "$bin" precision "$model" --methods event --set "solver.islands=$islands" --out "$tmp" 2>/dev/null \
            | sed -n '/^method/,/^$/p'
    done
done
