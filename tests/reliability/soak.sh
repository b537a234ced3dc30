#!/usr/bin/env bash
# The soak (docs/reliability.md): a small scene for 100,000 steps, every step checked for
# non-finite particles and particles inside colliders, resident memory sampled from outside.
#
#   bash tests/reliability/soak.sh [BUILD_DIR] [STEPS]     (defaults: build/dev, 100000)
#
# Needs sluice_soak and the baked demo colliders in BUILD_DIR (cmake --build BUILD_DIR --target
# sluice_soak sluice_assets). Writes BUILD_DIR/soak/: the scene, the driver's log (a row every
# 1000 steps) and rss.csv (seconds, VmRSS kB, every 10 s). Exit 0 when the run was clean and
# memory grew by less than 5 % between the first and the last tenth of the run.
set -euo pipefail
cd "$(dirname "$0")/../.."
build=${1:-build/dev}
steps=${2:-100000}
exe=$build/bin/sluice_soak
assets=$(cd "$build/assets" 2>/dev/null && pwd) || { echo "soak: no $build/assets (build sluice_assets)" >&2; exit 2; }
[ -x "$exe" ] || { echo "soak: no $exe (build sluice_soak)" >&2; exit 2; }
out=$build/soak
mkdir -p "$out"

# 300 particles (10 x 5 x 6 at 2 cm) dropped onto a ball (sphere.slc at 0.4, radius 0.1 m) on
# the floor of the demo tank, which they then slosh around and settle in.
cat >"$out/soak.json" <<JSON
{
    "version": 1,
    "name": "soak",
    "simulation": { "spacing": 0.02 },
    "fluid": [ { "box": { "min": [-0.1, 0.3, -0.06], "max": [0.1, 0.4, 0.06] } } ],
    "colliders": [
        { "asset": "$assets/tank.slc", "friction": 0.1 },
        { "asset": "$assets/sphere.slc", "translation": [0.0, 0.13, 0.0], "scale": 0.4, "friction": 0.2 }
    ],
    "domain": { "min": [-0.5, 0.0, -0.35], "max": [0.5, 0.7, 0.35] }
}
JSON

"$exe" "$out/soak.json" --steps "$steps" --report-every 1000 >"$out/soak.log" 2>&1 &
pid=$!
start=$(date +%s)
echo "seconds,rss_kb" >"$out/rss.csv"
while kill -0 "$pid" 2>/dev/null; do
  rss=$(awk '/^VmRSS:/ {print $2}' "/proc/$pid/status" 2>/dev/null || true)
  [ -n "$rss" ] && echo "$(( $(date +%s) - start )),$rss" >>"$out/rss.csv"
  sleep 10
done
set +e
wait "$pid"
status=$?
set -e
tail -n 6 "$out/soak.log"

# Memory: the median of the first and of the last tenth of the samples (after the first minute,
# which includes start-up), and the growth between them.
python3 - "$out/rss.csv" <<'PY'
import csv, statistics, sys
rows = [(int(r["seconds"]), int(r["rss_kb"])) for r in csv.DictReader(open(sys.argv[1]))]
rows = [r for r in rows if r[0] >= 60] or rows
if len(rows) < 2:
    print("soak: too few memory samples"); sys.exit(0)
tenth = max(1, len(rows) // 10)
first = statistics.median(r[1] for r in rows[:tenth])
last = statistics.median(r[1] for r in rows[-tenth:])
growth = (last - first) / first * 100
print(f"soak: VmRSS sampled from outside every 10 s: {len(rows)} samples, first tenth "
      f"{first:.0f} kB, last tenth {last:.0f} kB ({growth:+.2f} %), max {max(r[1] for r in rows)} kB")
sys.exit(0 if growth < 5 else 4)
PY
mem=$?
[ "$status" -eq 0 ] && [ "$mem" -eq 0 ] && echo "soak: passed" && exit 0
echo "soak: FAILED (driver exit $status, memory check exit $mem)" >&2
exit 1
