#!/usr/bin/python3
"""Writes darts scenes for the scaling benchmark: square grids of the Stanford
dragon (scenes/assets/dragon.obj, 100,000 triangles each) on a floor under a
quad light, from one dragon (100 thousand triangles) to 100 (10 million).

Usage: scripts/make-scale-scenes.py OUT_DIR [COUNT ...]   (default counts: 1 3 10 30 100)
Writes OUT_DIR/dragons-COUNT.json; each refers to the mesh by a path relative
to OUT_DIR. Standard library only.
"""
import json
import math
import os
import sys

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DRAGON = os.path.join(REPO, "scenes", "assets", "dragon.obj")
SPACING = 14.0  # the dragon is about 11 units long and 8 tall


def scene(count, mesh_path):
    side = math.ceil(math.sqrt(count))
    extent = side * SPACING
    surfaces = []
    for i in range(count):
        x = (i % side - (side - 1) / 2) * SPACING
        z = (i // side - (side - 1) / 2) * SPACING
        surfaces.append({
            "type": "mesh",
            "filename": mesh_path,
            "material": "jade",
            "transform": [{"rotate": [37 * i % 360, 0, 1, 0]}, {"translate": [x, 0, z]}],
        })
    surfaces.append({"type": "quad", "size": extent + 40, "material": "floor",
                     "transform": {"rotate": [-90, 1, 0, 0]}})
    surfaces.append({"type": "quad", "size": extent / 2 + 4, "material": "sun",
                     "transform": [{"rotate": [90, 1, 0, 0]}, {"translate": [0, extent + 20, extent / 4]}]})
    # A camera above and in front, framing the whole grid.
    distance = 0.9 * extent + 25.0
    return {
        "camera": {
            "transform": {"from": [-0.4 * distance, 0.7 * distance, distance], "at": [0, 2, 0], "up": [0, 1, 0]},
            "vfov": 45,
            "resolution": [512, 512],
        },
        "sampler": {"type": "independent", "samples": 16},
        "background": [0.6, 0.7, 0.9],
        "integrator": {"type": "path tracer mis", "max bounces": 8},
        "materials": [
            {"type": "lambertian", "name": "jade", "albedo": [0.3, 0.6, 0.4]},
            {"type": "lambertian", "name": "floor", "albedo": 0.6},
            {"type": "diffuse_light", "name": "sun", "emit": [8, 7.2, 6]},
        ],
        "surfaces": surfaces,
    }


def main():
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    out = sys.argv[1]
    counts = [int(c) for c in sys.argv[2:]] or [1, 3, 10, 30, 100]
    os.makedirs(out, exist_ok=True)
    mesh = os.path.relpath(DRAGON, out)
    for count in counts:
        path = os.path.join(out, "dragons-%d.json" % count)
        with open(path, "w") as f:
            json.dump(scene(count, mesh), f, indent=1)
        print(path)


main()
