#!/usr/bin/env python3
"""Writes wavepath's glTF 2.0 test assets into tests/data/gltf/ with the
standard library only, so that every byte of them is generated here (no
third-party asset, no licence to track):

  box-room.gltf   buffers embedded as a data: URI; a node tree (TRS and a
                  matrix), metal-rough materials, an emissive panel, a point
                  light (KHR_lights_punctual) and a camera.
  box-room.json   the same objects as a darts scene: world-space triangles,
                  the same materials, light and camera, so that the two
                  formats can be rendered and compared.
  textured.glb    binary glTF: a PNG base colour and a metallic-roughness
                  texture in buffer views, unsigned byte indices, normalized
                  unsigned short UVs, a sparse accessor, two cameras (one
                  orthographic) and no light (the white sky).
  external/       scene.gltf with its buffer (scene.bin) and image
                  (checker.png) as separate files.
  surface.glb     what glTF puts on a surface: normal maps (with TANGENT
                  and with tangents left to be derived), vertex colours
                  (COLOR_0), a texture on TEXCOORD_1 with clamped and
                  mirrored wrapping, alphaMode MASK (an RGBA PNG) and
                  BLEND, a one-sided wall seen from behind, thin-walled
                  transmission; a point light and a sun.
  mirror-bumps.glb  a white mirror sphere (metallic 1, roughness 0) under
                  a strongly tilted normal map, and no light: the white sky.
                  A white furnace: every pixel's radiance is 1 unless
                  mapped normals lose light.
  layers.glb      KHR_materials_clearcoat, _sheen, _specular, _iridescence,
                  _anisotropy and _volume, each with its textures (the
                  channels each reads), under a sun.
  translucent.glb KHR_materials_diffuse_transmission as the Khronos
                  DiffuseTransmissionTest lays it out: double-sided panes
                  lit from behind by a sun shining at the camera, in rows
                  of the factor (0 to 1), the colour factor, the factor's
                  texture (alpha) and the colour's texture (sRGB), and a
                  dark panel behind them that only light through them shows.
  lamp-room.glb   a room as Blender exports one lit by an emissive mesh
                  (KHR_materials_emissive_strength, no punctual light): it
                  renders by its lamp alone, without the default sky.
  labels.glb      balls on a plinth with emissive labels no brighter than
                  a white surface (emissiveFactor 1 times a texture): the
                  default sky lights it.
  instances.gltf  meshes placed by several nodes (instances): a smooth,
                  normal-mapped, one-sided pebble with tangents and vertex
                  colours placed plain, turned, stretched, mirrored, sheared,
                  nested two groups deep and by EXT_mesh_gpu_instancing (one
                  of those mirrored); a flat-shaded block (no NORMAL) placed
                  three times (mirrored, sheared, nested); an emissive quad
                  placed twice; a floor placed once. No surface touches
                  another, so every ray's closest hit is unambiguous.

Run it from the repository root: python3 scripts/make-gltf-test-assets.py
"""
import base64
import json
import math
import os
import struct
import zlib

OUT = os.path.join("tests", "data", "gltf")

FLOAT, USHORT, UBYTE, UINT = 5126, 5123, 5121, 5125
ARRAY_BUFFER, ELEMENT_ARRAY_BUFFER = 34962, 34963


class Buffer:
    """One glTF buffer, built up view by view (each 4-byte aligned)."""

    def __init__(self):
        self.data = bytearray()
        self.views = []
        self.accessors = []

    def view(self, payload, target=None):
        while len(self.data) % 4:
            self.data += b"\0"
        view = {"buffer": 0, "byteOffset": len(self.data), "byteLength": len(payload)}
        if target:
            view["target"] = target
        self.data += payload
        self.views.append(view)
        return len(self.views) - 1

    def accessor(self, fmt, component, kind, values, **extra):
        flat = [x for v in values for x in (v if isinstance(v, (list, tuple)) else [v])]
        target = ELEMENT_ARRAY_BUFFER if kind == "SCALAR" else ARRAY_BUFFER
        acc = {"bufferView": self.view(struct.pack("<%d%s" % (len(flat), fmt), *flat), target),
               "componentType": component, "count": len(values), "type": kind}
        if kind == "VEC3" and component == FLOAT:
            acc["min"] = [min(v[i] for v in values) for i in range(3)]
            acc["max"] = [max(v[i] for v in values) for i in range(3)]
        acc.update(extra)
        self.accessors.append(acc)
        return len(self.accessors) - 1


# ---- small linear algebra (column-major 4x4, as glTF stores matrices) ----

def mat_mul(a, b):
    return [sum(a[k * 4 + r] * b[c * 4 + k] for k in range(4)) for c in range(4) for r in range(4)]


def translate(t):
    return [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, t[0], t[1], t[2], 1]


def scale(s):
    return [s[0], 0, 0, 0, 0, s[1], 0, 0, 0, 0, s[2], 0, 0, 0, 0, 1]


def rotate_quat(q):
    x, y, z, w = q
    return [1 - 2 * (y * y + z * z), 2 * (x * y + z * w), 2 * (x * z - y * w), 0,
            2 * (x * y - z * w), 1 - 2 * (x * x + z * z), 2 * (y * z + x * w), 0,
            2 * (x * z + y * w), 2 * (y * z - x * w), 1 - 2 * (x * x + y * y), 0,
            0, 0, 0, 1]


def apply(m, p):
    return [m[0 + r] * p[0] + m[4 + r] * p[1] + m[8 + r] * p[2] + m[12 + r] for r in range(3)]


def look_at_matrix(eye, at, up):
    f = [at[i] - eye[i] for i in range(3)]
    n = math.sqrt(sum(x * x for x in f))
    z = [-x / n for x in f]  # the camera looks down -Z
    x = [up[1] * z[2] - up[2] * z[1], up[2] * z[0] - up[0] * z[2], up[0] * z[1] - up[1] * z[0]]
    n = math.sqrt(sum(v * v for v in x))
    x = [v / n for v in x]
    y = [z[1] * x[2] - z[2] * x[1], z[2] * x[0] - z[0] * x[2], z[0] * x[1] - z[1] * x[0]]
    return x + [0] + y + [0] + z + [0] + list(eye) + [1]


def quat_from_matrix(m):
    """The unit quaternion (x, y, z, w) of a column-major rotation matrix."""
    r = lambda row, col: m[col * 4 + row]
    w = math.sqrt(max(0.0, 1 + r(0, 0) + r(1, 1) + r(2, 2))) / 2
    x = math.copysign(math.sqrt(max(0.0, 1 + r(0, 0) - r(1, 1) - r(2, 2))) / 2, r(2, 1) - r(1, 2))
    y = math.copysign(math.sqrt(max(0.0, 1 - r(0, 0) + r(1, 1) - r(2, 2))) / 2, r(0, 2) - r(2, 0))
    z = math.copysign(math.sqrt(max(0.0, 1 - r(0, 0) - r(1, 1) + r(2, 2))) / 2, r(1, 0) - r(0, 1))
    return [x, y, z, w]


SUN_DIRECTION = [0.7, -0.6, -0.35]


def axis_angle(axis, degrees):
    h = math.radians(degrees) / 2
    n = math.sqrt(sum(a * a for a in axis))
    return [a / n * math.sin(h) for a in axis] + [math.cos(h)]


# ---- meshes --------------------------------------------------------------

def quad(size_x, size_z, y, facing_down=False):
    """Two triangles of a quad in the y plane, centred on the origin."""
    hx, hz = size_x / 2, size_z / 2
    pos = [[-hx, y, -hz], [hx, y, -hz], [hx, y, hz], [-hx, y, hz]]
    idx = [0, 2, 1, 0, 3, 2] if not facing_down else [0, 1, 2, 0, 2, 3]
    normal = [0, -1, 0] if facing_down else [0, 1, 0]
    return pos, [normal] * 4, [[0, 0], [1, 0], [1, 1], [0, 1]], idx


def cube():
    """A unit cube around the origin, 24 vertices (flat faces), 36 indices."""
    pos, nrm, uv, idx = [], [], [], []
    for axis in range(3):
        for sign in (-1, 1):
            n = [0, 0, 0]
            n[axis] = sign
            u = [0, 0, 0]
            u[(axis + 1) % 3] = 1
            v = [0, 0, 0]
            v[(axis + 2) % 3] = 1
            base = len(pos)
            for a, b in ((-1, -1), (1, -1), (1, 1), (-1, 1)):
                pos.append([0.5 * (n[i] + a * u[i] + b * v[i]) for i in range(3)])
                nrm.append(n)
                uv.append([(a + 1) / 2, (b + 1) / 2])
            tri = [0, 1, 2, 0, 2, 3] if sign > 0 else [0, 2, 1, 0, 3, 2]
            idx += [base + t for t in tri]
    return pos, nrm, uv, idx


def add_mesh(buf, mesh, material, name):
    pos, nrm, uv, idx = mesh
    prim = {"attributes": {"POSITION": buf.accessor("f", FLOAT, "VEC3", pos),
                           "NORMAL": buf.accessor("f", FLOAT, "VEC3", nrm),
                           "TEXCOORD_0": buf.accessor("f", FLOAT, "VEC2", uv)},
            "indices": buf.accessor("H", USHORT, "SCALAR", idx), "material": material}
    return {"name": name, "primitives": [prim]}


def png(width, height, pixel, alpha=False):
    """An 8-bit RGB (or RGBA) PNG; pixel(x, y) gives (r, g, b[, a]) in 0..255."""
    raw = b"".join(b"\0" + bytes(c for x in range(width) for c in pixel(x, y)) for y in range(height))

    def chunk(tag, data):
        return struct.pack(">I", len(data)) + tag + data + struct.pack(">I", zlib.crc32(tag + data) & 0xFFFFFFFF)
    color_type = 6 if alpha else 2
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, color_type, 0, 0, 0)) +
            chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b""))


def checker(x, y):
    return (230, 200, 60) if (x // 4 + y // 4) % 2 == 0 else (40, 60, 160)


def write_json(path, doc):
    with open(path, "w") as f:
        json.dump(doc, f, indent=1)
        f.write("\n")


# ---- box-room.gltf and its darts twin -------------------------------------

MATERIALS = [
    {"name": "floor", "pbrMetallicRoughness": {"baseColorFactor": [0.6, 0.6, 0.55, 1], "metallicFactor": 0.0, "roughnessFactor": 0.8}},
    {"name": "gold", "pbrMetallicRoughness": {"baseColorFactor": [1.0, 0.78, 0.35, 1], "metallicFactor": 1.0, "roughnessFactor": 0.35}},
    {"name": "red plastic", "pbrMetallicRoughness": {"baseColorFactor": [0.7, 0.1, 0.08, 1], "metallicFactor": 0.0, "roughnessFactor": 0.45},
     "extensions": {"KHR_materials_ior": {"ior": 1.45}}},
    {"name": "panel", "pbrMetallicRoughness": {"baseColorFactor": [0, 0, 0, 1], "metallicFactor": 0.0, "roughnessFactor": 1.0},
     "emissiveFactor": [1.0, 0.9, 0.8], "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 8.0}}},
]
LIGHT_POS = [1.5, 2.2, 1.2]
# A spot above the gold box, shining down its local -Z (turned to point down
# and a little forward), and a low sun from the left.
SPOT_POS = [-0.9, 2.4, 0.6]
SPOT_MATRIX = look_at_matrix(SPOT_POS, [-0.7, 0.0, 0.0], [0, 0, -1])
SPOT_CANDELA = 10 * 683
SPOT_CONES = [0.25, 0.45]
SUN_LUX = 1.5 * 683
LIGHT_CANDELA = 6 * 683  # 6 W/sr
CAMERA = {"eye": [0.3, 1.6, 4.2], "at": [0, 0.5, 0], "yfov": 0.75, "aspect": 1.25}


def box_room():
    # The sun's node: its -Z turned to the way the sunlight travels.
    sun_rotation = quat_from_matrix(look_at_matrix([0, 0, 0], SUN_DIRECTION, [0, 1, 0]))
    buf = Buffer()
    floor, box, panel = quad(5, 5, 0), cube(), quad(1.2, 1.2, 0, facing_down=True)
    meshes = [add_mesh(buf, floor, 0, "floor"), add_mesh(buf, box, 1, "gold box"),
              add_mesh(buf, box, 2, "red box"), add_mesh(buf, panel, 3, "panel")]
    # A group node (translated) holds the two boxes: one by TRS, one by a matrix.
    gold_trs = {"translation": [-0.7, 0.45, 0], "rotation": axis_angle([0, 1, 0], 30), "scale": [0.9, 0.9, 0.9]}
    red_matrix = mat_mul(translate([0.75, 0.35, 0.4]), mat_mul(rotate_quat(axis_angle([0, 1, 0], -20)), scale([0.7, 0.7, 0.7])))
    group = [0.0, 0.0, -0.2]
    cam = look_at_matrix(CAMERA["eye"], CAMERA["at"], [0, 1, 0])
    nodes = [
        {"name": "floor", "mesh": 0},
        {"name": "boxes", "translation": group, "children": [2, 3]},
        dict({"name": "gold box", "mesh": 1}, **gold_trs),
        {"name": "red box", "mesh": 2, "matrix": red_matrix},
        {"name": "panel", "mesh": 3, "translation": [0, 2.6, 0.3]},
        {"name": "lamp", "translation": LIGHT_POS, "extensions": {"KHR_lights_punctual": {"light": 0}}},
        {"name": "spot", "matrix": SPOT_MATRIX, "extensions": {"KHR_lights_punctual": {"light": 1}}},
        {"name": "sun", "rotation": sun_rotation, "extensions": {"KHR_lights_punctual": {"light": 2}}},
        {"name": "camera", "camera": 0, "matrix": cam},
    ]
    doc = {
        "asset": {"version": "2.0", "generator": "wavepath scripts/make-gltf-test-assets.py"},
        "extensionsUsed": ["KHR_lights_punctual", "KHR_materials_emissive_strength", "KHR_materials_ior"],
        "scene": 0, "scenes": [{"nodes": [0, 1, 4, 5, 6, 7, 8]}], "nodes": nodes, "meshes": meshes, "materials": MATERIALS,
        "cameras": [{"name": "main", "type": "perspective",
                     "perspective": {"yfov": CAMERA["yfov"], "aspectRatio": CAMERA["aspect"], "znear": 0.05}}],
        "extensions": {"KHR_lights_punctual": {"lights": [
            {"name": "lamp", "type": "point", "color": [1, 0.95, 0.9], "intensity": LIGHT_CANDELA},
            {"name": "spot", "type": "spot", "color": [0.8, 0.9, 1], "intensity": SPOT_CANDELA,
             "spot": {"innerConeAngle": SPOT_CONES[0], "outerConeAngle": SPOT_CONES[1]}},
            {"name": "sun", "type": "directional", "color": [1, 0.9, 0.7], "intensity": SUN_LUX}]}},
        "accessors": buf.accessors, "bufferViews": buf.views,
        "buffers": [{"byteLength": len(buf.data),
                     "uri": "data:application/octet-stream;base64," + base64.b64encode(bytes(buf.data)).decode()}],
    }
    write_json(os.path.join(OUT, "box-room.gltf"), doc)

    # The darts twin: every triangle placed by the same transforms.
    group_m = translate(group)
    gold_m = mat_mul(group_m, mat_mul(translate(gold_trs["translation"]), mat_mul(rotate_quat(gold_trs["rotation"]), scale(gold_trs["scale"]))))
    red_m = mat_mul(group_m, red_matrix)
    placed = [(floor, translate([0, 0, 0]), "floor"), (box, gold_m, "gold"), (box, red_m, "red plastic"),
              (panel, translate([0, 2.6, 0.3]), "panel")]
    surfaces = []
    for (pos, _, _, idx), m, material in placed:
        for t in range(0, len(idx), 3):
            surfaces.append({"type": "triangle", "material": material,
                             "positions": [[round(c, 7) for c in apply(m, pos[idx[t + k]])] for k in range(3)]})
    pbr = {mt["name"]: mt["pbrMetallicRoughness"] for mt in MATERIALS}

    def darts_material(name, ior=1.5):
        p = pbr[name]
        return {"type": "metal_rough", "name": name, "base_color": p["baseColorFactor"][:3], "metallic": p["metallicFactor"],
                "roughness": p["roughnessFactor"], "ior": ior}
    materials = [darts_material("floor"), darts_material("gold"), darts_material("red plastic", 1.45),
                 dict(darts_material("panel"), emit=[8.0 * c for c in MATERIALS[3]["emissiveFactor"]])]
    darts = {
        "camera": {"transform": {"from": CAMERA["eye"], "at": CAMERA["at"], "up": [0, 1, 0]},
                   "vfov": math.degrees(CAMERA["yfov"]), "resolution": [50, 40]},
        "sampler": {"samples": 64}, "background": 0,
        "integrator": {"type": "path tracer mis", "max bounces": 16},
        "materials": materials,
        "surfaces": surfaces + [
            {"type": "point_light", "position": LIGHT_POS, "intensity": [6 * c for c in (1, 0.95, 0.9)]},
            {"type": "spot_light", "position": SPOT_POS, "direction": [-0.7 - SPOT_POS[0], -SPOT_POS[1], -SPOT_POS[2]],
             "intensity": [10 * c for c in (0.8, 0.9, 1)], "inner_angle": math.degrees(SPOT_CONES[0]),
             "outer_angle": math.degrees(SPOT_CONES[1])},
            {"type": "directional_light", "direction": SUN_DIRECTION, "irradiance": [1.5 * c for c in (1, 0.9, 0.7)]}],
    }
    return darts


# ---- textured.glb ---------------------------------------------------------

def glb(doc, binary):
    text = json.dumps(doc, separators=(",", ":")).encode()
    text += b" " * (-len(text) % 4)
    binary = bytes(binary) + b"\0" * (-len(binary) % 4)
    body = struct.pack("<II", len(text), 0x4E4F534A) + text + struct.pack("<II", len(binary), 0x004E4942) + binary
    return struct.pack("<4sII", b"glTF", 2, 12 + len(body)) + body


def roughness_map(x, y):
    """Green: roughness from 0.2 (left) to 1 (right); blue: metallic in the top half."""
    return (0, int(255 * (0.2 + 0.8 * x / 15)), 255 if y < 8 else 0)


def textured():
    buf = Buffer()
    floor_pos, floor_nrm, _, floor_idx = quad(4, 4, 0)
    uv = [[0, 0], [2, 0], [2, 2], [0, 2]]  # repeats twice
    floor = {"attributes": {"POSITION": buf.accessor("f", FLOAT, "VEC3", floor_pos),
                            "NORMAL": buf.accessor("f", FLOAT, "VEC3", floor_nrm),
                            "TEXCOORD_0": buf.accessor("f", FLOAT, "VEC2", uv)},
             "indices": buf.accessor("B", UBYTE, "SCALAR", floor_idx), "material": 0}
    pos, nrm, cuv, idx = cube()
    positions = buf.accessor("f", FLOAT, "VEC3", pos)
    # Sparse: the twelve vertices at the top of the cube lifted to y = 0.9.
    top = [i for i, p in enumerate(pos) if p[1] > 0.4]
    sparse_idx = buf.view(struct.pack("<%dB" % len(top), *top))
    sparse_val = buf.view(struct.pack("<%df" % (3 * len(top)), *[c for i in top for c in (pos[i][0], 0.9, pos[i][2])]))
    buf.accessors[positions]["sparse"] = {"count": len(top), "indices": {"bufferView": sparse_idx, "componentType": UBYTE},
                                          "values": {"bufferView": sparse_val}}
    buf.accessors[positions]["max"][1] = 0.9
    box = {"attributes": {"POSITION": positions, "NORMAL": buf.accessor("f", FLOAT, "VEC3", nrm),
                          "TEXCOORD_0": buf.accessor("H", USHORT, "VEC2", [[round(65535 * c) for c in t] for t in cuv], normalized=True)},
           "indices": buf.accessor("B", UBYTE, "SCALAR", idx), "material": 1}
    base_png = buf.view(png(16, 16, checker))
    rough_png = buf.view(png(16, 16, roughness_map))
    doc = {
        "asset": {"version": "2.0", "generator": "wavepath scripts/make-gltf-test-assets.py"},
        "scene": 0, "scenes": [{"nodes": [0, 1, 2, 3]}],
        "nodes": [{"mesh": 0}, {"mesh": 1, "translation": [0, 0.5, 0]},
                  {"name": "ortho camera", "camera": 0, "translation": [0, 1, 5]},
                  {"name": "camera", "camera": 1, "matrix": look_at_matrix([2.5, 2.5, 3.5], [0, 0.6, 0], [0, 1, 0])}],
        "meshes": [{"primitives": [floor]}, {"primitives": [box]}],
        "extensionsUsed": ["KHR_texture_transform"],
        "materials": [{"name": "checker", "pbrMetallicRoughness": {"baseColorTexture": {
                          "index": 0, "extensions": {"KHR_texture_transform": {"offset": [0.5, 0.25], "rotation": math.pi / 2, "scale": [2, 3]}}},
                                                                 "metallicFactor": 0.0}},
                      {"name": "patchy", "pbrMetallicRoughness": {"baseColorFactor": [0.9, 0.9, 0.9, 1],
                                                                  "metallicRoughnessTexture": {"index": 1}}}],
        "textures": [{"source": 0, "sampler": 0}, {"source": 1, "sampler": 0}],
        "samplers": [{"magFilter": 9729, "minFilter": 9729}],
        "images": [{"bufferView": base_png, "mimeType": "image/png"}, {"bufferView": rough_png, "mimeType": "image/png"}],
        "cameras": [{"name": "ortho", "type": "orthographic", "orthographic": {"xmag": 2, "ymag": 2, "znear": 0.1, "zfar": 100}},
                    {"name": "persp", "type": "perspective", "perspective": {"yfov": 0.8, "znear": 0.1}}],
        "accessors": buf.accessors, "bufferViews": buf.views, "buffers": [{"byteLength": len(buf.data)}],
    }
    with open(os.path.join(OUT, "textured.glb"), "wb") as f:
        f.write(glb(doc, buf.data))


# ---- external/ --------------------------------------------------------------

def external():
    buf = Buffer()
    pos, nrm, uv, idx = quad(2, 2, 0)
    prim = {"attributes": {"POSITION": buf.accessor("f", FLOAT, "VEC3", pos), "TEXCOORD_0": buf.accessor("f", FLOAT, "VEC2", uv)},
            "indices": buf.accessor("I", UINT, "SCALAR", idx), "material": 0}
    doc = {
        "asset": {"version": "2.0"}, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}], "meshes": [{"primitives": [prim]}],
        "materials": [{"pbrMetallicRoughness": {"baseColorTexture": {"index": 0}, "metallicFactor": 0.0, "roughnessFactor": 1.0}}],
        "textures": [{"source": 0}], "images": [{"uri": "checker.png"}],
        "accessors": buf.accessors, "bufferViews": buf.views, "buffers": [{"byteLength": len(buf.data), "uri": "scene.bin"}],
    }
    write_json(os.path.join(OUT, "external", "scene.gltf"), doc)
    with open(os.path.join(OUT, "external", "scene.bin"), "wb") as f:
        f.write(bytes(buf.data))
    with open(os.path.join(OUT, "external", "checker.png"), "wb") as f:
        f.write(png(16, 16, checker))


# ---- surface.glb ------------------------------------------------------------

def normal_texel(n):
    """A tangent-space normal, normalised, as 8-bit RGB."""
    length = math.sqrt(sum(c * c for c in n))
    return tuple(int(round(255 * (c / length * 0.5 + 0.5))) for c in n)


def ripples(x, y):
    """A tangent-space normal map of ridges across u (x), strong enough to see."""
    return normal_texel([-0.9 * math.cos(2 * math.pi * (x + 0.5) / 8), 0.0, 1.0])


def dimples(slope):
    """A normal map of dimples in both directions (so the bitangent's sign
    shows too), their slopes reaching `slope`."""
    return lambda x, y: normal_texel([slope * math.sin(2 * math.pi * (x + 0.5) / 8),
                                      slope * math.sin(2 * math.pi * (y + 0.5) / 8), 1.0])


def fence(x, y):
    """RGBA: opaque white bars with fully transparent gaps between them."""
    bar = x % 8 < 3 or y % 8 < 2
    return (240, 240, 240, 255) if bar else (255, 0, 0, 0)


def stripes(x, y):
    """A gradient with a mark in one corner, so clamping and mirroring show."""
    return (int(255 * x / 15), 60 if y < 8 else 200, 255 if x < 3 and y < 3 else 30)


def surface():
    buf = Buffer()

    def prim(pos, idx, material, **attributes):
        attrs = {"POSITION": buf.accessor("f", FLOAT, "VEC3", pos)}
        for name, (fmt, component, kind, values, extra) in attributes.items():
            attrs[name] = buf.accessor(fmt, component, kind, values, **extra)
        return {"attributes": attrs, "indices": buf.accessor("H", USHORT, "SCALAR", idx), "material": material}

    def f(kind, values, **extra):
        return ("f", FLOAT, kind, values, extra)

    # The floor: the ripple normal map with its TANGENT given, vertex colours
    # (normalized unsigned bytes, RGBA) that tint the base colour.
    floor_pos, floor_nrm, _, floor_idx = quad(4, 4, 0)
    floor_uv = [[0, 0], [3, 0], [3, 3], [0, 3]]
    colors = [[255, 60, 60, 255], [60, 255, 60, 255], [60, 60, 255, 255], [255, 255, 255, 255]]
    floor = prim(floor_pos, floor_idx, 0, NORMAL=f("VEC3", floor_nrm), TEXCOORD_0=f("VEC2", floor_uv),
                 TANGENT=f("VEC4", [[1, 0, 0, 1]] * 4), COLOR_0=("B", UBYTE, "VEC4", colors, {"normalized": True}))
    # A cube with the dimple map and no TANGENT: the renderer derives them.
    pos, nrm, cuv, idx = cube()
    box = prim(pos, idx, 1, NORMAL=f("VEC3", nrm), TEXCOORD_0=f("VEC2", cuv))
    # A fence: MASK with an RGBA texture; double-sided.
    fence_pos = [[-1, 0, 0], [1, 0, 0], [1, 1.2, 0], [-1, 1.2, 0]]
    fence_idx = [0, 1, 2, 0, 2, 3]
    fence_uv = [[0, 1], [2, 1], [2, 0], [0, 0]]
    fence_prim = prim(fence_pos, fence_idx, 2, NORMAL=f("VEC3", [[0, 0, 1]] * 4), TEXCOORD_0=f("VEC2", fence_uv))
    # A pane: BLEND at alpha 0.4 (stochastic transparency), one-sided, its
    # base colour a gradient on the second UV set, clamped in u and
    # mirrored in v beyond [0, 1].
    pane_uv1 = [[-0.5, 1.5], [1.5, 1.5], [1.5, -0.5], [-0.5, -0.5]]
    pane = prim(fence_pos, fence_idx, 3, NORMAL=f("VEC3", [[0, 0, 1]] * 4), TEXCOORD_0=f("VEC2", fence_uv),
                TEXCOORD_1=f("VEC2", pane_uv1))
    # A wall facing away from the camera: one-sided, so the camera sees
    # through it; its colour would show if its back were there.
    wall = prim([[-0.6, 0, 0], [-0.6, 1.0, 0], [0.6, 1.0, 0], [0.6, 0, 0]], [0, 1, 2, 0, 2, 3], 4)
    # Thin-walled transmission on a second cube.
    glass = prim(pos, idx, 5, NORMAL=f("VEC3", nrm))
    normal_png = buf.view(png(16, 16, ripples))
    bumps_png = buf.view(png(16, 16, dimples(0.7)))
    fence_png = buf.view(png(16, 16, fence, alpha=True))
    stripes_png = buf.view(png(16, 16, stripes))
    sun_rotation = quat_from_matrix(look_at_matrix([0, 0, 0], [0.4, -1.0, -0.5], [0, 1, 0]))
    doc = {
        "asset": {"version": "2.0", "generator": "wavepath scripts/make-gltf-test-assets.py"},
        "scene": 0, "scenes": [{"nodes": [0, 1, 2, 3, 4, 5, 6, 7, 8]}],
        "nodes": [{"mesh": 0},
                  {"mesh": 1, "translation": [-1.0, 0.5, -0.6], "rotation": quat_from_matrix(look_at_matrix([0, 0, 0], [0.5, 0, -1], [0, 1, 0]))},
                  {"mesh": 2, "translation": [0.2, 0, -1.5]},
                  {"mesh": 3, "translation": [1.2, 0, 0.6], "scale": [0.5, 0.8, 1]},
                  {"mesh": 4, "translation": [-0.3, 0, 1.6]},
                  {"mesh": 5, "translation": [1.1, 0.35, -0.5], "scale": [0.7, 0.7, 0.7]},
                  {"name": "camera", "camera": 0, "matrix": look_at_matrix([0.2, 1.7, 3.6], [0, 0.4, -0.4], [0, 1, 0])},
                  {"name": "lamp", "translation": [1.0, 2.5, 1.5], "extensions": {"KHR_lights_punctual": {"light": 0}}},
                  {"name": "sun", "rotation": sun_rotation, "extensions": {"KHR_lights_punctual": {"light": 1}}}],
        "meshes": [{"name": "floor", "primitives": [floor]}, {"name": "bumpy box", "primitives": [box]},
                   {"name": "fence", "primitives": [fence_prim]}, {"name": "pane", "primitives": [pane]},
                   {"name": "wall", "primitives": [wall]}, {"name": "glass box", "primitives": [glass]}],
        "extensionsUsed": ["KHR_lights_punctual", "KHR_materials_transmission"],
        "extensions": {"KHR_lights_punctual": {"lights": [
            {"type": "point", "color": [1, 0.95, 0.9], "intensity": 8 * 683},
            {"type": "directional", "color": [1, 1, 1], "intensity": 1.2 * 683}]}},
        "materials": [
            {"name": "rippled floor", "pbrMetallicRoughness": {"baseColorFactor": [0.9, 0.9, 0.9, 1], "metallicFactor": 0.0, "roughnessFactor": 0.4},
             "normalTexture": {"index": 0, "scale": 1.0}},
            {"name": "dimpled metal", "pbrMetallicRoughness": {"baseColorFactor": [0.95, 0.7, 0.4, 1], "metallicFactor": 0.6, "roughnessFactor": 0.3},
             "normalTexture": {"index": 1, "scale": 0.8}},
            {"name": "fence", "pbrMetallicRoughness": {"baseColorTexture": {"index": 2}, "metallicFactor": 0.0},
             "alphaMode": "MASK", "alphaCutoff": 0.5, "doubleSided": True},
            {"name": "pane", "pbrMetallicRoughness": {"baseColorTexture": {"index": 3, "texCoord": 1}, "baseColorFactor": [0.3, 0.6, 1.0, 0.4],
                                                      "metallicFactor": 0.0, "roughnessFactor": 0.2},
             "alphaMode": "BLEND"},
            {"name": "wall (one-sided)", "pbrMetallicRoughness": {"baseColorFactor": [1.0, 0.2, 0.1, 1], "metallicFactor": 0.0}},
            {"name": "thin glass", "pbrMetallicRoughness": {"baseColorFactor": [0.9, 1.0, 0.9, 1], "metallicFactor": 0.0, "roughnessFactor": 0.25},
             "extensions": {"KHR_materials_transmission": {"transmissionFactor": 0.9, "transmissionTexture": {"index": 4}}}},
        ],
        "textures": [{"source": 0}, {"source": 1}, {"source": 2, "sampler": 0}, {"source": 3, "sampler": 1}, {"source": 2}],
        "samplers": [{"wrapS": 10497, "wrapT": 10497}, {"wrapS": 33071, "wrapT": 33648}],
        "images": [{"bufferView": v, "mimeType": "image/png"} for v in (normal_png, bumps_png, fence_png, stripes_png)],
        "cameras": [{"name": "view", "type": "perspective", "perspective": {"yfov": 0.8, "aspectRatio": 1.5, "znear": 0.1}}],
        "accessors": buf.accessors, "bufferViews": buf.views, "buffers": [{"byteLength": len(buf.data)}],
    }
    with open(os.path.join(OUT, "surface.glb"), "wb") as out:
        out.write(glb(doc, buf.data))


# ---- mirror-bumps.glb --------------------------------------------------------

def uv_sphere(rings=24, segments=48):
    """A unit sphere: positions, normals, UVs, tangents (along u) and indices."""
    pos, nrm, uv, tan, idx = [], [], [], [], []
    for r in range(rings + 1):
        theta = math.pi * r / rings
        for s in range(segments + 1):
            phi = 2 * math.pi * s / segments
            p = [math.sin(theta) * math.cos(phi), math.cos(theta), -math.sin(theta) * math.sin(phi)]
            pos.append(p)
            nrm.append(p)
            uv.append([s / segments * 4, r / rings * 2])
            tan.append([-math.sin(phi), 0.0, -math.cos(phi), 1.0])
    for r in range(rings):
        for s in range(segments):
            a, b = r * (segments + 1) + s, (r + 1) * (segments + 1) + s
            idx += [a, b, a + 1, a + 1, b, b + 1]
    return pos, nrm, uv, tan, idx


def mirror_bumps():
    buf = Buffer()
    pos, nrm, uv, tan, idx = uv_sphere()
    attrs = {"POSITION": buf.accessor("f", FLOAT, "VEC3", pos), "NORMAL": buf.accessor("f", FLOAT, "VEC3", nrm),
             "TEXCOORD_0": buf.accessor("f", FLOAT, "VEC2", uv), "TANGENT": buf.accessor("f", FLOAT, "VEC4", tan)}
    doc = {
        "asset": {"version": "2.0", "generator": "wavepath scripts/make-gltf-test-assets.py"},
        "scene": 0, "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0}],
        "meshes": [{"name": "bumpy mirror", "primitives": [
            {"attributes": attrs, "indices": buf.accessor("H", USHORT, "SCALAR", idx), "material": 0}]}],
        "materials": [{"name": "white mirror", "normalTexture": {"index": 0},
                       "pbrMetallicRoughness": {"baseColorFactor": [1, 1, 1, 1], "metallicFactor": 1.0, "roughnessFactor": 0.0}}],
        "textures": [{"source": 0}],
        "images": [{"bufferView": buf.view(png(16, 16, dimples(1.5))), "mimeType": "image/png"}],
        "accessors": buf.accessors, "bufferViews": buf.views, "buffers": [{"byteLength": len(buf.data)}],
    }
    with open(os.path.join(OUT, "mirror-bumps.glb"), "wb") as out:
        out.write(glb(doc, buf.data))


# ---- layers.glb ----------------------------------------------------------------

def layers():
    """Spheres in the PBR extensions Blender exports, under a sun: a clear
    coat with textured factor (R), roughness (G) and its own normal map; a
    sheen with a textured colour and an RGBA roughness texture (A); a tinted
    specular layer with textured factor (A) and colour; below them a thin
    film with textured factor (R) and thickness (G); a brushed metal whose
    anisotropy texture turns the direction (RG) and scales the strength (B);
    and glass refracting into an absorbing volume."""
    buf = Buffer()
    pos, nrm, uv, tan, idx = uv_sphere(16, 32)
    attrs = {"POSITION": buf.accessor("f", FLOAT, "VEC3", pos), "NORMAL": buf.accessor("f", FLOAT, "VEC3", nrm),
             "TEXCOORD_0": buf.accessor("f", FLOAT, "VEC2", uv), "TANGENT": buf.accessor("f", FLOAT, "VEC4", tan)}
    indices = buf.accessor("H", USHORT, "SCALAR", idx)
    # Red: the texel's column half (0 or 255); green: 64; blue: row bands;
    # alpha: 255 in the left half, 64 in the right.
    stripes_rgba = png(8, 8, lambda x, y: (255 if x < 4 else 0, 64, 30 * y, 255 if x < 4 else 64), alpha=True)
    base = {"baseColorFactor": [0.7, 0.15, 0.1, 1], "metallicFactor": 0.0, "roughnessFactor": 0.5}
    doc = {
        "asset": {"version": "2.0", "generator": "wavepath scripts/make-gltf-test-assets.py"},
        "extensionsUsed": ["KHR_materials_clearcoat", "KHR_materials_sheen", "KHR_materials_specular", "KHR_materials_iridescence",
                           "KHR_materials_anisotropy", "KHR_materials_transmission", "KHR_materials_ior", "KHR_materials_volume",
                           "KHR_materials_dispersion", "KHR_lights_punctual"],
        "scene": 0, "scenes": [{"nodes": [0, 1, 2, 3, 4, 5, 6, 7]}],
        "nodes": [{"mesh": 0, "translation": [-2.2, 1.1, 0]}, {"mesh": 1, "translation": [0, 1.1, 0]},
                  {"mesh": 2, "translation": [2.2, 1.1, 0]},
                  {"extensions": {"KHR_lights_punctual": {"light": 0}}, "rotation": [-0.3826834, 0, 0, 0.9238795]},
                  {"camera": 0, "translation": [0, 0, 10]},
                  {"mesh": 3, "translation": [-2.2, -1.1, 0]}, {"mesh": 4, "translation": [0, -1.1, 0]},
                  {"mesh": 5, "translation": [2.2, -1.1, 0]}],
        "cameras": [{"type": "perspective", "perspective": {"yfov": 0.55, "aspectRatio": 1.4, "znear": 0.1}}],
        "meshes": [{"name": "coated", "primitives": [{"attributes": attrs, "indices": indices, "material": 0}]},
                   {"name": "sheen", "primitives": [{"attributes": attrs, "indices": indices, "material": 1}]},
                   {"name": "specular", "primitives": [{"attributes": attrs, "indices": indices, "material": 2}]},
                   {"name": "film", "primitives": [{"attributes": attrs, "indices": indices, "material": 3}]},
                   {"name": "brushed", "primitives": [{"attributes": attrs, "indices": indices, "material": 4}]},
                   {"name": "glass", "primitives": [{"attributes": attrs, "indices": indices, "material": 5}]}],
        "materials": [
            {"name": "lacquer", "pbrMetallicRoughness": base, "extensions": {"KHR_materials_clearcoat": {
                "clearcoatFactor": 0.9, "clearcoatTexture": {"index": 0}, "clearcoatRoughnessFactor": 0.5,
                "clearcoatRoughnessTexture": {"index": 0}, "clearcoatNormalTexture": {"index": 1, "scale": 0.7}}}},
            {"name": "velvet", "pbrMetallicRoughness": {"baseColorFactor": [0.1, 0.05, 0.2, 1], "metallicFactor": 0.0, "roughnessFactor": 0.9},
             "extensions": {"KHR_materials_sheen": {"sheenColorFactor": [0.9, 0.6, 0.8], "sheenColorTexture": {"index": 2},
                                                    "sheenRoughnessFactor": 0.8, "sheenRoughnessTexture": {"index": 0}}}},
            {"name": "tinted", "pbrMetallicRoughness": base, "extensions": {"KHR_materials_specular": {
                "specularFactor": 0.8, "specularTexture": {"index": 0}, "specularColorFactor": [2.0, 1.5, 1.0],
                "specularColorTexture": {"index": 2}}}},
            {"name": "film", "pbrMetallicRoughness": {"baseColorFactor": [0.2, 0.2, 0.25, 1], "metallicFactor": 0.5, "roughnessFactor": 0.2},
             "extensions": {"KHR_materials_iridescence": {"iridescenceFactor": 1.0, "iridescenceTexture": {"index": 0}, "iridescenceIor": 1.4,
                                                          "iridescenceThicknessMinimum": 200, "iridescenceThicknessMaximum": 500,
                                                          "iridescenceThicknessTexture": {"index": 0}}}},
            {"name": "brushed", "pbrMetallicRoughness": {"baseColorFactor": [0.9, 0.85, 0.8, 1], "metallicFactor": 1.0, "roughnessFactor": 0.35},
             "extensions": {"KHR_materials_anisotropy": {"anisotropyStrength": 0.9, "anisotropyRotation": 0.4, "anisotropyTexture": {"index": 0}}}},
            {"name": "glass", "pbrMetallicRoughness": {"baseColorFactor": [1, 1, 1, 1], "metallicFactor": 0.0, "roughnessFactor": 0.1},
             "extensions": {"KHR_materials_transmission": {"transmissionFactor": 1.0}, "KHR_materials_ior": {"ior": 1.5},
                            "KHR_materials_volume": {"thicknessFactor": 1.0, "attenuationDistance": 0.8, "attenuationColor": [0.9, 0.4, 0.2]},
                            "KHR_materials_dispersion": {"dispersion": 0.6}}}],
        "extensions": {"KHR_lights_punctual": {"lights": [{"type": "directional", "intensity": 2.5 * 683}]}},
        "textures": [{"source": 0}, {"source": 1}, {"source": 2}],
        "images": [{"bufferView": buf.view(stripes_rgba), "mimeType": "image/png"},
                   {"bufferView": buf.view(png(16, 16, dimples(0.8))), "mimeType": "image/png"},
                   {"bufferView": buf.view(png(4, 4, checker)), "mimeType": "image/png"}],
        "accessors": buf.accessors, "bufferViews": buf.views, "buffers": [{"byteLength": len(buf.data)}],
    }
    with open(os.path.join(OUT, "layers.glb"), "wb") as out:
        out.write(glb(doc, buf.data))


# ---- translucent.glb -----------------------------------------------------------

def translucent():
    """Rows of double-sided 1 x 1 panes in the z = 0 plane facing the camera
    (+z), lit from behind by a sun travelling along +z: the factor from 0 to
    1 left to right (white transmission), the same with a red colour factor,
    a factor of 1 times a texture whose alpha ramps across the pane, and a
    colour texture (red and yellow stripes) at the row's factors. A dark
    pink strip half a unit behind the gap between the middle rows, out of
    the sun (the panes' shadows miss it), is lit by the light their backs
    reflect."""
    buf = Buffer()
    pos = [[-0.5, -0.5, 0], [0.5, -0.5, 0], [0.5, 0.5, 0], [-0.5, 0.5, 0]]
    attrs = {"POSITION": buf.accessor("f", FLOAT, "VEC3", pos), "NORMAL": buf.accessor("f", FLOAT, "VEC3", [[0, 0, 1]] * 4),
             "TEXCOORD_0": buf.accessor("f", FLOAT, "VEC2", [[0, 1], [1, 1], [1, 0], [0, 0]])}
    indices = buf.accessor("H", USHORT, "SCALAR", [0, 1, 2, 0, 2, 3])
    factors = [0.0, 0.25, 0.5, 0.75, 1.0]
    base = {"baseColorFactor": [0.0, 0.25, 0.25, 1], "metallicFactor": 0.0, "roughnessFactor": 0.5}
    rows = [
        lambda f: {"diffuseTransmissionFactor": f},
        lambda f: {"diffuseTransmissionFactor": f, "diffuseTransmissionColorFactor": [1, 0, 0]},
        lambda f: {"diffuseTransmissionFactor": 1.0, "diffuseTransmissionTexture": {"index": 0}},
        lambda f: {"diffuseTransmissionFactor": f, "diffuseTransmissionColorTexture": {"index": 1}},
    ]
    materials, meshes, nodes = [], [], []
    for r, row in enumerate(rows):
        for c, f in enumerate(factors):
            materials.append({"name": "row %d factor %g" % (r, f), "doubleSided": True, "pbrMetallicRoughness": base,
                              "extensions": {"KHR_materials_diffuse_transmission": row(f)}})
            meshes.append({"primitives": [{"attributes": attrs, "indices": indices, "material": len(materials) - 1}]})
            nodes.append({"mesh": len(meshes) - 1, "translation": [1.2 * (c - 2), 1.8 - 1.2 * r, 0]})
    materials.append({"name": "behind", "pbrMetallicRoughness": {"baseColorFactor": [0.5, 0.1, 0.2, 1], "metallicFactor": 0.0,
                                                                 "roughnessFactor": 1.0}})
    meshes.append({"primitives": [{"attributes": attrs, "indices": indices, "material": len(materials) - 1}]})
    nodes.append({"mesh": len(meshes) - 1, "translation": [0, 0, -0.5], "scale": [7, 0.15, 1]})
    nodes.append({"extensions": {"KHR_lights_punctual": {"light": 0}}, "rotation": [1, 0, 0, 0]})  # -Z turned to +Z
    nodes.append({"camera": 0, "translation": [0, 0, 9]})
    # Alpha ramps left to right; the colour stripes alternate red and yellow.
    ramp = png(8, 8, lambda x, y: (255, 255, 255, 32 * x + 16), alpha=True)
    stripes = png(8, 8, lambda x, y: (230, 40, 20) if (x // 2) % 2 == 0 else (240, 220, 40))
    doc = {
        "asset": {"version": "2.0", "generator": "wavepath scripts/make-gltf-test-assets.py"},
        "extensionsUsed": ["KHR_materials_diffuse_transmission", "KHR_lights_punctual"],
        "scene": 0, "scenes": [{"nodes": list(range(len(nodes)))}],
        "nodes": nodes, "meshes": meshes, "materials": materials,
        "cameras": [{"type": "perspective", "perspective": {"yfov": 0.6, "aspectRatio": 1.4, "znear": 0.1}}],
        "extensions": {"KHR_lights_punctual": {"lights": [{"type": "directional", "intensity": 3.0 * 683}]}},
        "textures": [{"source": 0}, {"source": 1}],
        "images": [{"bufferView": buf.view(ramp), "mimeType": "image/png"}, {"bufferView": buf.view(stripes), "mimeType": "image/png"}],
        "accessors": buf.accessors, "bufferViews": buf.views, "buffers": [{"byteLength": len(buf.data)}],
    }
    with open(os.path.join(OUT, "translucent.glb"), "wb") as out:
        out.write(glb(doc, buf.data))


# ---- instances.gltf --------------------------------------------------------

def instances():
    buf = Buffer()

    def f(kind, values):
        return buf.accessor("f", FLOAT, kind, values)

    def unit(v):
        n = math.sqrt(sum(c * c for c in v))
        return [c / n for c in v]

    # The pebble: a squashed UV sphere with smooth normals, UVs, tangents
    # along u and vertex colours; poles without degenerate triangles.
    rings, segments = 6, 10
    pos, nrm, uv, tan, col, idx = [], [], [], [], [], []
    for r in range(rings + 1):
        theta = math.pi * r / rings
        for s_ in range(segments + 1):
            phi = 2 * math.pi * s_ / segments
            p = [math.sin(theta) * math.cos(phi), 0.8 * math.cos(theta), math.sin(theta) * math.sin(phi)]
            pos.append(p)
            nrm.append(unit([p[0], p[1] / 0.64, p[2]]))
            uv.append([s_ / segments, r / rings])
            tan.append(unit([-math.sin(phi), 0.0, math.cos(phi)]) + [1.0])
            col.append([0.6 + 0.4 * (s_ % 2), 0.8, 0.6 + 0.4 * (r % 2), 1.0])
    for r in range(rings):
        for s_ in range(segments):
            a, b = r * (segments + 1) + s_, (r + 1) * (segments + 1) + s_
            if r != 0:
                idx += [a, a + 1, b]
            if r != rings - 1:
                idx += [a + 1, b + 1, b]
    pebble = {"attributes": {"POSITION": f("VEC3", pos), "NORMAL": f("VEC3", nrm), "TEXCOORD_0": f("VEC2", uv),
                             "TANGENT": f("VEC4", tan), "COLOR_0": f("VEC4", col)},
              "indices": buf.accessor("I", UINT, "SCALAR", idx), "material": 0}
    # The block: a unit cube without normals (flat shading, barycentric UVs).
    cube_pos, _, _, cube_idx = cube()
    block = {"attributes": {"POSITION": f("VEC3", cube_pos)}, "indices": buf.accessor("H", USHORT, "SCALAR", cube_idx), "material": 1}
    lamp_pos, _, _, lamp_idx = quad(1.0, 1.0, 0.0, facing_down=True)
    lamp = {"attributes": {"POSITION": f("VEC3", lamp_pos)}, "indices": buf.accessor("H", USHORT, "SCALAR", lamp_idx), "material": 2}
    floor_pos, floor_nrm, _, floor_idx = quad(16.0, 16.0, 0.0)
    floor = {"attributes": {"POSITION": f("VEC3", floor_pos), "NORMAL": f("VEC3", floor_nrm)},
             "indices": buf.accessor("H", USHORT, "SCALAR", floor_idx), "material": 3}
    # Three pebbles by EXT_mesh_gpu_instancing, the last mirrored.
    gpu_instances = {"TRANSLATION": f("VEC3", [[-2.2, 0.3, 1.8], [-1.0, 0.5, 2.4], [0.2, 0.4, 2.0]]),
                     "ROTATION": f("VEC4", [unit([0, 0.3, 0, 1]), unit([0.4, 0, 0.2, 1]), [0, 0, 0, 1]]),
                     "SCALE": f("VEC3", [[0.3, 0.3, 0.3], [0.25, 0.5, 0.25], [-0.35, 0.3, 0.3]])}
    for a in gpu_instances.values():  # instance attributes are no vertex data: their views have no target
        buf.views[buf.accessors[a]["bufferView"]].pop("target", None)
    nodes = [
        {"name": "pebble", "mesh": 0, "translation": [-2.0, 0.8, 0.0]},
        {"name": "pebble turned, smaller", "mesh": 0, "translation": [-0.6, 0.5, -0.5], "rotation": axis_angle([0, 0, 1], 35),
         "scale": [0.6, 0.6, 0.6]},
        {"name": "pebble stretched", "mesh": 0, "translation": [0.8, 0.6, 0.2], "scale": [0.5, 1.1, 0.8]},
        {"name": "pebble mirrored", "mesh": 0, "translation": [2.0, 0.7, 0.0], "rotation": axis_angle([0, 1, 0], 30),
         "scale": [-0.7, 0.7, 0.7]},
        {"name": "pebble sheared", "mesh": 0, "matrix": [0.6, 0, 0, 0, 0.45, 0.6, 0.2, 0, 0, 0, 0.6, 0, -1.0, 0.6, 1.2, 1]},
        {"name": "group", "translation": [0.5, 0.0, -2.0], "rotation": axis_angle([0, 1, 0], -25), "scale": [0.8, 0.8, 0.8],
         "children": [6]},
        {"name": "subgroup", "translation": [1.0, 0.2, 0.0], "rotation": axis_angle([1, 0, 0], 15), "children": [7, 8]},
        {"name": "pebble nested", "mesh": 0, "translation": [0.0, 0.8, 0.0], "scale": [0.9, 0.6, 0.9]},
        {"name": "block nested, mirrored", "mesh": 1, "translation": [-1.5, 0.6, 0.3], "rotation": axis_angle([1, 1, 0], 40),
         "scale": [1.0, -0.8, 1.2]},
        {"name": "block", "mesh": 1, "translation": [-2.8, 0.53, -1.5], "rotation": axis_angle([0, 1, 0], 20)},
        {"name": "block sheared", "mesh": 1, "matrix": [0.9, 0.0, 0.3, 0, 0.0, 0.7, 0, 0, 0.0, 0.5, 0.8, 0, 2.6, 0.4, -1.6, 1]},
        {"name": "lamp", "mesh": 2, "translation": [-1.0, 3.5, 0.5], "scale": [1.5, 1.0, 0.8]},
        {"name": "lamp turned", "mesh": 2, "translation": [1.5, 3.2, -0.5], "rotation": axis_angle([0, 0, 1], 20), "scale": [0.8, 1.0, 1.6]},
        {"name": "floor", "mesh": 3},
        {"name": "pebbles by EXT_mesh_gpu_instancing", "mesh": 0, "translation": [0.0, 0.0, 0.2], "rotation": axis_angle([0, 1, 0], 10),
         "extensions": {"EXT_mesh_gpu_instancing": {"attributes": gpu_instances}}},
        {"name": "camera", "camera": 0, "translation": [0.0, 4.2, 7.5], "rotation": axis_angle([1, 0, 0], -28)},
    ]
    doc = {
        "asset": {"version": "2.0", "generator": "wavepath scripts/make-gltf-test-assets.py"},
        "extensionsUsed": ["EXT_mesh_gpu_instancing", "KHR_materials_emissive_strength"],
        "scene": 0, "scenes": [{"nodes": [0, 1, 2, 3, 4, 5, 9, 10, 11, 12, 13, 14, 15]}], "nodes": nodes,
        "meshes": [{"name": "pebble", "primitives": [pebble]}, {"name": "block", "primitives": [block]},
                   {"name": "lamp", "primitives": [lamp]}, {"name": "floor", "primitives": [floor]}],
        "materials": [
            {"name": "pebble", "doubleSided": False, "normalTexture": {"index": 0, "scale": 0.8},
             "pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.5, 0.3, 1], "metallicFactor": 0.0, "roughnessFactor": 0.45}},
            {"name": "block", "pbrMetallicRoughness": {"baseColorFactor": [0.3, 0.5, 0.8, 1], "metallicFactor": 0.6, "roughnessFactor": 0.3}},
            {"name": "lamp", "doubleSided": False, "emissiveFactor": [1, 0.9, 0.7],
             "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 6}}, "pbrMetallicRoughness": {"baseColorFactor": [0, 0, 0, 1]}},
            {"name": "floor", "pbrMetallicRoughness": {"baseColorFactor": [0.7, 0.7, 0.7, 1], "metallicFactor": 0, "roughnessFactor": 1}}],
        "textures": [{"source": 0}],
        "images": [{"uri": "data:image/png;base64," + base64.b64encode(png(8, 8, dimples(0.5))).decode()}],
        "cameras": [{"type": "perspective", "perspective": {"yfov": 0.75, "aspectRatio": 1.5, "znear": 0.1}}],
        "accessors": buf.accessors, "bufferViews": buf.views,
        "buffers": [{"byteLength": len(buf.data),
                     "uri": "data:application/octet-stream;base64," + base64.b64encode(bytes(buf.data)).decode()}],
    }
    write_json(os.path.join(OUT, "instances.gltf"), doc)


# ---- lamp-room.glb and labels.glb: who gets the default sky ------------------

def lamp_room():
    """A room as Blender exports one lit by an emissive mesh: Y up, meshes
    with normals and UVs, the lamp's Principled emission written as
    emissiveFactor (its colour) and KHR_materials_emissive_strength (its
    strength, above 1), no punctual light, a camera outside the open front.
    Its emitter lights it, so it gets no default sky."""
    buf = Buffer()
    w, h, d = 4.0, 3.0, 4.0  # x from -2 to 2, y from 0 to 3, z from -2 to 2 (open towards +z)

    def wall(corners, material, name):
        a, b, c, e = corners
        ux = [b[i] - a[i] for i in range(3)]
        uy = [e[i] - a[i] for i in range(3)]
        n = [ux[1] * uy[2] - ux[2] * uy[1], ux[2] * uy[0] - ux[0] * uy[2], ux[0] * uy[1] - ux[1] * uy[0]]
        ln = math.sqrt(sum(x * x for x in n))
        return add_mesh(buf, ([a, b, c, e], [[x / ln for x in n]] * 4, [[0, 0], [1, 0], [1, 1], [0, 1]], [0, 1, 2, 0, 2, 3]),
                        material, name)
    x0, x1, z0, z1 = -w / 2, w / 2, -d / 2, d / 2
    meshes = [
        wall([[x0, 0, z1], [x1, 0, z1], [x1, 0, z0], [x0, 0, z0]], 0, "Floor"),
        wall([[x0, h, z0], [x1, h, z0], [x1, h, z1], [x0, h, z1]], 0, "Ceiling"),
        wall([[x0, 0, z0], [x1, 0, z0], [x1, h, z0], [x0, h, z0]], 0, "Back"),
        wall([[x0, 0, z1], [x0, 0, z0], [x0, h, z0], [x0, h, z1]], 1, "Left"),
        wall([[x1, 0, z0], [x1, 0, z1], [x1, h, z1], [x1, h, z0]], 2, "Right"),
        add_mesh(buf, cube(), 0, "Cube"),
        add_mesh(buf, quad(1.0, 0.8, 0.0, facing_down=True), 3, "Lamp"),
    ]
    nodes = [{"name": mesh["name"], "mesh": i} for i, mesh in enumerate(meshes)]
    nodes[5].update({"translation": [-0.6, 0.6, -0.4], "rotation": axis_angle([0, 1, 0], 25), "scale": [1.2, 1.2, 1.2]})
    nodes[6]["translation"] = [0.0, h - 0.01, 0.0]
    nodes.append({"name": "Camera", "camera": 0, "matrix": look_at_matrix([0.0, 1.5, 7.5], [0.0, 1.4, 0.0], [0, 1, 0])})
    white = {"baseColorFactor": [0.8, 0.8, 0.8, 1], "metallicFactor": 0.0, "roughnessFactor": 0.5}
    doc = {
        "asset": {"version": "2.0", "generator": "wavepath scripts/make-gltf-test-assets.py"},
        "extensionsUsed": ["KHR_materials_emissive_strength"],
        "scene": 0, "scenes": [{"name": "Scene", "nodes": list(range(len(nodes)))}], "nodes": nodes, "meshes": meshes,
        "materials": [
            {"name": "White", "pbrMetallicRoughness": white},
            {"name": "Red", "pbrMetallicRoughness": dict(white, baseColorFactor=[0.6, 0.08, 0.06, 1])},
            {"name": "Green", "pbrMetallicRoughness": dict(white, baseColorFactor=[0.1, 0.45, 0.12, 1])},
            {"name": "Emission", "emissiveFactor": [1.0, 0.95, 0.85],
             "extensions": {"KHR_materials_emissive_strength": {"emissiveStrength": 25.0}},
             "pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.8, 0.8, 1], "metallicFactor": 0.0, "roughnessFactor": 0.5}}],
        "cameras": [{"name": "Camera", "type": "perspective",
                     "perspective": {"yfov": 0.7, "aspectRatio": 1.333, "znear": 0.1, "zfar": 100}}],
        "accessors": buf.accessors, "bufferViews": buf.views, "buffers": [{"byteLength": len(buf.data)}],
    }
    with open(os.path.join(OUT, "lamp-room.glb"), "wb") as out:
        out.write(glb(doc, buf.data))


def label_text(x, y):
    """A label: black strokes on white, as ClearCoatTest's (white where no stroke)."""
    stroke = 2 <= y % 8 <= 5 and (x // 3) % 3 != 2 and 2 <= x < 46
    return (20, 20, 20) if stroke else (235, 235, 235)


def labels():
    """A model lit, as viewers light it, by their environment: three balls on
    a plinth, each with a label in front whose text is an emissive texture
    (emissiveFactor 1, no strength above it: no brighter than a white surface
    under the default sky). It gets the default sky."""
    buf = Buffer()
    pos, nrm, uv, _, idx = uv_sphere(rings=12, segments=24)
    ball = {"attributes": {"POSITION": buf.accessor("f", FLOAT, "VEC3", pos), "NORMAL": buf.accessor("f", FLOAT, "VEC3", nrm)},
            "indices": buf.accessor("H", USHORT, "SCALAR", idx), "material": 0}
    meshes = [{"name": "ball", "primitives": [ball]}, add_mesh(buf, cube(), 1, "plinth")]
    # A label stands upright facing +z: the quad in y turned about x.
    label = add_mesh(buf, quad(1.2, 0.3, 0.0), 2, "label")
    meshes.append(label)
    nodes = [{"name": "plinth", "mesh": 1, "translation": [0, -0.15, 0], "scale": [5.0, 0.3, 1.6]}]
    for i, x in enumerate((-1.6, 0.0, 1.6)):
        nodes.append({"name": "ball %d" % i, "mesh": 0, "translation": [x, 0.6, 0], "scale": [0.6, 0.6, 0.6]})
        nodes.append({"name": "label %d" % i, "mesh": 2, "translation": [x, 0.15, 0.75], "rotation": axis_angle([1, 0, 0], 90)})
    doc = {
        "asset": {"version": "2.0", "generator": "wavepath scripts/make-gltf-test-assets.py"},
        "scene": 0, "scenes": [{"nodes": list(range(len(nodes)))}], "nodes": nodes, "meshes": meshes,
        "materials": [
            {"name": "ball", "pbrMetallicRoughness": {"baseColorFactor": [0.2, 0.3, 0.8, 1], "metallicFactor": 0.0, "roughnessFactor": 0.3}},
            {"name": "plinth", "pbrMetallicRoughness": {"baseColorFactor": [0.5, 0.5, 0.5, 1], "metallicFactor": 0.0, "roughnessFactor": 0.9}},
            {"name": "label", "emissiveFactor": [1, 1, 1], "emissiveTexture": {"index": 0},
             "pbrMetallicRoughness": {"baseColorFactor": [0, 0, 0, 1], "metallicFactor": 0.0, "roughnessFactor": 0.9}}],
        "textures": [{"source": 0}],
        "images": [{"bufferView": buf.view(png(48, 16, label_text)), "mimeType": "image/png"}],
        "accessors": buf.accessors, "bufferViews": buf.views, "buffers": [{"byteLength": len(buf.data)}],
    }
    with open(os.path.join(OUT, "labels.glb"), "wb") as out:
        out.write(glb(doc, buf.data))


def main():
    os.makedirs(os.path.join(OUT, "external"), exist_ok=True)
    darts = box_room()
    write_json(os.path.join(OUT, "box-room.json"), darts)
    textured()
    external()
    surface()
    mirror_bumps()
    layers()
    translucent()
    instances()
    lamp_room()
    labels()


if __name__ == "__main__":
    main()
