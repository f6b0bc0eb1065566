#!/usr/bin/env bash
# timed.sh USAGE.json COMMAND [ARGS...]: runs COMMAND and, when it succeeds, writes its wall time
# and peak resident memory as {"seconds": S, "peak_kib": K} to USAGE.json (atomically), for the
# workflow's summary. COMMAND's exit status is passed on. GNU time measures the whole process
# tree's largest member, which is what a job's memory request must cover.
set -uo pipefail
usage=$1
shift
partial="$(dirname "$usage")/.$(basename "$usage").tmp$$"
mkdir -p "$(dirname "$usage")"
if [ -x /usr/bin/time ]; then
  /usr/bin/time -f '{"seconds": %e, "peak_kib": %M}' -o "$partial" "$@"
  status=$?
else  # no GNU time on this node: the seconds alone
  start=$(date +%s.%N)
  "$@"
  status=$?
  echo "{\"seconds\": $(echo "$(date +%s.%N) - $start" | bc), \"peak_kib\": null}" >"$partial"
fi
if [ "$status" -gt 128 ]; then
  echo "vdbfuse workflow: $1 was killed by signal $((status - 128)) ($(kill -l "$((status - 128))" 2>/dev/null || echo '?'))" >&2
elif [ "$status" -ne 0 ]; then
  echo "vdbfuse workflow: $1 exited with status $status" >&2
fi
if [ "$status" -eq 0 ]; then
  # GNU time puts a note before the figures when the command failed; the figures are the last line.
  tail -n 1 "$partial" >"$partial.last" && mv "$partial.last" "$usage"
fi
rm -f "$partial" "$partial.last"
exit "$status"
