#!/usr/bin/env bash
# One-command set-up for a fresh Debian 12 machine (run as root):
#   bash cmake/setup.sh demo    installs what is missing, builds, bakes and validates the demo
#   bash cmake/setup.sh test    installs what is missing, builds, runs the whole test suite
#   bash cmake/setup.sh asan    the same suite built with AddressSanitizer + UBSan (CI runs it too)
#   bash cmake/setup.sh fuzz    builds the libFuzzer targets with clang (`fuzz` preset, or
#                               SLUICE_FUZZ_PRESET) and runs each for SLUICE_FUZZ_SECONDS (60)
# A second run skips what is already installed and rebuilds only what changed.
set -euo pipefail
cd "$(dirname "$0")/.."

mode=${1:-}
case "$mode" in
  demo|test|asan|fuzz) ;;
  *) echo "usage: bash cmake/setup.sh demo|test|asan|fuzz" >&2; exit 2 ;;
esac

# Build tools and libraries (Debian 12 package names).
packages=(
  cmake ninja-build g++ pkg-config python3 python3-venv python3-dev
  libassimp-dev libcgal-dev libgmp-dev libmpfr-dev libboost-dev libboost-iostreams-dev libeigen3-dev
  libopenvdb-dev libtbb-dev libcereal-dev libcli11-dev libglm-dev libstb-dev libxxhash-dev libnanovdb-dev libnanovdb-tools
  libspdlog-dev libfmt-dev nlohmann-json3-dev rapidjson-dev
  libegl-dev libgl-dev libegl-mesa0 libgl1-mesa-dri libglfw3-dev libimgui-dev ffmpeg
  libgtest-dev libgmock-dev libbenchmark-dev glslang-tools
)
# Test data: third-party meshes (assimp's models, CGAL's data set).
if [ "$mode" != demo ]; then
  packages+=(assimp-testmodels libcgal-demo xvfb xauth libopenvdb-tools libepoxy-dev)
fi

# libFuzzer: clang with its sanitizer runtimes (libclang-rt-dev) and llvm-symbolizer (llvm).
if [ "$mode" = fuzz ]; then
  packages+=(clang libclang-rt-dev llvm)
fi

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  if [ "$(id -u)" -ne 0 ]; then
    echo "setup: missing Debian packages: ${missing[*]} (run as root, or install them)" >&2
    exit 2
  fi
  echo "setup: installing ${missing[*]}"
  apt-get update -q
  DEBIAN_FRONTEND=noninteractive apt-get install -y -q --no-install-recommends "${missing[@]}"
fi

jobs=$(nproc)
preset=dev
[ "$mode" = asan ] && preset=asan
if [ "$mode" = fuzz ]; then
  # SLUICE_FUZZ_PRESET=fuzz-ubsan: the same targets without ASan, several times the executions
  # per second on the mesh target (docs/reliability.md).
  fuzz_preset=${SLUICE_FUZZ_PRESET:-fuzz}
  cmake --preset "$fuzz_preset" >/dev/null
  cmake --build --preset "$fuzz_preset" -j "$jobs"
  exec bash tests/fuzz/run.sh --build "build/$fuzz_preset" --seconds "${SLUICE_FUZZ_SECONDS:-60}" \
    --jobs "${SLUICE_FUZZ_JOBS:-1}"
fi
cmake --preset "$preset" >/dev/null
cmake --build --preset "$preset" -j "$jobs"

if [ "$mode" = demo ]; then
  bash assets/demo.sh "build/$preset/bin"
else
  ctest --preset "$preset" -j "$jobs"
fi
