#!/usr/bin/env bash
# Runs a fixed list of jobs with one deckspin binary and keeps every output (files, stdout,
# stderr, exit code) with the timings masked, so that two builds can be compared.
# usage: scripts/outputs.sh BIN OUTDIR      (run from the repository root)
set -uo pipefail
bin=$(realpath "$1"); out=$2
root=$(pwd)
rm -rf "$out"; mkdir -p "$out"
out=$(realpath "$out")

# wall/CPU times are the only run-to-run noise: mask them
mask() {
  sed -E -e 's/wall [0-9.]+ (ms|s)/wall T/g' -e 's/\(([0-9.]+) s wall/(T s wall/g' \
         -e 's/"(wall_time|cpu_seconds|wall_seconds)": [0-9.e+-]+/"\1": T/g' \
         -e 's/ +[0-9.]+ s  peak err/ T s  peak err/g' -e 's/ in [0-9.]+ s on / in T s on /g'
}
job() { # name, then the arguments of deckspin
  local name=$1; shift
  local dir="$out/$name"; mkdir -p "$dir"
  (cd "$dir" && "$bin" "$@" >stdout.raw 2>stderr.raw; echo $? >exit)
  mask <"$dir/stdout.raw" >"$dir/stdout"; mask <"$dir/stderr.raw" >"$dir/stderr"
  rm -f "$dir/stdout.raw" "$dir/stderr.raw"
  find "$dir" -type f \( -name '*.json' -o -name '*.txt' \) | while read -r f; do mask <"$f" >"$f.m" && mv "$f.m" "$f"; done
  return 0
}
models=("$root/models/four-span.toml" "$root"/models/validation/*.toml)
for m in "${models[@]}"; do
  for method in event moreau penalty penalty-explicit; do
    job "run-$(basename "$m" .toml)-$method" run "$m" --out o --method "$method"
  done
done
job run-at run "$root/models/four-span.toml" --out o --at 5.0
job run-restitution-1 run "$root/models/four-span.toml" --out o --set contacts.restitution=1
# bilinear columns: a copy of the default model with its Takeda law replaced
mkdir -p "$out/run-bilinear"
sed -E -e 's#^law = \{ law = "takeda",(.*), unloading_exponent = [0-9.]+ \}#law = { law = "bilinear",\1 }#' \
    -e "s#\"\\.\\./excitations/#\"$root/excitations/#" "$root/models/four-span.toml" >"$out/run-bilinear/model.toml"
job run-bilinear run "$out/run-bilinear/model.toml" --out o --set contacts.mu=0.4
job modes modes "$root/models/four-span.toml"
job excitation excitation "$root/excitations/NORTHR_LOS000.AT2" --target-pga 0.6 --time-scale 0.5 --csv rec.csv
job sweep sweep "$root/models/four-span.toml" --set contacts.mu=0,0.3,0.7 --set excitation.run=4,6 --out sweep.csv
job study-mu study mu "$root/models/four-span.toml"
job study-pga study pga "$root/models/four-span.toml"
job stability stability "$root/models/four-span.toml" --quick
# the sweep's wall-time columns
sed -E -i 's/ +[0-9.]+$//' "$out/sweep/stdout"
for f in "$out"/sweep/sweep.csv; do
  [ -f "$f" ] && awk -F, 'NR==1{for(i=1;i<=NF;i++) if($i=="wall_time_s") c=i} {if(c) $c="T"; print}' OFS=, "$f" >"$f.m" && mv "$f.m" "$f"
done
echo "$(ls "$out" | wc -l) jobs written to $out"
