#!/usr/bin/env bash
# Work–precision of the event-driven method over an ensemble of the specimen's runs: runs 2–6
# × μ 0.3 / 0.5 / 0.7 of models/four-span.toml (15 configurations), each against its own
# reference at rtol 1e-10 (`deckspin precision --methods event`). One run does not judge a
# change to the step control: after dozens of impacts a release, stick or slip decision near
# a tie can go either way, and the history of one run can stay 1e-4 from its reference at
# any rtol. Per rtol: the mean number of steps, the geometric means of the history (RMS) and
# peak errors over the 15, and the largest history error.
#
#     scripts/precision-ensemble.sh [--set KEY=VALUE …]   (applied to every run)
set -euo pipefail
cd "$(dirname "$0")/.."
cargo build --release --quiet --bin deckspin
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
for run in 2 3 4 5 6; do
    for mu in 0.3 0.5 0.7; do
        target/release/deckspin precision models/four-span.toml --methods event \
            --set excitation.run=$run --set contacts.mu=$mu "$@" --out "$out" 2>/dev/null |
            awk '/^event/ && $2 ~ /^rtol=/ { sub("rtol=", "", $2); print $2, $7, $5, $4 }' |
            sort -u
    done
done | awk '
    { n[$1]++; steps[$1] += $2; lr[$1] += log($3 > 1e-300 ? $3 : 1e-300)
      lp[$1] += log($4 > 1e-300 ? $4 : 1e-300); if ($3 > mx[$1]) mx[$1] = $3 }
    END {
        printf "%-6s %4s %10s %14s %12s %16s\n", "rtol", "runs", "mean steps", "history error", "peak error", "largest history"
        for (r in n) printf "%-6s %4d %10.0f %14.2e %12.2e %16.2e\n", r, n[r], steps[r] / n[r], exp(lr[r] / n[r]), exp(lp[r] / n[r]), mx[r]
    }' | { read -r head; echo "$head"; sort -g -r -k1,1; }
