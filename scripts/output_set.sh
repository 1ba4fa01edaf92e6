#!/bin/bash
# Runs a fixed set of carom commands and keeps every file they write, so that two builds can be
# compared byte for byte after a change that must not change any output (a refactor):
#
#   scripts/output_set.sh OLD/carom /tmp/before && scripts/output_set.sh build/carom /tmp/after
#   diff -r /tmp/before /tmp/after          # nothing: the outputs are the same
#
# The set: the classic assignment's cases (table, trace, csv, json with the reference engine);
# carom init starts of disks and spheres run with a dump, a time series, an event log, periodic
# checkpoints, --check and a summary; a run stopped at a checkpoint and resumed with a GSD dump;
# compressions to a packing fraction and to a jam; new velocities from --kT. The json files lose
# the fields that depend on the clock (wall_seconds, events_per_second).
set -euo pipefail
if [[ $# -ne 2 ]]; then
  echo "usage: $0 CAROM OUT_DIR" >&2
  exit 2
fi
bin=$(realpath "$1")
out=$2
examples=$(cd "$(dirname "$0")/../examples" && pwd)
rm -rf "$out"
mkdir -p "$out"
cd "$out"
without_clock() {
  /usr/bin/python3 -c '
import json, sys
for path in sys.argv[1:]:
    d = json.load(open(path))
    for key in ("wall_seconds", "events_per_second"):
        d.pop(key, None)
    json.dump(d, open(path, "w"), indent=1, sort_keys=True)' "$@"
}
"$bin" run "$examples/walls_only.txt" 20 > walls.txt
"$bin" run "$examples/normal.txt" 20 --trace > trace.txt
"$bin" run "$examples/normal.txt" 20 --format csv > normal.csv
"$bin" run "$examples/normal.txt" 20 --engine reference --format json -o ref.json
"$bin" init --n 400 --phi 0.5 --boundary periodic --seed 3 -o gas.txt
"$bin" init --dim 3 --n 500 --phi 0.4 --boundary periodic --seed 3 -o sph.txt
for f in gas sph; do
  "$bin" run $f.txt 30 --equilibrate 5 --dump $f.xyz --every 0.5 --log $f.log.csv \
    --log-every 0.5 --events $f.events.csv --checkpoint $f.ckpt --checkpoint-every 20000 \
    --format json -o $f.json --summary $f.sum.json --check -q
  "$bin" run $f.txt 12 --checkpoint $f.r.ckpt -q --format json -o /dev/null
  "$bin" run --resume $f.r.ckpt 30 --equilibrate 12 --dump $f.r.gsd --every 0.5 \
    --log $f.r.log.csv --log-every 1 --events $f.r.events.csv --format json -o $f.r.json -q
  "$bin" compress $f.txt --phi 0.6 -o $f.c.txt --summary $f.c.json -q
  "$bin" compress $f.txt --jam --unit-diameter -o $f.j.txt --summary $f.j.json -q
  "$bin" run $f.txt 5 --kT 2 --seed 9 --format json -o $f.kt.json -q
  without_clock $f.json $f.sum.json $f.r.json $f.c.json $f.j.json $f.kt.json
done
without_clock ref.json
echo "$(ls | wc -l) files in $out"
