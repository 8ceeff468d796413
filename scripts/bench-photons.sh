#!/usr/bin/env bash
# The photon mapper against the path tracer on caustics: a glass ball and a
# mirror ball on a diffuse floor under a small sphere light
# (tests/data/features/photons.json) at WIDTH x HEIGHT (default 192x144).
# A reference by the path tracer at REF_SPP (default 16384) samples, then
# each estimator at a few sample counts: the wall time of the whole run
# (loading, the photon pass and the kernels' creation included, the same
# for both but the photons) and its RMSE relative to the reference's mean,
# so that equal times can be compared. The photon mapper's error does not fall below its bias (the
# search disc blurs the caustic); the path tracer's falls as 1/sqrt(spp),
# slowly where caustics make it noisy. On the default Vulkan device (or
# --cpu).
# RMSE and MAE (mean absolute error), both relative to the reference's mean:
# the path tracer's fireflies weigh on the first far more than the second.
# REF_FILE=path.pfm keeps the reference there and reuses it when it exists.
# Usage: [WIDTH=w HEIGHT=h REF_SPP=n REF_FILE=f] scripts/bench-photons.sh [BUILD_DIR] [extra render options]   (default: build)
set -euo pipefail
build=$(realpath "${1:-build}")
shift $(( $# > 0 ? 1 : 0 ))
cd "$(dirname "$0")/.."
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
width=${WIDTH:-192}
height=${HEIGHT:-144}
ref=${REF_SPP:-16384}
scene=tests/data/features/photons.json
echo "machine: $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs)"
"$build/wavepath" devices | sed -n 2p
# The wall time of a command, in seconds.
wall() {
  local t0 t1
  t0=$(date +%s.%N)
  "$@" >/dev/null 2>&1
  t1=$(date +%s.%N)
  awk -v a="$t0" -v b="$t1" 'BEGIN { printf "%.2f", b - a }'
}
rmse() {
  python3 - "$reference" "$1" <<'PY'
import math, struct, sys
def pfm(path):
    with open(path, "rb") as f:
        f.readline()
        w, h = map(int, f.readline().split())
        f.readline()
        return struct.unpack("<%df" % (w * h * 3), f.read(w * h * 12))
a, b = pfm(sys.argv[1]), pfm(sys.argv[2])
mean = max(sum(a) / len(a), 1e-12)
rmse = math.sqrt(sum((x - y) ** 2 for x, y in zip(a, b)) / len(a)) / mean
mae = sum(abs(x - y) for x, y in zip(a, b)) / len(a) / mean
print("%10.4f %10.4f" % (rmse, mae))
PY
}
# The photon mapper with a bench's photon count: 2M photons, the 30 nearest
# within 0.05 (the test scene's 200k photons keep its tests fast).
python3 -c '
import json
scene = json.load(open("tests/data/features/photons.json"))
scene["integrator"].update({"photons": 2000000, "search count": 30, "search radius": 0.05})
print(json.dumps(scene))' >"$out/photons.json"
# The photon pass alone, 2M photons: on the host's cores (as the CPU
# reference traces them; `wavepath info`) and by the device's photons kernel
# (a GPU renderer's; `render --stage-times`), with the ordering, balancing
# and upload that follow both. The caustic scene, open, loses most photons
# after a bounce or two; the Cornell box keeps them for many.
python3 -c '
import json
scene = json.load(open("scenes/cornell-box.json"))
scene["integrator"] = {"type": "photon mapper", "photons": 2000000}
print(json.dumps(scene))' >"$out/cornell-photons.json"
sed -i "s#\"filename\": \"#\"filename\": \"$PWD/scenes/#g" "$out/cornell-photons.json"
printf '%-28s %10s %10s %10s\n' "photon pass, 2M photons" "records" "host s" "device s"
for s in "$out/photons.json" "$out/cornell-photons.json"; do
  host=$("$build/wavepath" info "$s" | sed -n 's/^photons .* in \([0-9.]*\) s, \([0-9]*\) records.*/\1 \2/p')
  device=$("$build/wavepath" render "$s" -r 64 64 --spp 1 --stage-times --photon-pass kernels -o "$out/pass.pfm" "$@" | sed -n 's/^photon map: .* in \([0-9.]*\) s.*/\1/p')
  printf '%-28s %10s %10s %10s\n' "$(basename "$s")" "${host#* }" "${host% *}" "${device:-(cpu)}"
done
reference=${REF_FILE:-$out/ref.pfm}
[ -f "$reference" ] || "$build/wavepath" render "$scene" -r "$width" "$height" --integrator "path tracer mis" --spp "$ref" -o "$reference" "$@" >/dev/null
printf '%-26s %8s %10s %10s\n' "estimator" "time s" "rel. RMSE" "rel. MAE"
for spp in 16 64 256 1024; do
  t=$(wall "$build/wavepath" render "$scene" -r "$width" "$height" --integrator "path tracer mis" --spp "$spp" -o "$out/pt.pfm" "$@")
  printf '%-26s %8s %s\n' "path tracer mis, $spp spp" "$t" "$(rmse "$out/pt.pfm")"
done
for spp in 4 16 64; do
  t=$(wall "$build/wavepath" render "$out/photons.json" -r "$width" "$height" --spp "$spp" -o "$out/pm.pfm" "$@")
  printf '%-26s %8s %s\n' "photon mapper, $spp spp" "$t" "$(rmse "$out/pm.pfm")"
done
