#!/usr/bin/env bash
# Which part of the energy closure is the records' kinks (docs/robustness.md): the closure and
# the steps of runs off the specimen at several rtol (atol = rtol × 1e-3), without and with
# steps that stop at the records' samples (solver.stop_at_samples), so that the two are
# compared at equal numbers of steps; then the squeezed specimen (tables out of phase), the
# one case the kinks carry.
#
#     scripts/closure-steps.sh
set -euo pipefail
cd "$(dirname "$0")/.."
cargo build --release --quiet --bin deckspin
bin=target/release/deckspin
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
ff=../excitations/far-field

# "steps, closure" of one run: MODEL then --set arguments
row() {
    local model=$1
    shift
    "$bin" run "$model" --out "$tmp/out" "$@" 2>/dev/null |
        awk '/ steps \(/ { for (i = 1; i <= NF; i++) if ($i == "steps") s = $(i - 1) }
             /energy closure/ { c = $0; sub(/.*rel /, "", c); sub(/;.*/, "", c) }
             END { print s, c }'
}

case_rows() {
    local label=$1 model=$2
    shift 2
    for rtol in 1e-4 1e-5 1e-6 1e-7; do
        atol=$(python3 -c "print($rtol * 1e-3)")
        echo "$label | no  | $rtol | $(row "$model" "$@" --set solver.rtol=$rtol --set solver.atol=$atol)"
    done
    echo "$label | yes | 1e-4 | $(row "$model" "$@" --set solver.stop_at_samples=true)"
}

echo "run | stops at samples | rtol | steps, closure"
case_rows "rigid, Cape Mendocino, run 1" models/four-span-rigid.toml \
    --set excitation.longitudinal=$ff/CAPEMEND_RIO270.AT2 \
    --set excitation.transverse=$ff/CAPEMEND_RIO360.AT2 --set excitation.run=1
case_rows "rigid, Manjil Abbar, run 5, e 1, mu 0.1" models/four-span-rigid.toml \
    --set excitation.longitudinal=$ff/MANJIL_ABBARL.AT2 \
    --set excitation.transverse=$ff/MANJIL_ABBART.AT2 --set excitation.run=5 \
    --set contacts.restitution=1 --set contacts.mu=0.1
case_rows "three-frame, Hector Mine, mu 0.2" models/three-frame.toml \
    --set excitation.longitudinal=$ff/HECTOR_HEC000.AT2 \
    --set excitation.transverse=$ff/HECTOR_HEC090.AT2 --set contacts.mu=0.2

# the squeezed deck: the specimen with its tables out of phase
sed -e 's/^lag_bents = .*/lag_bents = [0.0, 0.05, 0.1]/' \
    -e 's/^lag_abutments = .*/lag_abutments = [0.0, 0.15]/' \
    models/four-span.toml >models/.closure-steps-lagged.toml
trap 'rm -rf "$tmp" models/.closure-steps-lagged.toml' EXIT
cm=(--set excitation.longitudinal=$ff/CAPEMEND_RIO270.AT2
    --set excitation.transverse=$ff/CAPEMEND_RIO360.AT2 --set excitation.run=7
    --set contacts.restitution=0)
lagged=models/.closure-steps-lagged.toml
for sas in false true; do
    echo "squeezed, Cape Mendocino, run 7, mu 1 | $sas | 1e-4 | $(row $lagged "${cm[@]}" --set contacts.mu=1 --set solver.stop_at_samples=$sas)"
    echo "squeezed, 3 s, mu 0 | $sas | 1e-8 | $(row $lagged "${cm[@]}" --set contacts.mu=0 --set solver.t_end=3 --set solver.rtol=1e-8 --set solver.atol=1e-11 --set solver.stop_at_samples=$sas)"
done
