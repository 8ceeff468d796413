#!/usr/bin/env bash
# check-agreement.sh: do the kernels and the CPU reference estimate the same
# image on every scene a user may bring? Renders each scene under the given
# files and folders small and fast, once on a kernel variant and once on the
# CPU reference (independent seeds), and compares the two with
# `wavepath compare --images`. One line per render pair, then a summary.
#
#   scripts/check-agreement.sh [options] PATH...
#
# PATH: scene files or folders searched recursively for darts JSON scenes
# (test files, "type": "tests", are left out), CS184 COLLADA (.dae) and
# glTF (.gltf, .glb).
#   --wavepath BIN     the binary (default: build/wavepath beside this script)
#   --spp N            samples per pixel of each side (default 32)
#   --size W H         image size (default 96 72); a .dae gets it as the
#                      course's -r, the central crop of its 800x600 frame
#   --variants A,B     kernel variants, each compared with the CPU (default gpu)
#   --out DIR          keep the renders (and an HTML report of each
#                      disagreement) in DIR (default: a scratch folder, removed)
#   --require-all      a scene that does not load counts as a failure (default:
#                      listed as skipped, with the loader's message)
#   --list FILE        also write the lines to FILE
#   --render-options "OPTS"  more options for every render of both sides,
#                      e.g. "--spectral"
#
# A .dae is rendered with the course's command line (-t 2 -s N -l 4 -m 5
# -r W H) under the course's estimator, again with --consistent-lights, and
# again as the 3-2 skeleton builds the scene (--cs184 3-2).
# The comparisons share one family-wise level: each runs at 0.01 / (number
# of comparisons), so a clean folder of a hundred scenes is not expected to
# show a false disagreement. Exit status: 0 when every pair agrees, 1 when
# one differs (or fails to render, or with --require-all fails to load), 2 on
# bad usage.
set -uo pipefail
here=$(cd "$(dirname "$0")" && pwd)
wavepath=$here/../build/wavepath
spp=32 width=96 height=72 variants=gpu out="" requireAll=0 list="" renderOptions=""
paths=()
usage() { sed -n '2,30p' "$0" | sed 's/^# \{0,1\}//' >&2; exit 2; }
while [ $# -gt 0 ]; do
  case $1 in
    --wavepath) wavepath=$2; shift 2 ;;
    --spp) spp=$2; shift 2 ;;
    --size) width=$2 height=$3; shift 3 ;;
    --variants) variants=$2; shift 2 ;;
    --out) out=$2; shift 2 ;;
    --require-all) requireAll=1; shift ;;
    --list) list=$2; shift 2 ;;
    --render-options) renderOptions=$2; shift 2 ;;
    -h|--help) usage ;;
    -*) echo "check-agreement.sh: unknown option $1" >&2; usage ;;
    *) paths+=("$1"); shift ;;
  esac
done
[ ${#paths[@]} -gt 0 ] || usage
[ -x "$wavepath" ] || { echo "check-agreement.sh: no wavepath binary at $wavepath (--wavepath BIN)" >&2; exit 2; }
if [ -z "$out" ]; then
  out=$(mktemp -d)
  trap 'rm -rf "$out"' EXIT
fi
mkdir -p "$out"
[ -z "$list" ] || : >"$list"

# The scenes, in a stable order.
scenes=()
for p in "${paths[@]}"; do
  [ -e "$p" ] || { echo "check-agreement.sh: $p: no such file or folder" >&2; exit 2; }
  while IFS= read -r -d '' f; do
    case $f in
      *.json) grep -Eq '"type"[[:space:]]*:[[:space:]]*"tests"' "$f" && continue ;;
    esac
    scenes+=("$f")
  done < <(find "$p" -type f \( -name '*.json' -o -name '*.dae' -o -name '*.gltf' -o -name '*.glb' \) -print0 | sort -z)
done

# Each scene's render settings: "label|extra render options".
settings_of() {
  case $1 in
    *.dae) echo "course|"; echo "consistent|--consistent-lights"; echo "3-2|--cs184 3-2" ;;
    *) echo "scene|" ;;
  esac
}
# Every render takes the --render-options too.
settings_with_options() {
  settings_of "$1" | while IFS='|' read -r label extra; do
    echo "$label${renderOptions:+ $renderOptions}|$extra $renderOptions"
  done
}
IFS=, read -r -a variantList <<<"$variants"
comparisons=0
for s in "${scenes[@]}"; do comparisons=$((comparisons + $(settings_with_options "$s" | wc -l) * ${#variantList[@]})); done
[ $comparisons -gt 0 ] || { echo "check-agreement.sh: no scenes under ${paths[*]}" >&2; exit 2; }
alpha=$(awk -v n=$comparisons 'BEGIN { printf "%.6g", 0.01 / n }')

say() { echo "$1"; [ -z "$list" ] || echo "$1" >>"$list"; }
# render SCENE OUT_BASE RENDERER EXTRA: one render; prints its wall time.
render() {
  local scene=$1 base=$2 renderer=$3 extra=$4 seed=1 start
  local -a who=()
  if [ "$renderer" = cpu ]; then who=(--cpu); seed=2; else who=(--variant "$renderer"); fi
  start=$(date +%s.%N)
  case $scene in
    *.dae) "$wavepath" render -t 2 -s "$spp" -l 4 -m 5 -r "$width" "$height" -f "$base.png" "${who[@]}" --seed $seed --quiet $extra "$scene" ;;
    *) "$wavepath" render "$scene" --spp "$spp" --resolution "$width" "$height" -o "$base.png" "${who[@]}" --seed $seed --quiet $extra ;;
  esac >"$base.log" 2>&1
  local rc=$?
  awk -v a="$start" -v b="$(date +%s.%N)" 'BEGIN { printf "%.1f", b - a }' >"$base.time"
  return $rc
}

agree=0 differ=0 skipped=0 errors=0 n=0
say "agreement: ${#scenes[@]} scenes, $comparisons comparisons at ${width}x${height}, $spp spp per side, each at level $alpha (family-wise 0.01)"
for s in "${scenes[@]}"; do
  while IFS='|' read -r label extra; do
    for v in "${variantList[@]}"; do
      n=$((n + 1))
      base=$out/$n-$(basename "$s" | tr -c 'A-Za-z0-9._\n-' _)
      name="$s [$label, $v]"
      render "$s" "$base-$v" "$v" "$extra"
      rc=$?
      if [ $rc -eq 2 ]; then
        skipped=$((skipped + 1))
        say "SKIP   $name: does not load: $(grep -v '^wavepath: note' "$base-$v.log" | head -n 1)"
        continue
      elif [ $rc -ne 0 ]; then
        errors=$((errors + 1))
        say "ERROR  $name: $v render exit $rc: $(tail -n 1 "$base-$v.log")"
        continue
      fi
      if ! render "$s" "$base-cpu" cpu "$extra"; then
        errors=$((errors + 1))
        say "ERROR  $name: CPU render failed: $(tail -n 1 "$base-cpu.log")"
        continue
      fi
      verdict=$("$wavepath" compare --images "$base-$v.exr" "$base-cpu.exr" --alpha "$alpha" --report "$base-report" 2>&1)
      rc=$?
      [ $rc -eq 1 ] || rm -rf "$base-report"
      bias=$(grep -o 'relative bias [^;]*(95%)' <<<"$verdict" | head -n 1)
      times="$v $(cat "$base-$v.time") s, cpu $(cat "$base-cpu.time") s"
      if [ $rc -eq 0 ]; then
        agree=$((agree + 1))
        say "AGREE  $name: $bias ($times)"
      elif [ $rc -eq 1 ]; then
        differ=$((differ + 1))
        say "DIFFER $name: $(head -n 1 <<<"$verdict") ($times; report $base-report/index.html)"
      else
        errors=$((errors + 1))
        say "ERROR  $name: compare exit $rc: $(head -n 1 <<<"$verdict")"
      fi
    done
  done < <(settings_with_options "$s")
done
say "summary: $n comparisons: $agree agree, $differ differ, $skipped skipped (do not load), $errors errors"
[ $differ -eq 0 ] && [ $errors -eq 0 ] && { [ $requireAll -eq 0 ] || [ $skipped -eq 0 ]; }
