# bench-rounds.sh — sourced by the benchmarks that time scene variants in
# interleaved rounds (bench-layers.sh, bench-media.sh):
#   bench_rounds BUILD ROUNDS DIR "VARIANTS" SAMPLES [render options]
# prints the machine and the default device, renders DIR/VARIANT.json once
# each to compile its kernels, then ROUNDS
# rounds of every variant in turn, and prints each variant's median render
# time, its samples per second (SAMPLES per render) and its ratio to the
# first variant's.
bench_rounds() {
  local build=$1 rounds=$2 dir=$3 variants=$4 samples=$5
  shift 5
  echo "machine: $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs)"
  "$build/wavepath" devices | sed -n 2p
  seconds() { sed -n 's/.*max bounces, \([0-9.]*\) s on .*/\1/p'; }
  median() { sort -g | awk '{v[NR] = $1} END {print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2}'; }
  local v
  for v in $variants; do "$build/wavepath" render "$dir/$v.json" --spp 4 -o "$dir/warm.png" "$@" >/dev/null 2>&1; done
  for _ in $(seq "$rounds"); do
    for v in $variants; do "$build/wavepath" render "$dir/$v.json" -o "$dir/r.png" "$@" 2>&1 | seconds >>"$dir/$v.t"; done
  done
  local first base m
  first=$(set -- $variants; echo "$1")
  base=$(median <"$dir/$first.t")
  for v in $variants; do
    m=$(median <"$dir/$v.t")
    printf '%-11s median %6.2f s  %6.3f Msamples/s  %5.2fx %s  (runs: %s)\n' "$v" "$m" \
      "$(awk -v s="$samples" -v m="$m" 'BEGIN { print s / m / 1e6 }')" "$(awk -v p="$base" -v m="$m" 'BEGIN { print m / p }')" "$first" \
      "$(tr '\n' ' ' <"$dir/$v.t")"
  done
}
