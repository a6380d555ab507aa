#!/usr/bin/env bash
# Public items per crate and loose files per folder, the figures of the crates' split
# (docs/architecture.md): a line per source tree with its public functions, types (struct, enum,
# trait, type), fields, constants and modules (`pub`, not `pub(crate)` / `pub(super)`; test
# modules included, as written), then each folder's loose .rs files (mod.rs, lib.rs, main.rs
# not counted).
#
#     scripts/public-items.sh [DIR …]      (default: every crate's src and the root src)
set -euo pipefail
cd "$(dirname "$0")/.."
dirs=("$@")
if [ ${#dirs[@]} -eq 0 ]; then
    dirs=(src)
    for d in crates/*/src; do if [ -d "$d" ]; then dirs+=("$d"); fi; done
fi
count() { { grep -rhoE "$1" --include="*.rs" "$2" || true; } | wc -l; }
printf '%-22s %6s %6s %6s %6s %6s %6s\n' tree fn pub_fn types pub_ty fields pub_c
for d in "${dirs[@]}"; do
    fns=$(count '^\s*(pub(\([a-z: ]+\))? )?(const )?(unsafe )?fn ' "$d")
    pfns=$(count '^\s*pub (const )?(unsafe )?fn ' "$d")
    tys=$(count '^\s*(pub(\([a-z: ]+\))? )?(struct|enum|trait|type) ' "$d")
    ptys=$(count '^\s*pub (struct|enum|trait|type) ' "$d")
    fields=$(count '^\s*pub [a-z_][a-z_0-9]*: ' "$d")
    consts=$(count '^\s*pub (const|static|mod) ' "$d")
    printf '%-22s %6s %6s %6s %6s %6s %6s\n' "$d" "$fns" "$pfns" "$tys" "$ptys" "$fields" "$consts"
done
echo
echo "loose files per folder (more than 8):"
for d in "${dirs[@]}"; do
    find "$d" -type d | while read -r f; do
        n=$(find "$f" -maxdepth 1 -name '*.rs' ! -name mod.rs ! -name lib.rs ! -name main.rs | wc -l)
        if [ "$n" -gt 8 ]; then printf '  %-34s %3s\n' "$f" "$n"; fi
    done
done
