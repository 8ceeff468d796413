#!/usr/bin/python3
"""Plots `wavepath convergence --csv` output: RMSE against samples per pixel,
log-log, one line per sampler, with the N^-1/2 slope of independent sampling
for reference. Needs Debian's python3-matplotlib.

usage: scripts/plot_convergence.py conv.csv --out convergence.png [--title TEXT]
"""
import argparse
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("csv")
    ap.add_argument("--out", required=True)
    ap.add_argument("--title", default="Convergence of the camera samplers")
    a = ap.parse_args()
    series = {}
    with open(a.csv, newline="") as f:
        for row in csv.DictReader(f):
            series.setdefault(row["sampler"], []).append((int(row["spp"]), float(row["rmse"])))
    if not series:
        sys.exit(f"{a.csv}: no rows")
    fig, ax = plt.subplots(figsize=(6, 4.2))
    for name, pts in series.items():
        pts.sort()
        ax.loglog([p[0] for p in pts], [p[1] for p in pts], "o-", label=name)
    first = sorted(series.get("independent", next(iter(series.values()))))
    n0, e0 = first[0]
    xs = [p[0] for p in first]
    ax.loglog(xs, [e0 * (x / n0) ** -0.5 for x in xs], "k:", label="N^-1/2")
    ax.set_xlabel("samples per pixel")
    ax.set_ylabel("RMSE against the reference")
    ax.set_title(a.title)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend()
    fig.tight_layout()
    fig.savefig(a.out, dpi=110)


if __name__ == "__main__":
    main()
