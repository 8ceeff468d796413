#!/usr/bin/env python3
"""Writes a glTF 2.0 scene laid out as Khronos' DispersionTest sample model
(glTF-Sample-Assets, Models/DispersionTest/glTF/DispersionTest.gltf): a grid
of 25 glass prisms, rows of index of refraction 1.0, 1.33, 1.5, 1.76 and
2.42 by columns of KHR_materials_dispersion 0, 0.5, 1, 2 and 5, 2.5 cm
apart across and 1.5 cm up, each a transmissive volume (transmission 1,
thickness 0.018478, base colour 0.8469, roughness 0) as its materials are,
in front of a backdrop printed with a checker and thin lines. The sample's
own meshes and textures are not copied: these prisms are plain triangular
prisms, and the backdrop glows (emissive) so that the lines seen through
the prisms fan into their colours. The colour-noise benchmark of
docs/benchmarks.md renders it (scripts/bench-colour-noise.sh).

  python3 scripts/gen-dispersion-grid.py OUT.gltf

Writes OUT.gltf with its buffer and backdrop image embedded (data URIs).
Standard library only.
"""
import base64
import json
import struct
import sys
import zlib

IORS = (1.0, 1.33, 1.5, 1.76, 2.42)
DISPERSIONS = (0.0, 0.5, 1.0, 2.0, 5.0)
THICKNESS = 0.018478000536561012
BASE = 0.8468725681304932
FLOAT, UINT = 5126, 5125


def prism():
    """A triangular prism 2 cm wide (x), its cross-section in y-z a triangle
    1.2 cm tall with its apex edge towards the camera (+z): positions and
    outward normals, flat-shaded, and triangle indices."""
    w, h, d = 0.01, 0.006, THICKNESS / 2
    tri = [(-h, -d), (h, -d), (0.0, d)]  # (y, z), counter-clockwise seen from +x
    pos, nrm, idx = [], [], []

    def face(corners, normal):
        base = len(pos) // 3
        for c in corners:
            pos.extend(c)
            nrm.extend(normal)
        for i in range(1, len(corners) - 1):
            idx.extend((base, base + i, base + i + 1))

    face([(w, y, z) for y, z in tri], (1.0, 0.0, 0.0))
    face([(-w, y, z) for y, z in reversed(tri)], (-1.0, 0.0, 0.0))
    for i in range(3):
        (y0, z0), (y1, z1) = tri[i], tri[(i + 1) % 3]
        ny, nz = z1 - z0, -(y1 - y0)
        length = (ny * ny + nz * nz) ** 0.5
        face([(-w, y0, z0), (w, y0, z0), (w, y1, z1), (-w, y1, z1)], (0.0, ny / length, nz / length))
    return pos, nrm, idx


def backdrop_png(size=256):
    """A checker of 8 by 8 squares, light and dark, crossed by thin dark
    lines every half square: RGB, 8 bits."""
    rows = []
    for y in range(size):
        row = bytearray([0])
        for x in range(size):
            square = (x * 8 // size + y * 8 // size) % 2
            value = 230 if square == 0 else 90
            if x % (size // 16) < 2 or y % (size // 16) < 2:
                value = 15
            row += bytes((value, value, value))
        rows.append(bytes(row))

    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)

    header = struct.pack(">IIBBBBB", size, size, 8, 2, 0, 0, 0)
    return b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header) + chunk(b"IDAT", zlib.compress(b"".join(rows), 9)) + chunk(b"IEND", b"")


def main():
    if len(sys.argv) != 2:
        sys.exit("usage: gen-dispersion-grid.py OUT.gltf")
    buf = bytearray()
    views, accessors = [], []

    def add(values, fmt, kind, count, component, target, minmax=None):
        while len(buf) % 4:
            buf.append(0)
        offset = len(buf)
        buf.extend(struct.pack("<%d%s" % (len(values), fmt), *values))
        views.append({"buffer": 0, "byteOffset": offset, "byteLength": len(buf) - offset, "target": target})
        accessor = {"bufferView": len(views) - 1, "componentType": component, "count": count, "type": kind}
        if minmax:
            accessor["min"], accessor["max"] = minmax
        accessors.append(accessor)
        return len(accessors) - 1

    pos, nrm, idx = prism()
    lo = [min(pos[i::3]) for i in range(3)]
    hi = [max(pos[i::3]) for i in range(3)]
    prismPos = add(pos, "f", "VEC3", len(pos) // 3, FLOAT, 34962, (lo, hi))
    prismNrm = add(nrm, "f", "VEC3", len(nrm) // 3, FLOAT, 34962)
    prismIdx = add(idx, "I", "SCALAR", len(idx), UINT, 34963)
    # The backdrop: a quad 16 cm by 11 cm, 3 cm behind the prisms, facing +z.
    bw, bh, bz = 0.08, 0.055, -0.03
    quad = [-bw, -bh, bz, bw, -bh, bz, bw, bh, bz, -bw, bh, bz]
    quadPos = add(quad, "f", "VEC3", 4, FLOAT, 34962, ([-bw, -bh, bz], [bw, bh, bz]))
    quadNrm = add([0.0, 0.0, 1.0] * 4, "f", "VEC3", 4, FLOAT, 34962)
    quadUv = add([0.0, 1.0, 1.0, 1.0, 1.0, 0.0, 0.0, 0.0], "f", "VEC2", 4, FLOAT, 34962)
    quadIdx = add([0, 1, 2, 0, 2, 3], "I", "SCALAR", 6, UINT, 34963)

    materials = [{
        "name": "Backdrop",
        "pbrMetallicRoughness": {"baseColorFactor": [0, 0, 0, 1], "metallicFactor": 0, "roughnessFactor": 1},
        "emissiveTexture": {"index": 0},
        "emissiveFactor": [1, 1, 1],
    }]
    meshes = [{"name": "Backdrop", "primitives": [{"attributes": {"POSITION": quadPos, "NORMAL": quadNrm, "TEXCOORD_0": quadUv},
                                                   "indices": quadIdx, "material": 0}]}]
    nodes = [{"name": "Backdrop", "mesh": 0}]
    for row, ior in enumerate(IORS):
        for col, dispersion in enumerate(DISPERSIONS):
            extensions = {
                "KHR_materials_transmission": {"transmissionFactor": 1},
                "KHR_materials_volume": {"thicknessFactor": THICKNESS},
                "KHR_materials_dispersion": {"dispersion": dispersion},
            }
            if ior != 1.5:
                extensions["KHR_materials_ior"] = {"ior": ior}
            materials.append({
                "name": "Mat_IOR_%g_D%g" % (ior, dispersion),
                "pbrMetallicRoughness": {"baseColorFactor": [BASE, BASE, BASE, 1], "metallicFactor": 0, "roughnessFactor": 0},
                "extensions": extensions,
            })
            meshes.append({"name": "Prism_IOR%g_D%g" % (ior, dispersion),
                           "primitives": [{"attributes": {"POSITION": prismPos, "NORMAL": prismNrm}, "indices": prismIdx,
                                           "material": len(materials) - 1}]})
            nodes.append({"name": meshes[-1]["name"], "mesh": len(meshes) - 1,
                          "translation": [-0.05 + 0.025 * col, -0.03 + 0.015 * row, 0.0]})
    nodes.append({"name": "Camera", "camera": 0, "translation": [0.0, 0.0, 0.2]})
    png = backdrop_png()
    gltf = {
        "asset": {"version": "2.0", "generator": "wavepath scripts/gen-dispersion-grid.py"},
        "extensionsUsed": ["KHR_materials_transmission", "KHR_materials_volume", "KHR_materials_ior", "KHR_materials_dispersion"],
        "scene": 0,
        "scenes": [{"nodes": list(range(len(nodes)))}],
        "nodes": nodes,
        "cameras": [{"type": "perspective", "perspective": {"yfov": 0.5, "aspectRatio": 1.0, "znear": 0.01}}],
        "meshes": meshes,
        "materials": materials,
        "textures": [{"source": 0}],
        "images": [{"uri": "data:image/png;base64," + base64.b64encode(png).decode("ascii")}],
        "accessors": accessors,
        "bufferViews": views,
        "buffers": [{"byteLength": len(buf), "uri": "data:application/octet-stream;base64," + base64.b64encode(bytes(buf)).decode("ascii")}],
    }
    with open(sys.argv[1], "w") as f:
        json.dump(gltf, f, indent=1)


if __name__ == "__main__":
    main()
