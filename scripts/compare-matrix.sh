#!/usr/bin/env bash
# Compares two directories written by scripts/render-matrix.sh, image by image: prints each image's
# rel_rmse and whether the files are identical, and exits non-zero if any image differs or is missing.
#   scripts/compare-matrix.sh BEFORE_DIR AFTER_DIR [ENVSHADOW]
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
before="${1:?usage: scripts/compare-matrix.sh BEFORE_DIR AFTER_DIR [ENVSHADOW]}"
after="${2:?usage: scripts/compare-matrix.sh BEFORE_DIR AFTER_DIR [ENVSHADOW]}"
envshadow="${3:-${ENVSHADOW_BUILD_DIR:-$root/build}/app/envshadow}"
status=0 count=0
for a in "$before"/*.exr; do
  name="$(basename "$a")"
  b="$after/$name"
  count=$((count + 1))
  if [ ! -f "$b" ]; then echo "$name: missing in $after"; status=1; continue; fi
  if cmp -s "$a" "$b"; then echo "$name: identical"; continue; fi
  line="$("$envshadow" compare "$a" "$b" 2>&1 || true)"
  echo "$name: $line"
  case "$line" in rel_rmse=0\ *) ;; *) status=1 ;; esac
done
echo "$count images compared"
exit $status
