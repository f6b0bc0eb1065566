#!/usr/bin/env bash
# Checks a GPU bundle made by scripts/gpu_bundle.sh:
#   - its size on disk is at most 48 MiB (what `du -sh` reports);
#   - every ELF file in it resolves its libraries, with LD_LIBRARY_PATH set to the bundle's lib/,
#     to files of the bundle or of glibc alone (ldd shows no "not found" and nothing else);
#   - unless --no-run: `env -i PATH=/usr/bin:/bin bash DIR/run.sh` exits 0 and, where this machine
#     has no NVIDIA GPU, says "no GPU" (what CI checks: the bundle must not rot).
#
#   bash scripts/check_gpu_bundle.sh [--no-run] DIR
set -euo pipefail
RUN=1
if [ "${1:-}" = "--no-run" ]; then
  RUN=0
  shift
fi
if [ $# -ne 1 ] || [ ! -d "$1" ]; then
  echo "usage: bash scripts/check_gpu_bundle.sh [--no-run] BUNDLE_DIR" >&2
  exit 2
fi
DIR=$(realpath "$1")
LIMIT_KIB=$((48 * 1024))
failed=0

size_kib=$(du -sk "$DIR" | cut -f1)
if [ "$size_kib" -gt "$LIMIT_KIB" ]; then
  echo "FAIL size: $DIR takes $((size_kib / 1024)) MiB, more than 48 MiB"
  du -sk "$DIR"/* | sort -n >&2
  failed=1
else
  echo "ok   size: $(awk -v k="$size_kib" 'BEGIN {printf "%.1f", k / 1024}') MiB of 48 MiB" \
       "(bin $(du -sh "$DIR/bin" | cut -f1), lib $(du -sh "$DIR/lib" | cut -f1), data $(du -sh "$DIR/data" | cut -f1))"
fi

glibc_lib() {
  case "$1" in
    linux-vdso.so.*|ld-linux-x86-64.so.*|libc.so.*|libm.so.*|libpthread.so.*|libdl.so.*|librt.so.*|libresolv.so.*|libutil.so.*) return 0 ;;
  esac
  return 1
}
elves=0
while IFS= read -r -d '' file; do
  [ "$(head -c 4 "$file" | od -An -c | tr -d ' \n')" = "177ELF" ] || continue
  elves=$((elves + 1))
  report=$(LD_LIBRARY_PATH="$DIR/lib" ldd "$file" 2>&1) || true
  bad=$(echo "$report" | grep "not found" || true)
  while read -r name arrow path _; do
    [ "$arrow" = "=>" ] || continue
    case "$(realpath -m "$path")" in "$DIR"/lib/*) continue ;; esac
    glibc_lib "$name" || bad="$bad
  $name => $path (outside the bundle and not glibc)"
  done <<<"$report"
  if [ -n "$bad" ]; then
    echo "FAIL ldd ${file#"$DIR"/}:$bad"
    failed=1
  fi
done < <(find "$DIR" -type f -print0)
[ "$elves" -gt 0 ] || { echo "FAIL ldd: no ELF file in $DIR"; failed=1; }
[ "$failed" -ne 0 ] || echo "ok   ldd: $elves ELF files resolve from the bundle's lib/ and glibc alone"

if [ "$RUN" -eq 1 ]; then
  rm -rf "$DIR/out"
  set +e
  output=$(env -i PATH=/usr/bin:/bin bash "$DIR/run.sh" 2>&1)
  rc=$?
  set -e
  if [ "$rc" -ne 0 ]; then
    echo "FAIL run.sh: exit $rc"
    echo "$output" | tail -20
    failed=1
  elif ! ls /dev/nvidia[0-9]* >/dev/null 2>&1 && ! echo "$output" | grep -q "no GPU"; then
    echo "FAIL run.sh: exit 0 on a machine without a GPU but no 'no GPU' line"
    echo "$output" | tail -20
    failed=1
  else
    echo "ok   run.sh under env -i: exit 0; $(echo "$output" | grep -m1 "no GPU" || echo "$output" | tail -1)"
  fi
  rm -rf "$DIR/out"
fi
exit "$failed"
