#!/usr/bin/env bash
# check-course-refs.sh: wavepath's images of the courses' own files against
# the courses' reference images, the regression suite of the course
# conventions. Each row of scripts/course-refs.tsv names a course file, the
# image wavepath writes for it, the reference it must match and the
# tolerance, with the reason where it is wide.
#
#   scripts/check-course-refs.sh [options]
#
#   --darts DIR      a checkout of cs87-dartmouth/darts-2022 (its scenes/ with
#                    the *-ref.png and *-ref.exr images); its rows are skipped
#                    without it
#   --cs184 DIR      a checkout of the CS184 skeleton (its dae/ folder) and
#   --peer BIN       the course's own renderer built from it
#                    (the 3-2 skeleton with the staff library, see
#                    docs/scene-format.md); the "peer" rows render each .dae
#                    with both and compare; skipped without them
#   --wavepath BIN   (default: build/wavepath beside this script)
#   --spp N          render darts scenes and .dae files at N samples per pixel
#                    instead of their own (quicker, noisier: the tolerances
#                    are for the files' own counts, 256 for the .dae rows)
#   --only TEXT      only the rows whose file contains TEXT
#   --out DIR        keep the renders in DIR (default: a scratch folder)
#   --compare-only   compare the renders an earlier run left in --out DIR
#                    again, rendering nothing
#   --list FILE      also write the lines to FILE
#
# The course files are copied into the output folder and rendered or run
# (`wavepath test`) there, so nothing is written into the checkouts. One line
# per image: WITHIN or BEYOND its tolerance with the measures, or SKIP with
# the reason (an asset the course distributes apart from the skeleton, say),
# then a summary. Exit status: 0 when no image is beyond its tolerance, 1
# otherwise, 2 on bad usage.
set -uo pipefail
here=$(cd "$(dirname "$0")" && pwd)
wavepath=$here/../build/wavepath
table=$here/course-refs.tsv
darts="" cs184="" peer="" spp="" only="" out="" list="" compareOnly=0
usage() { sed -n '2,35p' "$0" | sed 's/^# \{0,1\}//' >&2; exit 2; }
while [ $# -gt 0 ]; do
  case $1 in
    --darts) darts=$(cd "$2" && pwd) || exit 2; shift 2 ;;
    --cs184) cs184=$(cd "$2" && pwd) || exit 2; shift 2 ;;
    --peer) peer=$(readlink -f "$2"); shift 2 ;;
    --wavepath) wavepath=$(readlink -f "$2"); shift 2 ;;
    --spp) spp=$2; shift 2 ;;
    --only) only=$2; shift 2 ;;
    --out) out=$2; shift 2 ;;
    --list) list=$2; shift 2 ;;
    --compare-only) compareOnly=1; shift ;;
    -h|--help) usage ;;
    *) echo "check-course-refs.sh: unknown argument $1" >&2; usage ;;
  esac
done
[ -x "$wavepath" ] || { echo "check-course-refs.sh: no wavepath binary at $wavepath (--wavepath BIN)" >&2; exit 2; }
[ -n "$darts$cs184" ] || { echo "check-course-refs.sh: give --darts DIR and/or --cs184 DIR --peer BIN" >&2; exit 2; }
[ $compareOnly -eq 0 ] || [ -n "$out" ] || { echo "check-course-refs.sh: --compare-only needs --out DIR" >&2; exit 2; }
if [ -n "$cs184" ] && [ $compareOnly -eq 0 ] && [ ! -x "$peer" ]; then echo "check-course-refs.sh: --cs184 needs --peer BIN (the course's renderer)" >&2; exit 2; fi
if [ -z "$out" ]; then
  out=$(mktemp -d)
  trap 'rm -rf "$out"' EXIT
fi
mkdir -p "$out"
out=$(cd "$out" && pwd)
[ -z "$list" ] || : >"$list"
say() { echo "$1"; [ -z "$list" ] || echo "$1" >>"$list"; }

# run_file COURSE FILE: renders or runs the course file once, in a copy of
# its folder; sets `work` (that folder) and `problem` (why images may be
# missing: the loader's message).
declare -A ran
run_file() {
  local course=$1 file=$2 root
  [ "$course" = darts ] && root=$darts || root=$cs184
  work=$out/$course/$(dirname "$file")
  local key="$course/$file"
  if [ -n "${ran[$key]+x}" ]; then problem=${ran[$key]}; return; fi
  if [ $compareOnly -eq 1 ]; then
    ran[$key]=$(grep -h -m 1 -E 'error|failed' "$work/$(basename "${file%.*}").err" 2>/dev/null | sed 's/^wavepath: error: //')
    problem=${ran[$key]}
    return
  fi
  mkdir -p "$work"
  cp -r "$root/$(dirname "$file")/." "$work/"
  local name base rc
  [ -n "$root" ] && [ -d "$root/$(dirname "$file")" ] || { problem="no folder $(dirname "$file") in the $course checkout"; ran[$key]=$problem; return; }
  name=$(basename "$file")
  base=${name%.*}
  (
    cd "$work" || exit 3
    if [ "$course" = cs184 ]; then
      flags=(-t 2 -s "${spp:-256}" -l 4 -m 5 -r 480 360)
      "$peer" "${flags[@]}" -a "${spp:-256}" 0.05 -f "$base-peer.png" "$name" >"$base-peer.log" 2>&1 || echo "the course's renderer failed" >>"$base.err"
      "$wavepath" render "${flags[@]}" --cs184 3-2 -f "$base.png" "$name"
    elif grep -Eq '"type"[[:space:]]*:[[:space:]]*"tests"' "$name"; then
      "$wavepath" test "$name"
    else
      "$wavepath" render "$name" -o "$base.png" ${spp:+--spp "$spp"}
    fi
  ) >"$work/$base.log" 2>>"$work/$base.err"
  rc=$?
  problem=$(grep -h -m 1 -E 'error|failed' "$work/$base.err" 2>/dev/null | sed 's/^wavepath: error: //')
  [ $rc -eq 0 ] || [ -n "$problem" ] || problem="exit $rc"
  ran[$key]=$problem
}

# The table, read whole and checked before anything runs (a row naming
# another course, or a short row, stops the run: it would copy from nowhere).
mapfile -t rows < <(grep -v -e '^#' -e '^[[:space:]]*$' "$table")
for r in "${!rows[@]}"; do
  IFS=$'\t' read -r course file image reference meanTol blockTol region why <<<"${rows[$r]}"
  if [[ $course != darts && $course != cs184 ]] || [ -z "$why" ] || ! [[ $meanTol =~ ^[0-9.]+$ && $blockTol =~ ^[0-9.]+$ ]] ||
     [[ $file == /* || $file == *..* ]]; then
    echo "check-course-refs.sh: $table: row $((r + 1)) is not COURSE FILE IMAGE REFERENCE MEAN BLOCK REGION WHY (tab-separated)" >&2
    exit 2
  fi
done

within=0 beyond=0 skipped=0
say "course references: $(date -u +%Y-%m-%d), $("$wavepath" devices 2>/dev/null | sed -n 2p | sed 's/^ *//')${spp:+, $spp spp}"
for row in "${rows[@]}"; do
  IFS=$'\t' read -r course file image reference meanTol blockTol region why <<<"$row"
  [ -z "$only" ] || [[ $file == *"$only"* ]] || continue
  if { [ "$course" = darts ] && [ -z "$darts" ]; } || { [ "$course" = cs184 ] && [ -z "$cs184" ]; }; then continue; fi
  run_file "$course" "$file"
  [ "$reference" = peer ] && reference="${image%.png}-peer.png"
  if [ ! -f "$work/$image" ] || [ ! -f "$work/$reference" ]; then
    skipped=$((skipped + 1))
    say "SKIP   $course $file: $image: not written${problem:+ ($problem)}"
    continue
  fi
  extra=()
  read -r -a r <<<"$region"
  if [ ${#r[@]} -eq 2 ]; then extra=(--exclude-rows "${r[0]}" "${r[1]}"); elif [ ${#r[@]} -eq 4 ]; then extra=(--mask "${r[@]}"); fi
  [ "$course" = cs184 ] && extra+=(--curve cs184)
  verdict=$("$wavepath" compare --reference "$work/$reference" "$work/$image" --tolerance "$meanTol" "$blockTol" "${extra[@]}" 2>&1)
  rc=$?
  if [ $rc -eq 0 ]; then within=$((within + 1)); tag=WITHIN; elif [ $rc -eq 1 ]; then beyond=$((beyond + 1)); tag=BEYOND; else
    skipped=$((skipped + 1)); tag=SKIP; fi
  say "$(printf '%-6s' $tag) $course $file: $image: ${verdict#*: }"
done
say "summary: $within within their tolerances, $beyond beyond, $skipped skipped"
[ $beyond -eq 0 ]
