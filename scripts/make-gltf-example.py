#!/usr/bin/env python3
"""Writes scenes/spot.glb, the glTF example of the README, with the standard
library only: the spot mesh (scenes/assets/spot.obj, MIT licence) with
smooth vertex normals, and three textures drawn here: a base colour of
patches, a normal map of fine grooves and a metallic-roughness map that
makes the patches polished metal and the rest rough paint; a spot light and
a sun (KHR_lights_punctual). It has no camera: wavepath frames it.

  python3 scripts/make-gltf-example.py
  ./build/wavepath render scenes/spot.glb --env scenes/assets/sky.hdr -o spot.png
"""
import importlib.util
import math
import os

# The PNG and binary-glTF writers of the test models' script.
_spec = importlib.util.spec_from_file_location("assets", os.path.join(os.path.dirname(os.path.abspath(__file__)), "make-gltf-test-assets.py"))
assets = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(assets)

SIZE = 256  # texture width and height


def read_obj(path):
    positions, uvs, corners = [], [], []
    with open(path) as f:
        for line in f:
            part = line.split()
            if not part:
                continue
            if part[0] == "v":
                positions.append([float(c) for c in part[1:4]])
            elif part[0] == "vt":
                uvs.append([float(c) for c in part[1:3]])
            elif part[0] == "f":
                face = [tuple(int(i) - 1 for i in c.split("/")[:2]) for c in part[1:]]
                for k in range(1, len(face) - 1):
                    corners += [face[0], face[k], face[k + 1]]
    return positions, uvs, corners


def sub(a, b):
    return [a[i] - b[i] for i in range(3)]


def cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def normalize(v):
    length = math.sqrt(sum(c * c for c in v)) or 1.0
    return [c / length for c in v]


def mesh(positions, uvs, corners):
    """glTF vertices (one per position and UV pair), smooth normals, indices."""
    normals = [[0.0, 0.0, 0.0] for _ in positions]
    for t in range(0, len(corners), 3):
        p = [positions[corners[t + k][0]] for k in range(3)]
        n = cross(sub(p[1], p[0]), sub(p[2], p[0]))  # area-weighted
        for k in range(3):
            normals[corners[t + k][0]] = [normals[corners[t + k][0]][i] + n[i] for i in range(3)]
    index, pos, nrm, uv, idx = {}, [], [], [], []
    for c in corners:
        if c not in index:
            index[c] = len(pos)
            pos.append(positions[c[0]])
            nrm.append(normalize(normals[c[0]]))
            u, v = uvs[c[1]]
            uv.append([u, 1.0 - v])  # OBJ's v runs up the image, glTF's down
        idx.append(index[c])
    return pos, nrm, uv, idx


def patch(x, y):
    """1 inside the patches (a few soft-edged blobs, wrapping), 0 outside."""
    u, v = x / SIZE, y / SIZE
    value = 0.0
    for cx, cy, r in ((0.2, 0.3, 0.12), (0.55, 0.2, 0.09), (0.8, 0.65, 0.14), (0.35, 0.75, 0.1), (0.65, 0.45, 0.07)):
        dx = min(abs(u - cx), 1 - abs(u - cx))
        dy = min(abs(v - cy), 1 - abs(v - cy))
        value = max(value, min(1.0, max(0.0, (r - math.hypot(dx, dy)) / 0.015)))
    return value


def base_color(x, y):
    p = patch(x, y)
    paint = (235, 228, 210)
    gold = (255, 196, 90)
    return tuple(int(paint[i] + (gold[i] - paint[i]) * p) for i in range(3))


def grooves(x, y):
    """Tangent-space normals of fine grooves along v, outside the patches."""
    slope = 0.35 * math.sin(2 * math.pi * x / 8) * (1 - patch(x, y))
    n = normalize([-slope, 0.0, 1.0])
    return tuple(int(round(255 * (c * 0.5 + 0.5))) for c in n)


def metal_rough(x, y):
    p = patch(x, y)
    return (0, int(255 * (0.6 - 0.45 * p)), int(255 * p))  # G roughness, B metallic


def look_rotation(direction):
    """The quaternion (x, y, z, w) that turns -Z to `direction` (y up)."""
    f = normalize(direction)
    r = normalize(cross(f, [0, 1, 0]))
    u = cross(r, f)
    m = [r, u, [-c for c in f]]  # columns: x, y, z axes
    trace = m[0][0] + m[1][1] + m[2][2]
    w = math.sqrt(max(0.0, 1 + trace)) / 2
    return [(m[1][2] - m[2][1]) / (4 * w), (m[2][0] - m[0][2]) / (4 * w), (m[0][1] - m[1][0]) / (4 * w), w]


def main():
    pos, nrm, uv, idx = mesh(*read_obj(os.path.join("scenes", "assets", "spot.obj")))
    buf = assets.Buffer()
    FLOAT, USHORT = assets.FLOAT, assets.USHORT
    attributes = {"POSITION": buf.accessor("f", FLOAT, "VEC3", pos), "NORMAL": buf.accessor("f", FLOAT, "VEC3", nrm),
                  "TEXCOORD_0": buf.accessor("f", FLOAT, "VEC2", uv)}
    indices = buf.accessor("H", USHORT, "SCALAR", idx)
    images = [buf.view(assets.png(SIZE, SIZE, f)) for f in (base_color, grooves, metal_rough)]
    # The ground: a dark rough disc (a 32-gon) under the mesh.
    ground_y = min(p[1] for p in pos)
    ring = [[1.0 * math.cos(2 * math.pi * k / 32), ground_y, 1.0 * math.sin(2 * math.pi * k / 32)] for k in range(32)]
    ground_pos = [[0, ground_y, 0]] + ring
    ground_idx = [i for k in range(32) for i in (0, 1 + (k + 1) % 32, 1 + k)]
    ground = {"attributes": {"POSITION": buf.accessor("f", FLOAT, "VEC3", ground_pos)},
              "indices": buf.accessor("H", USHORT, "SCALAR", ground_idx), "material": 1}
    doc = {
        "asset": {"version": "2.0", "generator": "wavepath scripts/make-gltf-example.py"},
        "scene": 0, "scenes": [{"nodes": [0, 1, 2, 3]}],
        "nodes": [{"name": "spot", "mesh": 0, "rotation": look_rotation([0.7, 0, 1])},
                  {"name": "ground", "mesh": 1},
                  {"name": "key light", "translation": [1.6, 2.2, 1.8], "rotation": look_rotation([-1.6, -2.6, -1.8]),
                   "extensions": {"KHR_lights_punctual": {"light": 0}}},
                  {"name": "sun", "rotation": look_rotation([0.5, -1.0, -0.6]), "extensions": {"KHR_lights_punctual": {"light": 1}}}],
        "meshes": [{"name": "spot", "primitives": [{"attributes": attributes, "indices": indices, "material": 0}]},
                   {"name": "ground", "primitives": [ground]}],
        "materials": [
            {"name": "gilded paint", "normalTexture": {"index": 1},
             "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}, "metallicRoughnessTexture": {"index": 2}}},
            {"name": "slate", "pbrMetallicRoughness": {"baseColorFactor": [0.12, 0.12, 0.13, 1], "metallicFactor": 0, "roughnessFactor": 0.7}}],
        "textures": [{"source": i, "sampler": 0} for i in range(3)],
        "samplers": [{"wrapS": 10497, "wrapT": 10497}],
        "images": [{"bufferView": v, "mimeType": "image/png"} for v in images],
        "extensionsUsed": ["KHR_lights_punctual"],
        "extensions": {"KHR_lights_punctual": {"lights": [
            {"name": "key", "type": "spot", "color": [1, 0.9, 0.8], "intensity": 30 * 683, "spot": {"innerConeAngle": 0.3, "outerConeAngle": 0.6}},
            {"name": "sun", "type": "directional", "color": [1, 0.97, 0.9], "intensity": 2 * 683}]}},
        "accessors": buf.accessors, "bufferViews": buf.views, "buffers": [{"byteLength": len(buf.data)}],
    }
    with open(os.path.join("scenes", "spot.glb"), "wb") as f:
        f.write(assets.glb(doc, buf.data))


if __name__ == "__main__":
    main()
