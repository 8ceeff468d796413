#!/usr/bin/env bash
# `wavepath bench`: variants are timed only after they agree with the CPU
# reference; results come out as a table, JSON and CSV.
# Usage: bench_cli.sh WAVEPATH TEST_DATA_DIR
set -u
wavepath=$1
data=$2
source "$(dirname "$0")/testlib.sh"
common=(--scenes "$data/furnace.json" --variants gpu,gpu-oneray --spp 1 --repeats 2 --check-spp 16)

"$wavepath" bench "${common[@]}" --out "$work/r.json" --csv "$work/r.csv" >"$work/out" 2>&1
check "bench exits 0 when every variant passes its check" $?
check "the table shows both variants timed" $(grep -cE '^  gpu(-oneray)? +pass' "$work/out" | grep -qx 2; echo $?)
check "JSON has both variants with timings" $([ "$(grep -c '"check_passed": true' "$work/r.json")" -eq 2 ] &&
  grep -q '"samples_per_second"' "$work/r.json" && grep -q '"extend"' "$work/r.json"; echo $?)
check "JSON counts the rays traced and their rates" $(grep -q '"closest_hit_rays": [1-9]' "$work/r.json" &&
  grep -q '"shadow_rays": [0-9]' "$work/r.json" && grep -q '"closest_hit_mrays_per_second": {' "$work/r.json"; echo $?)
check "CSV has a header and a row per variant" $([ "$(wc -l <"$work/r.csv")" -eq 3 ]; echo $?)

# A planted bias makes every variant disagree: none may be timed.
"$wavepath" bench "${common[@]}" --plant-bias 1.1 --out "$work/p.json" >"$work/out" 2>"$work/err"
rc=$?
check "a variant that disagrees is not timed: exit 1" $([ $rc -eq 1 ]; echo $?)
check "it says so" $(grep -q "not timed" "$work/err"; echo $?)
check "JSON records the failed checks and no timings" $([ "$(grep -c '"check_passed": false' "$work/p.json")" -eq 2 ] &&
  ! grep -q '"samples_per_second"' "$work/p.json"; echo $?)

# Ray casting: the GPU's hits are checked against the CPU traversal, then timed;
# Embree (installed by scripts/install-deps.sh) traces the same rays.
"$wavepath" bench --raycast --scenes "$data/furnace.json" --variants gpu --resolution 32 32 --repeats 1 \
  --out "$work/rc.json" --csv "$work/rc.csv" >"$work/out" 2>&1
check "ray casting bench exits 0" $?
check "ray casting writes a CSV row for each JSON row, with the same rates" $(python3 -c '
import csv, json, sys
rows = json.load(open(sys.argv[1]))["raycast"]
table = list(csv.DictReader(open(sys.argv[2])))
same = len(table) == len(rows) and all(
    t["rays"] == r["rays"] and t["variant"] == r["variant"] and float(t["mrays_per_second"]) == r["mrays_per_second"]
    and float(t["cpu_walk_steps_per_ray"]) == r["cpu_walk_steps_per_ray"] for t, r in zip(table, rows))
sys.exit(0 if same else 1)' "$work/rc.json" "$work/rc.csv"; echo $?)
check "ray casting checks and times the camera, bounce and shadow rays" $(python3 -c '
import json, sys
rows = json.load(open(sys.argv[1]))["raycast"]
sets = sorted(r["rays"] for r in rows if r["check_passed"] and r["mrays_per_second"] > 0)
sys.exit(0 if sets == ["bounce", "primary", "shadow"] else 1)' "$work/rc.json"; echo $?)
check "ray casting counts the CPU walk's steps per ray of every set" $(python3 -c '
import json, sys
rows = json.load(open(sys.argv[1]))["raycast"]
sys.exit(0 if len(rows) == 3 and all(r["cpu_walk_steps_per_ray"] >= 1 for r in rows) else 1)' "$work/rc.json"; echo $?)
# Embree is optional at build time: without it the benchmarks say so and time
# wavepath alone.
embree=1
grep -q "Embree baseline: not built in" "$work/out" && embree=0
if [ $embree = 1 ]; then
  check "ray casting reports the ratio to Embree" $(grep -q '"ratio_to_embree"' "$work/rc.json"; echo $?)
  check "ray casting reports each repeat's ratio to Embree, which holds the headline ratio" $(python3 -c '
import json, sys
rows = json.load(open(sys.argv[1]))["raycast"]
def ok(r):
    p = r["ratio_to_embree_per_repeat"]
    # With one repeat, the ratio of the medians is the one paired ratio.
    return 0 < p["min"] <= p["median"] <= p["max"] and abs(r["ratio_to_embree"] - p["median"]) <= 1e-9 * p["median"]
sys.exit(0 if rows and all(ok(r) for r in rows) else 1)' "$work/rc.json"; echo $?)
  "$wavepath" bench --raycast --scenes "$data/quad-light.json" --variants gpu --resolution 16 16 --repeats 1 >"$work/out" 2>&1
  check "a scene with spheres is timed without the Embree baseline" $([ $? -eq 0 ] && grep -q "triangle scenes only" "$work/out"; echo $?)
  # Embree places the instances by its own two levels and finds the hits the
  # CPU walk finds. Every material two-sided: Embree culls no back faces.
  python3 -c '
import json, os, shutil, sys
src, out = sys.argv[1], sys.argv[2]
doc = json.load(open(src))
for m in doc["materials"]:
    m["doubleSided"] = True
for b in doc["buffers"]:
    if not b["uri"].startswith("data:"):
        shutil.copy(os.path.join(os.path.dirname(src), b["uri"]), os.path.dirname(out))
json.dump(doc, open(out, "w"))' "$data/gltf/instances.gltf" "$work/instances.gltf"
  "$wavepath" bench --raycast --scenes "$work/instances.gltf" --variants gpu --resolution 32 32 --repeats 1 --out "$work/inst.json" \
    >"$work/out" 2>&1
  check "Embree is the baseline of instanced scenes too, with the same hits" $([ $? -eq 0 ] && python3 -c '
import json, sys
rows = json.load(open(sys.argv[1]))["raycast"]
sys.exit(0 if len(rows) == 3 and all("embree_mrays_per_second" in r and r["embree_mismatches"] == 0 for r in rows) else 1)' "$work/inst.json"; echo $?)
else
  check "built without Embree, ray casting reports no ratio" $(! grep -q '"ratio_to_embree"' "$work/rc.json"; echo $?)
fi

# The SIMT model: no device timing, deterministic figures, a measured file's
# order beside its own; a file that is not bench --raycast's is refused.
"$wavepath" bench --simt --scenes "$data/furnace.json" --variants gpu,gpu-bvh2 --resolution 16 16 --reorder morton \
  --measured "$work/rc.json" --out "$work/simt.json" --csv "$work/simt.csv" >"$work/out" 2>&1
check "the SIMT model exits 0" $?
check "it models every variant, ray set (sorted ones too) and warp width, with the measured rate beside" $(python3 -c '
import json, sys
rows = json.load(open(sys.argv[1]))["simt"]
keys = {(r["variant"], r["rays_set"], r["warp_width"]) for r in rows}
want = {(v, s, w) for v in ("gpu", "gpu-bvh2") for s in ("primary", "bounce", "shadow", "bounce/morton", "shadow/morton") for w in (32, 64)}
ok = keys == want and all(0 < r["simd_efficiency"] <= 1 and r["predicted_mrays_per_second"] > 0 for r in rows)
ok = ok and all("measured_mrays_per_second" in r for r in rows if r["variant"] == "gpu" and "/" not in r["rays_set"])
sys.exit(0 if ok else 1)' "$work/simt.json"; echo $?)
"$wavepath" bench --simt --scenes "$data/furnace.json" --variants gpu,gpu-bvh2 --resolution 16 16 --reorder morton \
  --measured "$work/rc.json" --csv "$work/simt2.csv" >/dev/null 2>&1
check "the same model twice gives the same figures" $(cmp -s "$work/simt.csv" "$work/simt2.csv"; echo $?)
"$wavepath" bench --simt --scenes "$data/furnace.json" --resolution 8 8 --warps 8,12 >"$work/out" 2>"$work/err"
check "a warp width the model does not know: exit 2 naming the option" $([ $? -eq 2 ] && grep -q -- "--warps" "$work/err"; echo $?)
echo '{"render": []}' >"$work/notraycast.json"
"$wavepath" bench --simt --scenes "$data/furnace.json" --resolution 8 8 --measured "$work/notraycast.json" >"$work/out" 2>"$work/err"
check "a measured file without ray casting: exit 2 naming it" $([ $? -eq 2 ] && grep -q "notraycast.json: no \"raycast\" array" "$work/err"; echo $?)

# A scene whose path starts with a quote: CSV fields are quoted where needed,
# so a CSV reader gets the path back whole (unquoted, it read a quoted field).
mkdir -p "$work/\"odd\" dir" && cp "$data/furnace.json" "$data/furnace-box.obj" "$data/furnace-box.mtl" "$work/\"odd\" dir/"
(cd "$work" && "$wavepath" bench --raycast --scenes "\"odd\" dir/furnace.json" --variants gpu --resolution 16 16 --repeats 1 \
  --csv odd.csv >out 2>&1)
check "a scene's path with quotes reads back whole from the CSV" $(python3 -c '
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
sys.exit(0 if len(rows) == 3 and all(r["scene"] == sys.argv[2] for r in rows) else 1)' "$work/odd.csv" '"odd" dir/furnace.json'; echo $?)

# BVH builds: the tree the renderer builds, timed against Embree's build of
# the same triangles; a scene with spheres is timed without Embree.
"$wavepath" bench --build --scenes "$data/furnace.json,$data/quad-light.json" --repeats 2 \
  --out "$work/b.json" --csv "$work/b.csv" >"$work/out" 2>&1
check "build bench exits 0" $?
check "build bench reports the rate and the SAH cost of every scene" $([ "$(grep -c '"mprims_per_second"' "$work/b.json")" -ge 2 ] &&
  [ "$(grep -c '"sah_cost"' "$work/b.json")" -ge 2 ]; echo $?)
check "build bench times the greedy collapse of every scene" $(
  [ "$(grep -c '"greedy_mprims_per_second"' "$work/b.json")" -eq 2 ] && grep -q "wavepath, 8-wide, greedy collapse" "$work/out"; echo $?)
check "build bench times the clustered SAH build of every (binned-SAH) scene" $(
  [ "$(grep -c '"clustered_mprims_per_second"' "$work/b.json")" -eq 2 ] && grep -q "wavepath clustered SAH, 8-wide" "$work/out"; echo $?)
check "build bench names the renderer's split method (binned SAH at these sizes)" $(
  [ "$(grep -c '"renderer_split": "binned SAH"' "$work/b.json")" -eq 2 ] && grep -q "wavepath, 8-wide (the renderer's)" "$work/out"; echo $?)
check "build bench splits the renderer's build into the binary tree and the collapse" $(python3 -c '
import json, sys
rows = json.load(open(sys.argv[1]))["build"]
def ok(r):
    tree, collapse, wide = r["wide_binary_tree_seconds"], r["wide_collapse_seconds"], r["wide_seconds"]
    return 0 < collapse["min"] and collapse["median"] < wide["median"] and 0 < tree["min"] and tree["median"] < wide["median"]
sys.exit(0 if len(rows) == 2 and all(ok(r) for r in rows) else 1)' "$work/b.json"; echo $?)
if [ $embree = 1 ]; then
  check "build bench reports the ratio to Embree" $(grep -q '"ratio_to_embree"' "$work/b.json" && grep -q "ratio wavepath / Embree" "$work/out"; echo $?)
  check "build bench times the scene with spheres without Embree" $(grep -q "triangle scenes only" "$work/out" &&
    [ "$(grep -c '"ratio_to_embree"' "$work/b.json")" -eq 1 ]; echo $?)
else
  check "built without Embree, the build bench reports no ratio" $(! grep -q '"ratio_to_embree"' "$work/b.json"; echo $?)
fi
check "build bench CSV has a header and a row per scene" $([ "$(wc -l <"$work/b.csv")" -eq 3 ]; echo $?)
check "build bench CSV rows fill the header's columns, with the JSON's figures" $(python3 -c '
import csv, json, sys
rows = json.load(open(sys.argv[1]))["build"]
with open(sys.argv[2]) as f:
    header = next(csv.reader(f))
    f.seek(0)
    table = list(csv.DictReader(f))
same = len(table) == len(rows) and all(
    None not in t and float(t["greedy_sah_cost"]) == r["greedy_sah_cost"] and float(t["wide_sah_cost"]) == r["wide_sah_cost"]
    and float(t["mprims_per_second"]) == r["mprims_per_second"]
    and float(t["wide_collapse_seconds"]) == r["wide_collapse_seconds"]["median"] for t, r in zip(table, rows))
sys.exit(0 if same and all(len(t) == len(header) for t in table) else 1)' "$work/b.json" "$work/b.csv"; echo $?)
"$wavepath" bench --build --raycast >"$work/out" 2>"$work/err"
check "--build with --raycast: exit 2" $([ $? -eq 2 ]; echo $?)

# The charts of scripts/plot_bench.py, from the three kinds of results.
plot="$(dirname "$0")/../scripts/plot_bench.py"
"$plot" "$work/r.json" --out "$work/plots" >/dev/null && "$plot" "$work/rc.json" --out "$work/plots" >/dev/null &&
  "$plot" "$work/b.json" --out "$work/plots" >/dev/null
check "plot_bench.py draws the render, ray-casting and build charts" $([ -s "$work/plots/bench_samples_per_second.png" ] &&
  [ -s "$work/plots/bench_stage_times.png" ] && [ -s "$work/plots/bench_raycast.png" ] && [ -s "$work/plots/bench_build.png" ]; echo $?)
"$plot" "$work/out" >/dev/null 2>"$work/err"
check "plot_bench.py on a file that is not JSON: exit 2" $([ $? -eq 2 ] && grep -q "plot_bench: error" "$work/err"; echo $?)

# Sampler convergence: RMSE rows for both samplers, and their chart.
"$wavepath" convergence "$data/features/materials.json" --integrator normals -r 16 12 --max-spp 8 --reference-spp 64 \
  --csv "$work/conv.csv" >"$work/out" 2>&1
check "convergence writes a row per sampler and sample count" $([ $? -eq 0 ] && [ "$(wc -l <"$work/conv.csv")" -eq 9 ] &&
  grep -q "^cmj,8," "$work/conv.csv"; echo $?)
"$(dirname "$0")/../scripts/plot_convergence.py" "$work/conv.csv" --out "$work/conv.png"
check "plot_convergence.py draws the chart" $([ -s "$work/conv.png" ]; echo $?)

# The instancing benchmark's forest (scripts/gen-forest.py), small: its two
# forms (EXT_mesh_gpu_instancing, nested plain nodes) are one forest of
# instances, and ray casting through it passes the CPU check.
gen="$(dirname "$0")/../scripts/gen-forest.py"
python3 "$gen" "$work/ext.gltf" --instances 60 --triangles 3000 >/dev/null &&
  python3 "$gen" "$work/nodes.gltf" --instances 60 --triangles 3000 --nodes >/dev/null
check "gen-forest.py writes both forms" $?
for form in ext nodes; do
  "$wavepath" info "$work/$form.gltf" >"$work/$form.info" 2>&1
  check "the forest ($form) holds 60 instances of 3 meshes" $(grep -q "^instances *60 instances of 3 meshes: 3000 unique" "$work/$form.info"; echo $?)
  "$wavepath" render "$work/$form.gltf" -r 48 27 --spp 16 -q -o "$work/$form.png"
  check "the forest ($form) renders" $?
done
"$wavepath" compare --images "$work/ext.exr" "$work/nodes.exr" >"$work/out" 2>&1
check "both forms render the same forest" $?
"$wavepath" bench --raycast --scenes "$work/ext.gltf" --variants gpu,gpu-bvh2 --resolution 32 18 --repeats 1 >"$work/out" 2>&1
check "ray casting through the instances passes the check" $([ $? -eq 0 ] && grep -q "60 instances placing" "$work/out" &&
  ! grep -q "not timed" "$work/out"; echo $?)

"$wavepath" bench --variants gpu-wg7 >"$work/out" 2>"$work/err"
check "unknown variant: exit 2, one line" $([ $? -eq 2 ] && [ "$(wc -l <"$work/err")" -eq 1 ] && grep -q "gpu-wg7" "$work/err"; echo $?)
"$wavepath" bench --scenes "$data/bad-unknown-key.json" >"$work/out" 2>"$work/err"
check "bad scene: exit 2 before any work" $([ $? -eq 2 ] && grep -q "/camera/fov" "$work/err"; echo $?)
"$wavepath" bench --build --scenes "$data/bad-unknown-key.json" --out "$work/bad-build.json" >"$work/out" 2>"$work/err"
check "build bench, bad scene: exit 2, the place named, no results file" $([ $? -eq 2 ] && grep -q "/camera/fov" "$work/err" &&
  [ ! -e "$work/bad-build.json" ]; echo $?)

finish
