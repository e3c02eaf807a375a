#!/bin/bash
# usage: queue.sh FOAMGRAIN_BINARY VARIANT...  (in a scratch directory)
# Makes and runs each variant natively to 1.0 s, one thread, niced; writes VARIANT/done.
here="$(cd "$(dirname "$0")" && pwd)"
bin="$1"; shift
for v in "$@"; do
  [ -d "$v" ] || python3 "$here/make_variant.py" "$v" || continue
  [ -f "$v/done" ] && continue
  start=$(date +%s)
  nice -n 10 "$bin" run "$v" --np 1 > "$v/run.log" 2>&1
  echo "exit $? wall $(( $(date +%s) - start )) s" > "$v/done"
done
