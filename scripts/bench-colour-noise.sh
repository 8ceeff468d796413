#!/usr/bin/env bash
# bench-colour-noise.sh: the spectral mode's colour noise against RGB's at
# equal time (issue 58; docs/benchmarks.md, "Spectral mode"). Renders a
# scene in each mode for the same time budget (pipeline creation included),
# and in each mode a reference with REF_SPP samples, then prints each mode's
# RMSE of chromaticity against its own reference: per pixel, the colour
# with its luminance matched to the reference's, less the reference's, over
# the reference's luminance; over the pixels a tenth of the reference's mean
# luminance and brighter. Also RGB against the spectral reference.
#
#   scripts/bench-colour-noise.sh [SCENE] [SECONDS] [REF_SPP] [SIZE]
#
# Defaults: tests/data/features/dispersion.json (a flint ball, a diamond
# and frosted water over stripes), 4 s, 16384 spp, 48 (pixels square).
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
wavepath=${WAVEPATH:-$here/../build/wavepath}
scene=${1:-$here/../tests/data/features/dispersion.json}
seconds=${2:-4}
refSpp=${3:-16384}
size=${4:-48}
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
for mode in rgb spectral; do
  "$wavepath" render "$scene" -r "$size" "$size" --"$mode" --spp "$refSpp" --seed 1 -o "$out/$mode-ref.pfm" --quiet
  "$wavepath" render "$scene" -r "$size" "$size" --"$mode" --spp 1000000 --time "${seconds}s" --seed 2 -o "$out/$mode.pfm" --quiet
done
python3 - "$out" <<'PY'
import math, struct, sys
def pfm(path):
    with open(path, "rb") as f:
        kind = f.readline().strip()
        w, h = map(int, f.readline().split())
        scale = float(f.readline())
        n = w * h * (3 if kind == b"PF" else 1)
        data = struct.unpack(("<" if scale < 0 else ">") + "%df" % n, f.read(4 * n))
    return [data[3 * i:3 * i + 3] for i in range(w * h)]
out = sys.argv[1]
# A pixel's colour error with its luminance matched to the reference's:
# rgb - ref * (Y / Y_ref), over Y_ref (Y the luminance), so that only the
# chromaticity's error remains, and no noisy denominator of its own inflates
# it (a single wavelength's sRGB may sum to about 0).
def luminance(p):
    return 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2]
# Each mode against its own reference (its noise), and RGB against the
# spectral reference (the image dispersion really makes: RGB's three bands
# are a bias there).
for mode, against in (("rgb", "rgb"), ("spectral", "spectral"), ("rgb", "spectral")):
    ref, img = pfm(out + "/" + against + "-ref.pfm"), pfm(out + "/" + mode + ".pfm")
    mean = sum(luminance(p) for p in ref) / len(ref)
    err, n = 0.0, 0
    for r, p in zip(ref, img):
        yr = luminance(r)
        if yr < 0.1 * mean:
            continue
        k = luminance(p) / yr
        err += sum(((p[c] - r[c] * k) / yr) ** 2 for c in range(3))
        n += 1
    print("%-9s against the %-9s reference: chromaticity RMSE %.5f over %d pixels" % (mode, against, math.sqrt(err / max(n, 1)), n))
PY
