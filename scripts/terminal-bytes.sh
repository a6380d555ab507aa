#!/usr/bin/env bash
# Bytes the workbench sends to its terminal per second, idle and during a run, at 80x24: the
# workbench on models/four-span.toml in a detached tmux pane, its output recorded by
# script(1); the first run is left to finish, the idle bytes are counted over 10 s, then `r`
# reruns and the bytes up to its end ("#2 done", or "failed" when the accuracy check finds the fixed step too coarse) are counted with the wall time they took. So that a
# run lasts seconds, the model is solved by Moreau–Jean with a 20 µs step (some 6 s here; the
# event-driven default takes 0.1 s).
#
#     scripts/terminal-bytes.sh [TERM]      (default: the pane's own, screen: 16 colours)
#
# DECKSPIN_BIN=PATH measures that binary instead of building this checkout's.
# Needs tmux and script (util-linux).
set -euo pipefail
cd "$(dirname "$0")/.."
bin=${DECKSPIN_BIN:-}
if [ -z "$bin" ]; then
    cargo build --release --quiet --bin deckspin
    bin=$PWD/target/release/deckspin
fi
tmp=$(mktemp -d)
sock=deckspin-bytes-$$
trap 'tmux -L "$sock" kill-server 2>/dev/null || true; rm -rf "$tmp"' EXIT
cp -r models excitations "$tmp"/
sed -i 's/^method = "event"/method = "moreau"/; s/^step = 0.001 /step = 0.00002 /' \
    "$tmp/models/four-span.toml"
grep -q '^step = 0.00002 ' "$tmp/models/four-span.toml"
log=$tmp/out.log
term=${1:-}
envs=""
[ -n "$term" ] && envs="TERM=$term"
tmux -L "$sock" -f /dev/null new-session -d -s b -x 80 -y 24 \
    "cd '$tmp' && env $envs script -q -f -c '$bin models/four-span.toml' '$log'; sleep 60"
size() { stat -c %s "$log" 2>/dev/null || echo 0; }
wait_for() {
    for _ in $(seq 1200); do
        tmux -L "$sock" capture-pane -p -t b | grep -Eq "$1" && return 0
        sleep 0.05
    done
    echo "timed out waiting for '$1'" >&2
    exit 1
}
wait_for "#1 (done|failed)"
sleep 1
a=$(size)
sleep 10
b=$(size)
echo "idle at 80x24: $(((b - a) / 10)) B/s ($((b - a)) bytes in 10 s)"
a=$(size)
t0=$(date +%s%N)
tmux -L "$sock" send-keys -t b r
wait_for "#2 (done|failed)"
t1=$(date +%s%N)
b=$(size)
ms=$(((t1 - t0) / 1000000))
echo "running at 80x24: $(((b - a) * 1000 / ms)) B/s ($((b - a)) bytes in $ms ms, the 16 s run)"
tmux -L "$sock" send-keys -t b q
# the workbench writes its run list on the way out: let it end before the folder goes
sleep 1
