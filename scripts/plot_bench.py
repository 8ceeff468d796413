#!/usr/bin/python3
"""Charts of `wavepath bench` results (JSON written with --out).

Usage: scripts/plot_bench.py RESULTS.json [--out DIR]

Render benchmarks give two charts: samples per second per variant and scene
(median, with the min-max range as error bars), and the per-stage GPU time of
each variant. Ray-casting benchmarks give Mrays/s of wavepath and Embree side
by side for the primary, bounce and shadow rays of each scene; build benchmarks, the
BVH build rate of wavepath (binary tree, all of it, the greedy collapse and
the clustered SAH build) and Embree. Uses Debian's
python3-numpy and python3-matplotlib (hence /usr/bin/python3).
"""
import argparse
import json
import os
import sys

import matplotlib

matplotlib.use("Agg")  # files only, no display
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def short(path):
    return os.path.splitext(os.path.basename(path))[0]


def save_chart(fig, ax, out_dir, name, ylabel, title):
    """Labels, legend and layout of a chart; writes it as out_dir/name and returns the path."""
    ax.set_ylabel(ylabel)
    ax.set_title(title)
    ax.legend()
    fig.tight_layout()
    path = os.path.join(out_dir, name)
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return path


def plot_render(results, out_dir):
    scenes = results["scenes"]
    variants = sorted({v["variant"] for s in scenes for v in s["variants"]})
    width = 0.8 / max(len(variants), 1)
    x = np.arange(len(scenes))
    fig, ax = plt.subplots(figsize=(8, 4.5))
    for i, name in enumerate(variants):
        med, lo, hi = [], [], []
        for s in scenes:
            v = next((v for v in s["variants"] if v["variant"] == name and v["check_passed"]), None)
            r = v["samples_per_second"] if v else {"median": 0, "min": 0, "max": 0}
            med.append(r["median"] / 1e6)
            lo.append((r["median"] - r["min"]) / 1e6)
            hi.append((r["max"] - r["median"]) / 1e6)
        ax.bar(x + (i - (len(variants) - 1) / 2) * width, med, width, yerr=[lo, hi], capsize=3, label=name)
    ax.set_xticks(x, [short(s["scene"]) for s in scenes])
    paths = [save_chart(fig, ax, out_dir, "bench_samples_per_second.png", "Msamples/s (median, min-max)",
                        "wavepath bench on " + results["device"]["name"])]

    # Per-stage time of each (scene, variant), stacked.
    stages = ["generate", "prepare", "extend", "sort", "shade", "connect", "accumulate", "megakernel"]
    labels, data = [], []
    for s in scenes:
        for v in s["variants"]:
            if v["check_passed"]:
                labels.append(short(s["scene"]) + "\n" + v["variant"])
                data.append([v["stage_seconds"].get(st, {"median": 0.0})["median"] for st in stages])
    if data:
        data = np.array(data)
        fig, ax = plt.subplots(figsize=(max(6, 1.2 * len(labels)), 4.5))
        bottom = np.zeros(len(labels))
        for k, st in enumerate(stages):
            ax.bar(labels, data[:, k], bottom=bottom, label=st)
            bottom += data[:, k]
        paths.append(save_chart(fig, ax, out_dir, "bench_stage_times.png", "GPU seconds per render (median)",
                                "Time per kernel stage"))
    return paths


def plot_raycast(results, out_dir):
    rows = [r for r in results["raycast"] if r.get("check_passed")]
    order = {"primary": 0, "bounce": 1, "shadow": 2}
    keys = sorted({(r["scene"], r["rays"]) for r in rows}, key=lambda k: (k[0], order.get(k[1], 3)))
    variants = sorted({r["variant"] for r in rows})
    series = variants + (["Embree"] if any("embree_mrays_per_second" in r for r in rows) else [])
    width = 0.8 / max(len(series), 1)
    x = np.arange(len(keys))
    fig, ax = plt.subplots(figsize=(max(7, 1.3 * len(keys)), 4.5))
    for i, name in enumerate(series):
        vals = []
        for scene, rays in keys:
            match = [r for r in rows if r["scene"] == scene and r["rays"] == rays]
            if name == "Embree":
                vals.append(match[0].get("embree_mrays_per_second", 0) if match else 0)
            else:
                vals.append(next((r["mrays_per_second"] for r in match if r["variant"] == name), 0))
        ax.bar(x + (i - (len(series) - 1) / 2) * width, vals, width, label=name)
    ax.set_xticks(x, [short(s) + "\n" + r for s, r in keys])
    return [save_chart(fig, ax, out_dir, "bench_raycast.png", "Mrays/s (shadow rays: any hit; median)",
                       "Ray casting on " + results["device"]["name"])]


def plot_build(results, out_dir):
    rows = results["build"]
    # The scene's split method (binned SAH unless it names another) and the
    # clustered build; the JSON's renderer_split says which the renderer uses.
    series = [("wavepath, 8-wide", lambda r: r["mprims_per_second"]),
              ("wavepath, binary layout", lambda r: r["primitives"] / r["binary_seconds"]["median"] / 1e6)]
    if any("greedy_mprims_per_second" in r for r in rows):
        series.append(("wavepath, 8-wide, greedy collapse", lambda r: r.get("greedy_mprims_per_second", 0)))
    if any("clustered_mprims_per_second" in r for r in rows):
        series.append(("wavepath clustered SAH, 8-wide", lambda r: r.get("clustered_mprims_per_second", 0)))
    if any("embree_mprims_per_second" in r for r in rows):
        series.append(("Embree", lambda r: r.get("embree_mprims_per_second", 0)))
    width = 0.8 / len(series)
    x = np.arange(len(rows))
    fig, ax = plt.subplots(figsize=(max(7, 1.3 * len(rows)), 4.5))
    top = 0.0
    for i, (name, rate) in enumerate(series):
        values = [rate(r) for r in rows]
        top = max([top] + values)
        ax.bar(x + (i - (len(series) - 1) / 2) * width, values, width, label=name)
    ax.set_ylim(0, 1.35 * top)  # room for the legend above the bars
    ax.set_xticks(x, [short(r["scene"]) + "\n" + f"{r['primitives']:,}" for r in rows])
    return [save_chart(fig, ax, out_dir, "bench_build.png", "M primitives/s (median)", f"BVH build on {results['threads']} threads")]


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("results", help="JSON written by wavepath bench --out")
    parser.add_argument("--out", default=".", help="directory for the PNG charts (default: .)")
    args = parser.parse_args()
    try:
        with open(args.results) as f:
            results = json.load(f)
    except (OSError, json.JSONDecodeError) as e:
        print(f"plot_bench: error: {args.results}: {e}", file=sys.stderr)
        return 2
    os.makedirs(args.out, exist_ok=True)
    if "raycast" in results:
        paths = plot_raycast(results, args.out)
    elif "build" in results:
        paths = plot_build(results, args.out)
    elif "scenes" in results:
        paths = plot_render(results, args.out)
    else:
        print(f"plot_bench: error: {args.results}: not a wavepath bench result", file=sys.stderr)
        return 2
    for p in paths:
        print(p)
    return 0


if __name__ == "__main__":
    sys.exit(main())
