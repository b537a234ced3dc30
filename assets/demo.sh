#!/usr/bin/env bash
# The demo: bakes every demo collider with the CGAL backend (only those the build has not
# already baked, see assets/CMakeLists.txt), validates it against its mesh (storing the figures
# in the asset) and draws a slice of it.
#   bash assets/demo.sh BIN_DIR [OUT_DIR]
# BIN_DIR holds sluice-bake (build/dev/bin); OUT_DIR defaults to build/dev/assets.
# Called by `bash cmake/setup.sh demo`. Exits 1 if a collider fails validation, 2 on bad usage.
set -euo pipefail

here=$(cd "$(dirname "$0")" && pwd)
root=$(dirname "$here")
if [ $# -lt 1 ] || [ $# -gt 2 ]; then
  echo "usage: bash assets/demo.sh BIN_DIR [OUT_DIR]" >&2
  exit 2
fi
exe="$1/sluice-bake"
out=${2:-$root/build/dev/assets}
if [ ! -x "$exe" ]; then
  echo "demo: $exe not found; build first (cmake --preset dev && cmake --build --preset dev)" >&2
  exit 2
fi
mkdir -p "$out"
out=$(cd "$out" && pwd) # the manifest below names files by absolute path

# [m] one grid spacing for every collider, as a scene would use: 2.7 voxels across the 2 cm
# walls of the funnel and pea shooter, 4 across the tank's 3 cm walls, and a demo of seconds.
voxel_size=0.0075
meshes=(sphere funnel peashooter tank)

"$exe" --version
demo_start=$(date +%s%N)

# One batch for the bakes: the build bakes the same colliders with the same settings into
# build/<preset>/assets (sluice_bake_colliders in assets/CMakeLists.txt), so there they are
# fresh and nothing is baked again; anywhere else batch bakes them, on all cores.
json_path() { local p=${1//\\/\\\\}; printf '"%s"' "${p//\"/\\\"}"; }
manifest=$(mktemp --suffix=.json)
trap 'rm -f "$manifest"' EXIT
{
  echo '{"colliders": ['
  sep=""
  for name in "${meshes[@]}"; do
    printf '%s  {"mesh": %s, "output": %s, "voxelSize": %s, "backend": "cgal"}' "$sep" \
      "$(json_path "$here/$name.obj")" "$(json_path "$out/$name.slc")" "$voxel_size"
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
  if ! "$exe" validate "$out/$name.slc" "$here/$name.obj" --write --quiet; then
    failed+=("$name")
  fi
  "$exe" info "$out/$name.slc" --slice z=0.5 --png "$out/$name-z.png" | tail -n 1
  end=$(date +%s%N)
  echo "  total      $(( (end - start) / 1000000 )) ms for validate and slice"
done
demo_end=$(date +%s%N)

echo
echo "demo: ${#meshes[@]} colliders in $out ($(( (demo_end - demo_start) / 1000000 )) ms)"
if [ ${#failed[@]} -gt 0 ]; then
  echo "demo: validation FAILED for: ${failed[*]}" >&2
  exit 1
fi
echo "demo: every collider validated against its mesh"
