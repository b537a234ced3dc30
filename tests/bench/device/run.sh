#!/usr/bin/env bash
# Measures the GPU floors of the performance and GPU-baker issues on the machine it runs on, and
# runs every shader through that machine's driver. Made for a bare NVIDIA machine reached with
# the `run` tool (../shared/device/README.md), after tests/bench/device/pack.sh here:
#
#   bash tests/bench/device/run.sh [--quick]
#
# SLUICE_DEVICE_PHASES (default "shaders solver render surface bodies bake") picks the phases, so a
# re-run after a fix spends the device's minutes on what changed; SLUICE_BAKE_MESHES (default
# "armadillo bunny00") and SLUICE_BAKE_REPEAT (5) size the baker phase.
#
# Works in /tmp/sluice-device-work: gpu.txt, gl-info.txt, one log and one JSON per benchmark,
# bake.md, shots/ (a picture of every shipped scene in both surface modes), and summary.txt,
# which states each floor with the measured figure. After every phase it puts summary.txt,
# results.tar.gz (all of it but the baked asset and the pictures) and shots.tar.gz into $OUT
# (default /tmp/sluice-device): the run tool brings back only a few files, and of a call that ran
# past its limit only those already there. Needs no Python. --quick: few steps and no
# 1M-particle scenes, to try the script on llvmpipe.
#
# Exit status: 0 when everything ran (whether or not a floor is met: summary.txt says), 1 when
# something failed to run (its log is in $OUT).
set -uo pipefail
cd "$(dirname "$0")/../../.."
quick=0
[ "${1:-}" = "--quick" ] && quick=1
final=${OUT:-/tmp/sluice-device}
out=/tmp/sluice-device-work
rm -rf "$out" && mkdir -p "$out/shots" "$final"
failed=0
phases=${SLUICE_DEVICE_PHASES:-shaders solver render surface bodies bake}
phase() { case " $phases " in *" $1 "*) return 0 ;; esac; return 1; }

# The GL/EGL dispatch libraries and NVIDIA's EGL vendor file, where this is the NVIDIA machine.
if ls .gl/*.deb >/dev/null 2>&1 && command -v dpkg >/dev/null && [ "$(id -u)" = 0 ] &&
  { command -v nvidia-smi >/dev/null || [ -e /dev/nvidiactl ]; }; then
  for f in .gl/*.deb; do dpkg -x "$f" /; done
  ldconfig
fi
vendor=/usr/local/nvidia/share/glvnd/egl_vendor.d/10_nvidia.json
[ -f "$vendor" ] && export __EGL_VENDOR_LIBRARY_FILENAMES=$vendor
pack=/tmp/sluice-pack
rm -rf "$pack" && mkdir -p "$pack" && tar -xzf .devpack/pack.tar.gz -C "$pack" || exit 1
export LD_LIBRARY_PATH=$pack/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}
bin=$pack/bin
# The scenes are unpacked into a copy, so .devpack stays under the carry limit for the next call.
scenes=/tmp/sluice-device-scenes
rm -rf "$scenes" && cp -r .devpack/scenes "$scenes" || exit 1
meshes=.devpack/meshes
for packed in "$scenes"/*.slc.gz; do
  [ -f "$packed" ] && { gunzip -f "$packed" || exit 1; }
done

# One step of the script: its output into $out/NAME.log, a line in the console either way.
step() {
  local name=$1; shift
  local start=$SECONDS
  if timeout "${SLUICE_STEP_TIMEOUT:-240}" "$@" >"$out/$name.log" 2>&1; then
    echo "ok    $name ($((SECONDS - start)) s)"
  else
    echo "FAIL  $name (exit $?, $((SECONDS - start)) s): see $name.log"; tail -n 5 "$out/$name.log"
    failed=1
  fi
}
# A number from a JSON file written by sluice-play --bench (one key per line): json FILE KEY.
json() { awk -v k="\"$2\":" '$1 == k { gsub(/,$/, "", $2); print $2; exit }' "$1"; }

# The floors, each with its measured figure, and everything so far into $final.
publish() {
  {
    echo "GPU: $(head -n 1 "$out/gpu.txt")"
    echo "GL:  $(grep -m1 '^renderer' "$out/gl-info.txt" 2>/dev/null)"
    f=$out/wave-sphere-15k.json
    if [ -f "$f" ]; then
      echo "15k wave-sphere ($(json "$f" particles) particles, $(json "$f" substeps) substeps," \
        "$(json "$f" meanIterations) iterations): $(json "$f" stepsPerSecondGpu) steps/s by GPU" \
        "timers, $(json "$f" stepsPerSecondWall) wall (floor: >= 3000)"
    fi
    f=$out/wave-sphere-15k.json
    if [ -f "$f" ]; then
      echo "  GPU commands per substep: $(json "$f" dispatchesPerSubstep) dispatches issued," \
        "$(json "$f" dispatchesRunPerSubstep) launched work, $(json "$f" barriersPerSubstep)" \
        "barriers; $(json "$f" neighbourLanes) neighbour lanes"
    fi
    f=$out/wave-sphere-15k-max3.json
    if [ -f "$f" ]; then
      echo "  at most 3 iterations (no idle dispatches issued after a stop at 2):" \
        "$(json "$f" stepsPerSecondGpu) steps/s by GPU timers, $(json "$f" stepsPerSecondWall)" \
        "wall; $(json "$f" dispatchesPerSubstep) dispatches issued," \
        "$(json "$f" dispatchesRunPerSubstep) launched, $(json "$f" meanIterations) iterations"
    fi
    for f in "$out"/wave-sphere-15k-lanes-*.json; do
      [ -f "$f" ] && echo "  with $(json "$f" neighbourLanes) lanes: $(json "$f" stepsPerSecondGpu)" \
        "steps/s by GPU timers, $(json "$f" stepsPerSecondWall) wall"
    done
    f=$out/dam-break-1m-4it.json
    if [ -f "$f" ]; then
      awk -v s="$(json "$f" medianStepMs)" -v n="$(json "$f" substeps)" -v p="$(json "$f" particles)" \
        'BEGIN { printf "1M dam break, 4 iterations (%d particles): %.3f ms per substep (full solver step), %.3f ms per %d-substep frame (floor: <= 4 ms per step)\n", p, s / n, s, n }'
    fi
    f=$out/dam-break-1m.json
    if [ -f "$f" ]; then
      awk -v s="$(json "$f" medianStepMs)" -v e="$(json "$f" emit)" -v n="$(json "$f" substeps)" \
        'BEGIN { printf "1M dam break, shipped defaults: %.3f ms per substep (floor: <= 1.0), emit %.4f ms per substep (floor: <= 0.02)\n", s / n, e / n }'
    fi
    f=$out/render.json
    if [ -f "$f" ]; then
      echo "impostor spheres, $(json "$f" particles) particles at $(json "$f" width)x$(json "$f" height):" \
        "$(json "$f" fluid) ms GPU (floor at 1M, 1920x1080: <= 2 ms), frame $(json "$f" medianFrameMs)" \
        "ms, wall $(json "$f" wallMsPerFrame) ms per waited-for frame;" \
        "timers cover drawing: $(json "$f" gpuTimersCoverDrawing)"
    fi
    f=$out/render-raster.json
    if [ -f "$f" ]; then
      echo "  the same, every sphere rasterised (--raster-spheres): $(json "$f" fluid) ms GPU," \
        "frame $(json "$f" medianFrameMs) ms, wall $(json "$f" wallMsPerFrame) ms"
    fi
    f=$out/render-fluid.json
    if [ -f "$f" ]; then
      echo "screen-space surface, $(json "$f" particles) particles at $(json "$f" width)x$(json "$f" height):" \
        "frame $(json "$f" medianFrameMs) ms GPU (floor at 1M, 1920x1080: <= 3 ms), wall" \
        "$(json "$f" wallMsPerFrame) ms per waited-for frame; fluid pass $(json "$f" fluid) ms:" \
        "spheres $(json "$f" spheres), smooth $(json "$f" smooth), shade $(json "$f" shade) ms"
    fi
    grep -m1 '^surface meshes' "$out/surface-mesh-1m.log" 2>/dev/null |
      sed 's/$/ (floor: >= 20 M particles\/s)/'
    grep -m1 '^  surface stages' "$out/surface-mesh-1m.log" 2>/dev/null
    grep -m1 '^surface meshes' "$out/surface-mesh-1m-restvolume.log" 2>/dev/null |
      sed 's/^/--no-surface-normalised: /'
    grep -m1 '^  surface stages' "$out/surface-mesh-1m-restvolume.log" 2>/dev/null
    f=$out/render-mesh.json
    if [ -f "$f" ]; then
      echo "surface mesh mode, $(json "$f" particles) particles at $(json "$f" width)x$(json "$f" height):" \
        "fluid pass $(json "$f" fluid) ms GPU (the mesh rebuilt every frame), frame" \
        "$(json "$f" medianFrameMs) ms, wall $(json "$f" wallMsPerFrame) ms"
    fi
    for f in "$out"/wave-sphere-15k.json "$out"/dam-break-1m-4it.json; do
      [ -f "$f" ] && echo "$(basename "$f" .json): $(json "$f" bytesPerParticle) bytes per particle (floor: <= 200)"
    done
    for tag in s20mm s5mm; do
      f0=$out/bodies-0-$tag.json
      [ -f "$f0" ] || continue
      base=$(json "$f0" medianStepMs)
      echo "bodies ($tag, $(json "$f0" particles) particles): fluid-only step $base ms"
      for n in 1 16 64; do
        f=$out/bodies-$n-$tag.json
        [ -f "$f" ] || continue
        awk -v n=$n -v b="$base" -v s="$(json "$f" medianStepMs)" -v p="$(json "$f" bodies)" \
          'BEGIN { printf "  %2d bodies: step %.3f ms, %.2fx fluid-only, coupling share %.0f %%, body pass %.3f ms (%.0f %%)\n", n, s, s / b, 100 * (1 - b / s), p, 100 * p / s }'
      done
    done
    echo "bake (bake_bench, seconds; floors: <= 0.03 s at 128^3, <= 0.2 s at 256^3):"
    grep -E '^\|' "$out/bench-bake.log" 2>/dev/null
    grep -E '^\|' "$out/bench-bake-bunny00.log" 2>/dev/null
    grep -E 'max|mismatch' "$out/validate-armadillo.log" 2>/dev/null | head -n 4
  } >"$out/summary.txt"
  cp "$out/summary.txt" "$final/summary.txt"
  tar -czf "$final/results.tar.gz" -C "$out" --exclude='*.slc' --exclude=./shots .
  # The pictures apart: if they are over what the run tool brings back, the figures still come.
  tar -czf "$final/shots.tar.gz" -C "$out" shots
}

(nvidia-smi -L 2>/dev/null || echo "no nvidia-smi") >"$out/gpu.txt"
cat .devpack/commit >>"$out/gpu.txt" 2>/dev/null
step gl-info "$bin/sluice-bake" gl-info
cp "$out/gl-info.log" "$out/gl-info.txt"

# Every shader through this driver: each shipped scene simulated and checked, pictured in both
# surface modes (the render passes), and a mesh baked on the GPU and validated against CGAL.
steps=60
[ $quick = 1 ] && steps=4
res=128
[ $quick = 1 ] && res=32
if phase shaders; then
  for scene in "$scenes"/*.json; do
    name=$(basename "$scene" .json)
    case $name in *-15k|*-1m|*-1m-4it|bodies-*) continue ;; esac
    for surface in spheres fluid mesh; do
      step "shader-$name-$surface" "$bin/sluice-play" "$scene" --headless --check --quiet \
        --steps $steps --screenshot-at $steps --shots "$out/shots/$surface" --surface $surface \
        --size 1280x720
    done
  done
  step bake-armadillo "$bin/sluice-bake" bake "$meshes/armadillo.off" --backend gpu \
    --resolution $res -o "$out/armadillo.slc"
  step validate-armadillo "$bin/sluice-bake" validate "$out/armadillo.slc" "$meshes/armadillo.off"
  publish
fi

# The solver floors. The 15k scene keeps the shipped adaptive iterations; the 1M scenes run
# exactly 4 iterations a substep and the shipped defaults.
if phase solver; then
  if [ $quick = 1 ]; then
    step bench-15k "$bin/sluice-play" "$scenes/wave-sphere-15k.json" --bench --warmup 2 \
      --steps 3 --bench-json "$out/wave-sphere-15k.json"
  else
    step bench-15k "$bin/sluice-play" "$scenes/wave-sphere-15k.json" --bench --warmup 300 \
      --steps 3000 --bench-json "$out/wave-sphere-15k.json"
    # The same with maxIterations 3: what the early stop's 10 idle dispatches a substep cost.
    step bench-15k-max3 "$bin/sluice-play" "$scenes/wave-sphere-15k-max3.json" --bench \
      --warmup 300 --steps 3000 --bench-json "$out/wave-sphere-15k-max3.json"
    step bench-1m-4it "$bin/sluice-play" "$scenes/dam-break-1m-4it.json" --bench --warmup 30 \
      --steps 200 --bench-json "$out/dam-break-1m-4it.json"
    step bench-1m "$bin/sluice-play" "$scenes/dam-break-1m.json" --bench --warmup 30 \
      --steps 200 --bench-json "$out/dam-break-1m.json"
    # The neighbour lanes the GPU does not pick for 15k, for comparison.
    for lanes in 1 2 4 16; do
      step "bench-15k-lanes-$lanes" "$bin/sluice-play" "$scenes/wave-sphere-15k.json" --bench \
        --warmup 100 --steps 1000 --neighbour-lanes $lanes \
        --bench-json "$out/wave-sphere-15k-lanes-$lanes.json"
    done
  fi
  publish
fi

# The render floors: the 1M dam break after 35 frames of 4 iterations, drawn at 1920x1080 as
# impostor spheres and as the screen-space surface.
if phase render; then
  rscene=$scenes/dam-break-1m-4it.json
  rwarm=30 rsteps=5 rframes=300
  [ $quick = 1 ] && rscene=$scenes/dam-break.json rwarm=1 rsteps=1 rframes=3
  for surface in spheres fluid; do
    json_out=$out/render.json
    [ $surface = fluid ] && json_out=$out/render-fluid.json
    step "bench-render-$surface" "$bin/sluice-play" "$rscene" --bench --warmup $rwarm \
      --steps $rsteps --bench-frames $rframes --surface $surface --bench-json "$json_out"
  done
  # The reconstructed surface mesh, rebuilt every frame (fewer frames: it is the slow mode).
  step bench-render-mesh "$bin/sluice-play" "$rscene" --bench --warmup $rwarm \
    --steps $rsteps --bench-frames 30 --surface mesh --bench-json "$out/render-mesh.json"
  # Every sphere rasterised, for comparison with the compute pass for small ones.
  step bench-render-raster "$bin/sluice-play" "$rscene" --bench --warmup $rwarm \
    --steps $rsteps --bench-frames $rframes --raster-spheres --bench-json "$out/render-raster.json"
  publish
fi

# The fluid's surface mesh (issue 28: at least 20 M particles/s on a GPU): the 1M dam break
# after its warm-up frames, one mesh a step, reconstructed, downloaded and written as PLY.
if phase surface; then
  sscene=$scenes/dam-break-1m-4it.json ssteps=30
  [ $quick = 1 ] && sscene=$scenes/dam-break.json ssteps=2
  rm -rf /tmp/sluice-device-surface
  step surface-mesh-1m "$bin/sluice-play" "$sscene" --headless --steps $ssteps \
    --surface-mesh /tmp/sluice-device-surface --surface-every 5 --stats-json "$out/surface-mesh.json"
  # The rest-volume field beside the default (density-normalised: two field passes).
  rm -rf /tmp/sluice-device-surface
  step surface-mesh-1m-restvolume "$bin/sluice-play" "$sscene" --headless --steps $ssteps \
    --surface-mesh /tmp/sluice-device-surface --surface-every 5 --no-surface-normalised
  publish
fi

# What dynamic bodies cost (issue 13): tests/bench/pbf/bodies.py's pool with 0, 1, 16 and 64
# floating crates, at its llvmpipe spacing and at 5 mm, each with its fluid-only run.
bsteps=100
[ $quick = 1 ] && bsteps=2
if phase bodies; then
  for tag in s20mm s5mm; do
    [ $quick = 1 ] && [ $tag = s5mm ] && continue
    for n in 0 1 16 64; do
      step "bench-bodies-$n-$tag" "$bin/sluice-play" "$scenes/bodies-$n-$tag.json" --bench \
        --warmup 30 --steps $bsteps --bench-json "$out/bodies-$n-$tag.json"
    done
  done
  publish
fi

# The baker floors (and the CPU peers on this machine's cores).
if phase bake; then
  for mesh in ${SLUICE_BAKE_MESHES:-armadillo bunny00}; do
    log=bench-bake-$mesh
    [ $mesh = armadillo ] && log=bench-bake
    if [ $quick = 1 ]; then
      step $log "$bin/bake_bench" "$meshes/$mesh.off" 32 --repeat 1
    else
      step $log "$bin/bake_bench" "$meshes/$mesh.off" 128 256 --repeat "${SLUICE_BAKE_REPEAT:-5}"
    fi
  done
  cp "$out/bench-bake.log" "$out/bake.md" 2>/dev/null
fi

publish
cat "$out/summary.txt"
exit $failed
