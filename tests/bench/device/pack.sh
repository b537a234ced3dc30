#!/usr/bin/env bash
# Builds and packs everything tests/bench/device/run.sh needs on a bare NVIDIA machine
# (../shared/device/README.md), into .gl/ and .devpack/ at the repository root (both kept out of
# git through .git/info/exclude). Then one device call measures every GPU floor:
#
#   bash tests/bench/device/pack.sh                 # here: ~10 minutes the first time
#   run(command="bash tests/bench/device/run.sh", carry=[".gl", ".devpack"])
#
# What it makes:
#   .gl/*.deb                  the GL/EGL dispatch libraries (libglvnd), downloaded once
#   .devpack/pack.tar.gz       sluice-play, sluice-bake and bake_bench (a release build with the
#                              bench tools, build/device) and every shared library they need
#                              but libc, GL and EGL (../shared/device/pack)
#   .devpack/scenes/           the benchmark scenes (make_scenes.py) and the shipped ones, with
#                              their colliders
#   .devpack/meshes/           the meshes the baker is timed on (CGAL's armadillo and bunny)
set -euo pipefail
cd "$(dirname "$0")/../../.."
build=${SLUICE_DEVICE_BUILD:-build/device}
shared=${SLUICE_SHARED:-../shared}

exclude=$(git rev-parse --git-path info/exclude)
mkdir -p "$(dirname "$exclude")"
for ignored in /.gl/ /.devpack/; do
  grep -qxF "$ignored" "$exclude" 2>/dev/null || echo "$ignored" >>"$exclude"
done

if ! ls .gl/*.deb >/dev/null 2>&1; then
  echo "pack: downloading the GL/EGL dispatch libraries into .gl/"
  mkdir -p .gl /tmp/amd64/partial
  o=(-oAPT::Architecture=amd64 -oAPT::Architectures=amd64 -oDir::State::Lists=/tmp/amd64)
  apt-get "${o[@]}" update >/dev/null
  (cd .gl && apt-get "${o[@]}" download libvulkan1 libegl1 libglvnd0 libopengl0 libgl1 libglx0 libgles2)
fi

if [ ! -f "$build/CMakeCache.txt" ]; then
  cmake --preset release -B "$build" -DSLUICE_BUILD_TESTS=ON
fi
cmake --build "$build" -j"$(nproc)" --target sluice-play sluice-bake bake_bench sluice_assets

rm -rf .devpack
"$shared/device/pack" .devpack "$build/bin/sluice-play" "$build/bin/sluice-bake" \
  "$build/bin/bake_bench"
python3 tests/bench/device/make_scenes.py --assets "$build/assets" --out .devpack/scenes
# The run tool carries 64 MiB at most: the big colliders (the terrain's NanoVDB band, 61 MB)
# travel gzipped, and run.sh unpacks them.
find .devpack/scenes -name '*.slc' -size +8M -exec gzip -9 {} +
mkdir -p .devpack/meshes
meshes=$(find "$build" build -path '*cgal/data/meshes' -type d 2>/dev/null | head -n 1)
[ -n "$meshes" ] || { echo "pack: CGAL's meshes not found under $build (configure with tests on)" >&2; exit 2; }
cp "$meshes/armadillo.off" "$meshes/bunny00.off" .devpack/meshes/
git rev-parse HEAD >.devpack/commit
du -sh .gl .devpack
echo "pack: done; on the device: bash tests/bench/device/run.sh (carry .gl and .devpack)"
