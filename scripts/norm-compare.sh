#!/usr/bin/env bash
# Experiment (reverted with the code it measures): work–precision of the event-driven method
# over runs 2–6 × μ 0.3 / 0.5 / 0.7 of the specimen, for one error control
# (std | scale | qonly | tsit5). Prints run, μ, rtol, steps, history error, peak error.
set -euo pipefail
cd "$(dirname "$0")/.."
unset DECKSPIN_SCALE DECKSPIN_QONLY DECKSPIN_TSIT5
case "${1:-std}" in
  scale) export DECKSPIN_SCALE=1 ;;
  qonly) export DECKSPIN_QONLY=1 ;;
  tsit5) export DECKSPIN_TSIT5=1 ;;
esac
out=$(mktemp -d)
for run in 2 3 4 5 6; do for mu in 0.3 0.5 0.7; do
  target/release/deckspin precision models/four-span.toml --methods event \
      --set excitation.run=$run --set contacts.mu=$mu --out "$out" 2>/dev/null |
    awk -v r=$run -v m=$mu '/^event/ && $2 ~ /rtol/ { sub("rtol=", "", $2); print r, m, $2, $7, $5, $4 }' |
    sort -u
done; done
rm -rf "$out"
