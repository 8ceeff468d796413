#!/usr/bin/env python3
"""Writes a glTF 2.0 forest for the instancing benchmark of docs/benchmarks.md:
N instances (default 1,000,000) of three tree meshes (a conifer, a broadleaf
tree, a bush) that together hold T unique triangles (default 1,000,000), on
a grey ground plane, with a camera at the forest's edge and a sun
(KHR_lights_punctual). The unique geometry is small and the instanced
geometry is N times larger, which is what the benchmark measures: how a
renderer copes with instancing rather than with raw triangle counts.

  python3 scripts/gen-forest.py OUT.gltf [--instances N] [--triangles T]
                                [--seed S] [--nodes] [--grid]

Writes OUT.gltf and its buffer OUT.bin beside it. By default each tree mesh
has one node with EXT_mesh_gpu_instancing (TRANSLATION, ROTATION, SCALE per
instance); --nodes writes every instance as a plain node instead, in rows of
at most 1000 under translated row nodes (for renderers without the
extension; meant for small N). --grid writes the plainer forest a new user
would: one broadleaf mesh of T triangles on every point of the grid,
unmoved, unturned and unscaled. The placement depends only on --seed, so
both forms of one seed hold the same forest. Standard library only.
"""
import argparse
import array
import json
import math
import os
import random
import sys
import time

SPACING = 4.0  # distance between neighbouring trees
JITTER = 0.35  # each tree moves up to this fraction of SPACING off its grid point
SCALES = (0.7, 1.3)  # uniform scale range of an instance
ROW_CHILDREN = 1000  # --nodes: at most this many trees under one row node

FLOAT, UINT = 5126, 5125
ARRAY_BUFFER, ELEMENT_ARRAY_BUFFER = 34962, 34963

# wavepath reads a directional light's intensity in lux and divides by
# 683 lm/W (docs/scene-format.md, KHR_lights_punctual), so 3 * 683 lux is a
# sun of 3 W/m^2 there, as bright as the suns of scripts/make-gltf-*.py.
SUN_LUX = 3 * 683


class MeshBuilder:
    """Positions (flat x, y, z) and triangle indices of one mesh."""

    def __init__(self):
        self.pos = []
        self.idx = []

    def vertex(self, x, y, z):
        self.pos += (x, y, z)
        return len(self.pos) // 3 - 1

    def lathe(self, profile, segments):
        """A surface of revolution about +Y. `profile` lists (radius, y) in
        the order that puts the outside on the left as one walks it top to
        bottom (down the side, then inwards under a base); radius 0 is a
        pole, one vertex. Returns the number of triangles added."""
        rings = []
        for r, y in profile:
            if r == 0.0:
                rings.append([self.vertex(0.0, y, 0.0)] * segments)
            else:
                rings.append([self.vertex(r * math.cos(2 * math.pi * s / segments), y,
                                          r * math.sin(2 * math.pi * s / segments)) for s in range(segments)])
        before = len(self.idx)
        for k in range(len(profile) - 1):
            up, lo = rings[k], rings[k + 1]
            up_pole, lo_pole = profile[k][0] == 0.0, profile[k + 1][0] == 0.0
            for s in range(segments):
                t = (s + 1) % segments
                if not up_pole:
                    self.idx += (up[s], up[t], lo[s])
                if not lo_pole:
                    self.idx += (up[t], lo[t], lo[s])
        return (len(self.idx) - before) // 3

    def geodesic_sphere(self, frequency):
        """A unit icosahedron with each face cut into frequency^2 triangles,
        pushed onto the sphere; edge and corner vertices shared exactly."""
        t = (1 + math.sqrt(5)) / 2
        corners = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t),
                   (0, -1, -t), (0, 1, -t), (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
        faces = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4),
                 (11, 10, 2), (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8),
                 (3, 8, 9), (4, 9, 5), (2, 4, 11), (6, 2, 10), (8, 6, 7), (9, 8, 1)]
        n = frequency
        shared = {}
        first = len(self.idx)

        def point(a, b, c, wa, wb, wc):
            # Keyed by the exact integer weights of the icosahedron's corners.
            key = tuple(sorted((v, w) for v, w in ((a, wa), (b, wb), (c, wc)) if w))
            index = shared.get(key)
            if index is None:
                x = sum(corners[v][0] * w for v, w in key)
                y = sum(corners[v][1] * w for v, w in key)
                z = sum(corners[v][2] * w for v, w in key)
                length = math.sqrt(x * x + y * y + z * z)
                index = shared[key] = self.vertex(x / length, y / length, z / length)
            return index

        for a, b, c in faces:
            rows = [[point(a, b, c, n - i, i - j, j) for j in range(i + 1)] for i in range(n + 1)]
            for i in range(n):
                for j in range(i + 1):
                    self.idx += (rows[i][j], rows[i + 1][j], rows[i + 1][j + 1])
                    if j < i:
                        self.idx += (rows[i][j], rows[i + 1][j + 1], rows[i][j + 1])
        return (len(self.idx) - first) // 3

    def transform_since(self, first_vertex, fn):
        """Moves the vertices from `first_vertex` on by fn(x, y, z)."""
        p = self.pos
        for v in range(first_vertex * 3, len(p), 3):
            p[v], p[v + 1], p[v + 2] = fn(p[v], p[v + 1], p[v + 2])

    def vertex_count(self):
        return len(self.pos) // 3


def lumpy(cx, cy, cz, rx, ry, rz, amount, phase):
    """Places a unit sphere's points on an ellipsoid with radii rx, ry, rz
    about (cx, cy, cz), its radius varied smoothly by up to `amount` so that
    a crown is not a perfect ball."""
    def fn(x, y, z):
        f = 1.0 + amount * math.sin(3.1 * x + phase) * math.sin(2.7 * y + 0.4 + phase) * math.sin(3.3 * z + 2.1)
        return cx + rx * f * x, cy + ry * f * y, cz + rz * f * z
    return fn


# Each tree's triangle count as a function of its resolution, and its build.
# A tree's origin is the base of its trunk, +Y up; heights about 9 (the trees) and 5 (the bush).

def conifer_triangles(segments, rings, layers):
    # trunk: 2 * segments; each cone layer: a side of `rings` rings,
    # segments * (2 * rings - 1), and its underside, segments.
    return 2 * segments * (1 + rings * layers)


def conifer(segments, rings, layers):
    m = MeshBuilder()
    m.lathe([(0.25, 2.0), (0.25, 0.0)], segments)  # the trunk's top hides inside the lowest cone
    base, top = 1.5, 7.0  # the lowest cone's base, the highest one's base
    for layer in range(layers):
        f = layer / (layers - 1)
        y0 = base + (top - base) * f  # this cone's base
        radius = 2.3 * (1 - 0.55 * f)
        height = 3.2 * (1 - 0.3 * f)
        side = [(0.0, y0 + height)]
        for k in range(1, rings + 1):
            t = k / rings
            side.append((radius * t, y0 + height * (1 - t) - 0.25 * t * t))  # a slight droop at the rim
        m.lathe(side, segments)
        rim_y = side[-1][1]
        m.lathe([(radius, rim_y), (0.0, rim_y)], segments)  # the underside, its own vertices for a crease
    return m


def broadleaf_triangles(frequency, segments, stacks):
    return 20 * frequency * frequency + 2 * segments * stacks


def broadleaf(frequency, segments, stacks):
    m = MeshBuilder()
    trunk_top = 4.2  # inside the crown
    m.lathe([(0.22 + 0.08 * k / stacks, trunk_top * (1 - k / stacks)) for k in range(stacks + 1)], segments)  # tapering
    first = m.vertex_count()
    m.geodesic_sphere(frequency)
    m.transform_since(first, lumpy(0.0, 6.4, 0.0, 2.8, 2.6, 2.8, 0.07, 0.3))
    return m


def bush_triangles(segments, stacks):
    # a UV sphere: a fan at each pole and quads between.
    return 2 * segments * (stacks - 1)


def bush(segments, stacks):
    m = MeshBuilder()
    profile = [(0.0, 1.0)]
    for k in range(1, stacks):
        phi = math.pi * k / stacks
        profile.append((math.sin(phi), math.cos(phi)))
    profile.append((0.0, -1.0))
    m.lathe(profile, segments)
    m.transform_since(0, lumpy(0.0, 2.4, 0.0, 3.0, 2.6, 3.0, 0.08, 1.7))  # sunk 0.2 into the ground
    return m


def pick(share, candidates):
    """The resolution whose triangle count is nearest `share`; among those
    within 0.1 % of it (or as near as any), the best-shaped (least penalty)."""
    best = min(abs(tris - share) for tris, _, _ in candidates)
    slack = max(best, int(share * 0.001))
    return min((penalty, params) for tris, penalty, params in candidates if abs(tris - share) <= slack)[1]


def conifer_params(share):
    out = []
    for layers in (3, 4, 5):
        for segments in range(6, 4097):
            rings = round((share / (2 * segments) - 1) / layers)
            if rings < 1:
                break
            # Square-ish quads: about 3.6 segments per ring on these cones.
            penalty = abs(math.log(segments / (3.6 * rings))) + 0.1 * abs(layers - 4)
            out.append((conifer_triangles(segments, rings, layers), penalty, (segments, rings, layers)))
    return pick(share, out)


def broadleaf_params(share):
    out = []
    top = max(1, int(math.sqrt(share / 20)))
    for frequency in range(max(1, top - 2), top + 1):
        rest = share - 20 * frequency * frequency
        for segments in range(6, 129):
            stacks = max(1, round(rest / (2 * segments)))
            penalty = abs(math.log(segments / 24)) + 0.2 * (top - frequency) + 0.1 * abs(math.log(stacks / segments * 4))
            out.append((broadleaf_triangles(frequency, segments, stacks), penalty, (frequency, segments, stacks)))
    return pick(share, out)


def bush_params(share):
    out = []
    for segments in range(6, 4097):
        stacks = round(share / (2 * segments) + 1)
        if stacks < 3:
            break
        out.append((bush_triangles(segments, stacks), abs(math.log(segments / (2 * stacks))), (segments, stacks)))
    return pick(share, out)


def smooth_normals(pos, idx, name):
    """Unit vertex normals: the area-weighted sum of the faces around each
    vertex. Refuses degenerate triangles."""
    acc = [0.0] * len(pos)
    p = pos
    smallest = math.inf
    for t in range(0, len(idx), 3):
        a, b, c = idx[t] * 3, idx[t + 1] * 3, idx[t + 2] * 3
        ax, ay, az = p[a], p[a + 1], p[a + 2]
        ux, uy, uz = p[b] - ax, p[b + 1] - ay, p[b + 2] - az
        vx, vy, vz = p[c] - ax, p[c + 1] - ay, p[c + 2] - az
        nx, ny, nz = uy * vz - uz * vy, uz * vx - ux * vz, ux * vy - uy * vx
        area2 = nx * nx + ny * ny + nz * nz
        if area2 < smallest:
            smallest = area2
        for v in (a, b, c):
            acc[v] += nx
            acc[v + 1] += ny
            acc[v + 2] += nz
    if smallest <= 1e-20:
        sys.exit(f"gen-forest.py: {name} has a degenerate triangle; choose more triangles")
    for v in range(0, len(acc), 3):
        x, y, z = acc[v], acc[v + 1], acc[v + 2]
        inv = 1.0 / math.sqrt(x * x + y * y + z * z)
        acc[v], acc[v + 1], acc[v + 2] = x * inv, y * inv, z * inv
    return acc


class Buffer:
    """One binary buffer of bufferViews and their accessors."""

    def __init__(self):
        self.data = bytearray()
        self.views = []
        self.accessors = []

    def view(self, blob, target=None):
        self.data += b"\0" * (-len(self.data) % 4)
        view = {"buffer": 0, "byteOffset": len(self.data), "byteLength": len(blob)}
        if target is not None:
            view["target"] = target
        self.data += blob
        self.views.append(view)
        return len(self.views) - 1

    def accessor(self, values, type_, target=None):
        """An accessor of `values` (an array.array of 'f' or 'I'), tightly
        packed in a view of its own, with min and max of each component."""
        width = {"SCALAR": 1, "VEC3": 3, "VEC4": 4}[type_]
        if sys.byteorder == "big":
            values = array.array(values.typecode, values)
            values.byteswap()
            native = array.array(values.typecode, values)
            native.byteswap()
        else:
            native = values
        acc = {"bufferView": self.view(values.tobytes(), target), "componentType": FLOAT if values.typecode == "f" else UINT,
               "count": len(values) // width, "type": type_,
               # values read back from the array are the float32s stored
               "min": [min(native[c::width]) for c in range(width)],
               "max": [max(native[c::width]) for c in range(width)]}
        self.accessors.append(acc)
        return len(self.accessors) - 1


def quat_from_to(a, b):
    """The unit quaternion (x, y, z, w) that turns unit vector a to unit vector b."""
    cx, cy, cz = a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]
    w = 1.0 + a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
    n = math.sqrt(cx * cx + cy * cy + cz * cz + w * w)
    return [cx / n + 0.0, cy / n + 0.0, cz / n + 0.0, w / n]  # + 0.0: no -0.0


def normalize(v):
    n = math.sqrt(sum(c * c for c in v))
    return [c / n for c in v]


def place(count, seed, kinds=3, regular=False):
    """The trees: per tree mesh (of `kinds`), flat lists of translations
    (x, y, z), rotations (x, y, z, w) and scales (s, s, s); each tree's mesh
    in grid order; and the grid's side. `regular`: on the grid's points,
    unturned, of scale 1."""
    rng = random.Random(seed)
    rand = rng.random
    side = max(1, math.ceil(math.sqrt(count)))
    half = (side - 1) / 2
    trans, rots, scales = [[] for _ in range(kinds)], [[] for _ in range(kinds)], [[] for _ in range(kinds)]
    choice = bytearray(count)
    s0, ds = SCALES[0], SCALES[1] - SCALES[0]
    jitter = 0.0 if regular else JITTER
    for n in range(count):
        x = (n % side - half + jitter * (2 * rand() - 1)) * SPACING
        z = (n // side - half + jitter * (2 * rand() - 1)) * SPACING
        angle = 0.0 if regular else math.pi * rand()  # half the rotation angle about +Y, in [0, pi)
        s = 1.0 if regular else s0 + ds * rand()
        k = choice[n] = min(kinds - 1, int(kinds * rand()))
        trans[k] += (x, 0.0, z)
        rots[k] += (0.0, math.sin(angle), 0.0, math.cos(angle))
        scales[k] += (s, s, s)
    return trans, rots, scales, choice, side


def main():
    ap = argparse.ArgumentParser(description="Writes a glTF forest for the instancing benchmark (docs/benchmarks.md).")
    ap.add_argument("out", metavar="OUT.gltf", help="the glTF file; its buffer goes to OUT.bin beside it")
    ap.add_argument("--instances", type=int, default=1_000_000, metavar="N", help="trees (default 1,000,000)")
    ap.add_argument("--triangles", type=int, default=1_000_000, metavar="T",
                    help="unique triangles of the three tree meshes together (default 1,000,000)")
    ap.add_argument("--seed", type=int, default=1, metavar="S", help="seed of the placement (default 1)")
    ap.add_argument("--nodes", action="store_true",
                    help="one plain node per tree instead of EXT_mesh_gpu_instancing (for small N)")
    ap.add_argument("--grid", action="store_true",
                    help="one broadleaf mesh of T triangles on every grid point, unmoved, unturned, unscaled")
    args = ap.parse_args()
    if args.instances < 1:
        ap.error("--instances must be at least 1")
    if args.triangles < 600:
        ap.error("--triangles must be at least 600 (200 a tree)")
    start = time.time()

    out = args.out
    stem = out[:-5] if out.endswith(".gltf") else out
    bin_path = stem + ".bin"

    if args.grid:
        trees = [("broadleaf", "broadleaves", broadleaf(*broadleaf_params(args.triangles)), [0.12, 0.34, 0.07, 1.0])]
    else:
        # The triangle budget, a third to each tree.
        shares = [args.triangles // 3, args.triangles // 3, args.triangles - 2 * (args.triangles // 3)]
        trees = [("conifer", "conifers", conifer(*conifer_params(shares[0])), [0.05, 0.20, 0.06, 1.0]),
                 ("broadleaf", "broadleaves", broadleaf(*broadleaf_params(shares[1])), [0.12, 0.34, 0.07, 1.0]),
                 ("bush", "bushes", bush(*bush_params(shares[2])), [0.20, 0.38, 0.10, 1.0])]

    buf = Buffer()
    meshes, materials, tree_tris = [], [], []
    for k, (name, _, m, colour) in enumerate(trees):
        normals = smooth_normals(m.pos, m.idx, name)
        prim = {"attributes": {"POSITION": buf.accessor(array.array("f", m.pos), "VEC3", ARRAY_BUFFER),
                               "NORMAL": buf.accessor(array.array("f", normals), "VEC3", ARRAY_BUFFER)},
                "indices": buf.accessor(array.array("I", m.idx), "SCALAR", ELEMENT_ARRAY_BUFFER),
                "material": k, "mode": 4}
        meshes.append({"name": name, "primitives": [prim]})
        materials.append({"name": name, "pbrMetallicRoughness": {"baseColorFactor": colour, "metallicFactor": 0.0,
                                                                 "roughnessFactor": 0.8}})
        tree_tris.append(len(m.idx) // 3)
    unique = sum(tree_tris)
    if abs(unique - args.triangles) > 0.01 * args.triangles:
        print(f"gen-forest.py: warning: {unique} unique triangles, more than 1 % off {args.triangles}", file=sys.stderr)

    trans, rots, scales, choice, side = place(args.instances, args.seed, len(trees), args.grid)
    extent = side * SPACING  # the forest covers [-extent/2, extent/2] in x and z

    # The ground: a square a little larger than the forest, facing up.
    h = extent / 2 + 10.0
    ground = {"attributes": {"POSITION": buf.accessor(array.array("f", [-h, 0, -h, h, 0, -h, h, 0, h, -h, 0, h]), "VEC3", ARRAY_BUFFER),
                             "NORMAL": buf.accessor(array.array("f", [0, 1, 0] * 4), "VEC3", ARRAY_BUFFER)},
              "indices": buf.accessor(array.array("I", [0, 2, 1, 0, 3, 2]), "SCALAR", ELEMENT_ARRAY_BUFFER),
              "material": len(trees), "mode": 4}
    meshes.append({"name": "ground", "primitives": [ground]})
    materials.append({"name": "ground", "pbrMetallicRoughness": {"baseColorFactor": [0.35, 0.35, 0.35, 1.0],
                                                                 "metallicFactor": 0.0, "roughnessFactor": 0.9}})

    nodes = [{"name": "ground", "mesh": len(trees)}]
    top = [0]
    extensions_used = ["KHR_lights_punctual"]
    counts = [len(t) // 3 for t in trans]
    if not args.nodes:
        extensions_used.append("EXT_mesh_gpu_instancing")
        for k in range(len(trees)):
            if counts[k] == 0:
                continue  # an accessor may not be empty
            # Instance data is not vertex data: its views have no target.
            attributes = {"TRANSLATION": buf.accessor(array.array("f", trans[k]), "VEC3"),
                          "ROTATION": buf.accessor(array.array("f", rots[k]), "VEC4"),
                          "SCALE": buf.accessor(array.array("f", scales[k]), "VEC3")}
            top.append(len(nodes))
            nodes.append({"name": trees[k][1], "mesh": k, "extensions": {"EXT_mesh_gpu_instancing": {"attributes": attributes}}})
    else:
        # Rows of the grid (at most ROW_CHILDREN trees each) under row nodes
        # translated to the row's z; the trees' translations are relative.
        rows = {}
        cursor = [0, 0, 0]
        for n, k in enumerate(choice):
            c = cursor[k]
            cursor[k] += 1
            x, _, z = trans[k][3 * c:3 * c + 3]
            row_key = (n // side, (n % side) // ROW_CHILDREN)
            row = rows.get(row_key)
            if row is None:
                row_z = (n // side - (side - 1) / 2) * SPACING
                row = rows[row_key] = {"name": f"row {row_key[0]}" + (f".{row_key[1]}" if side > ROW_CHILDREN else ""),
                                       "translation": [0.0, 0.0, row_z], "children": []}
                top.append(len(nodes))
                nodes.append(row)
            s = scales[k][3 * c]
            row["children"].append(len(nodes))
            nodes.append({"mesh": k, "translation": [round(x, 6), 0.0, round(z - row["translation"][2], 6)],
                          "rotation": rots[k][4 * c:4 * c + 4], "scale": [s, s, s]})

    # The camera stands at the forest's +Z edge, 12 up, looking along -Z
    # and 8 degrees down into it (a camera looks down its local -Z).
    pitch = math.radians(8.0)
    top.append(len(nodes))
    nodes.append({"name": "camera", "camera": 0, "translation": [0.0, 12.0, extent / 2 + 2.0],
                  "rotation": quat_from_to([0, 0, -1], [0.0, -math.sin(pitch), -math.cos(pitch)])})
    # The sun shines down its node's -Z: from the upper left, behind the camera.
    top.append(len(nodes))
    nodes.append({"name": "sun", "rotation": quat_from_to([0, 0, -1], normalize([0.55, -1.0, -0.45])),
                  "extensions": {"KHR_lights_punctual": {"light": 0}}})

    doc = {
        "asset": {"version": "2.0", "generator": "wavepath scripts/gen-forest.py"},
        "extensionsUsed": extensions_used,
        "extensions": {"KHR_lights_punctual": {"lights": [
            {"name": "sun", "type": "directional", "color": [1.0, 0.96, 0.88], "intensity": SUN_LUX}]}},
        "scene": 0,
        "scenes": [{"name": "forest", "nodes": top}],
        "nodes": nodes,
        "cameras": [{"name": "edge", "type": "perspective",
                     "perspective": {"yfov": 0.7, "aspectRatio": 16 / 9, "znear": 0.1}}],
        "meshes": meshes,
        "materials": materials,
        "accessors": buf.accessors,
        "bufferViews": buf.views,
        "buffers": [{"byteLength": len(buf.data), "uri": os.path.basename(bin_path)}],
    }
    with open(bin_path, "wb") as f:
        f.write(buf.data)
    with open(out, "w") as f:
        if len(nodes) > 10000:
            json.dump(doc, f, separators=(",", ":"))
        else:
            json.dump(doc, f, indent=1)
        f.write("\n")

    instanced = sum(c * t for c, t in zip(counts, tree_tris))
    kinds = ", ".join(f"{c} {tree[1]}" for c, tree in zip(counts, trees))
    print(f"{out}: {args.instances} instances ({kinds}), "
          f"{unique} unique triangles ({' + '.join(map(str, tree_tris))}, ground 2 more), "
          f"{instanced} instanced triangles; {os.path.getsize(out)} bytes + {bin_path} {os.path.getsize(bin_path)} bytes; "
          f"{time.time() - start:.1f} s")


if __name__ == "__main__":
    main()
