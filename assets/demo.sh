#!/usr/bin/env bash
# The demo: bakes every demo collider with the CGAL backend (only those the build has not
# already baked, see assets/CMakeLists.txt), validates it against its mesh and draws a slice of
# it; then plays the wave-with-sphere scene: in the viewer window when there is a display,
# otherwise headless, printing the statistics table and writing PLY frames, an MP4 and a PNG.
#   bash assets/demo.sh BIN_DIR [OUT_DIR]
# BIN_DIR holds sluice-bake and sluice-play (build/dev/bin). The colliders and scenes are the
# build's, in BIN_DIR/../assets; the demo only reads them. Everything the demo makes (slices,
# statistics, PLY frames, video, pictures) goes into OUT_DIR, by default BIN_DIR/../demo
# (build/dev/demo), never among the build products that the build and the tests read.
# Called by `bash cmake/setup.sh demo`. Exits 1 if a collider fails validation, 2 on bad usage.
set -euo pipefail

here=$(cd "$(dirname "$0")" && pwd)
if [ $# -lt 1 ] || [ $# -gt 2 ]; then
  echo "usage: bash assets/demo.sh BIN_DIR [OUT_DIR]" >&2
  exit 2
fi
exe="$1/sluice-bake"
if [ ! -x "$exe" ]; then
  echo "demo: $exe not found; build first (cmake --preset dev && cmake --build --preset dev)" >&2
  exit 2
fi
bin=$(cd "$1" && pwd)
assets=$(dirname "$bin")/assets # the build's colliders and scenes
out=${2:-$(dirname "$bin")/demo}
mkdir -p "$assets" "$out"
out=$(cd "$out" && pwd) # the manifest below names files by absolute path

# [m] one grid spacing for every collider, as a scene would use: 2.7 voxels across the 2 cm
# walls of the funnel and pea shooter, 4 across the tank's 3 cm walls, and a demo of seconds.
voxel_size=0.0075
meshes=(sphere funnel peashooter tank crate)

"$exe" --version
demo_start=$(date +%s%N)

# One batch for the bakes: the build bakes the same colliders with the same settings into
# build/<preset>/assets (sluice_bake_colliders in assets/CMakeLists.txt), so they are fresh and
# nothing is baked again; a build without them gets them baked there, on all cores.
json_path() { local p=${1//\\/\\\\}; printf '"%s"' "${p//\"/\\\"}"; }
manifest=$(mktemp --suffix=.json)
trap 'rm -f "$manifest"' EXIT
{
  echo '{"colliders": ['
  sep=""
  for name in "${meshes[@]}"; do
    printf '%s  {"mesh": %s, "output": %s, "voxelSize": %s, "backend": "cgal"}' "$sep" \
      "$(json_path "$here/$name.obj")" "$(json_path "$assets/$name.slc")" "$voxel_size"
    sep=$',\n'
  done
  printf '\n]}\n'
} > "$manifest"
echo
"$exe" batch "$manifest" --jobs "$(nproc 2>/dev/null || echo 1)"

failed=()
for name in "${meshes[@]}"; do
  echo
  echo "== $name"
  start=$(date +%s%N)
  if ! "$exe" validate "$assets/$name.slc" "$here/$name.obj" --quiet; then
    failed+=("$name")
  fi
  "$exe" info "$assets/$name.slc" --slice z=0.5 --png "$out/$name-z.png" | tail -n 1
  end=$(date +%s%N)
  echo "  total      $(( (end - start) / 1000000 )) ms for validate and slice"
done
demo_end=$(date +%s%N)

echo
echo "demo: ${#meshes[@]} colliders in $assets ($(( (demo_end - demo_start) / 1000000 )) ms)"
if [ ${#failed[@]} -gt 0 ]; then
  echo "demo: validation FAILED for: ${failed[*]}" >&2
  exit 1
fi
echo "demo: every collider validated against its mesh"

# The fluid: the wave hitting the sphere. With a display, in the viewer window; without one (or
# when the window cannot open: exit 3), headless: 2 s of it (120 steps of 1/60 s), statistics
# every 10 steps, a PLY frame every 10 steps, every second step rendered into an MP4 and step 120
# into a PNG. --check fails the demo if a particle ever ends up inside a collider or non-finite.
scene="$assets/wave-sphere.json" # the build copies it next to the colliders it names
if [ ! -f "$scene" ]; then
  echo "demo: $scene not found; build first (cmake --build --preset dev)" >&2
  exit 2
fi
play="$1/sluice-play"
echo
if [ -n "${DISPLAY:-}${WAYLAND_DISPLAY:-}" ]; then
  echo "demo: opening the viewer on $scene (drag to orbit, wheel to zoom, F1 for the keys, Esc to quit)"
  status=0
  "$play" "$scene" --shots "$out" || status=$?
  [ "$status" -ne 3 ] && exit "$status"
  echo "demo: the window could not open; playing headless instead"
fi
frames="$out/wave-sphere-ply"
video="$out/wave-sphere.mp4"
"$play" "$scene" --headless --steps 120 --stats-every 10 --check \
  --stats-json "$out/wave-sphere-stats.json" --dump-ply "$frames" --dump-every 10 \
  --video "$video" --every 2 --size 640x360 --zoom 0.75 --screenshot-at 120 --shots "$out"
echo "demo: video $video, picture $out/wave-sphere-000120.png"
echo "demo: PLY frames in $frames (open them in Blender, Houdini or MeshLab), statistics in" \
  "$out/wave-sphere-stats.json"
