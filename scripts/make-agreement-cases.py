#!/usr/bin/env python3
"""Writes the generated cases of the GPU-against-CPU agreement check
(scripts/check-agreement.sh) into OUTDIR: small scenes, each exercising
what users' files do and our own scenes did not, one light kind at a time.

    make-agreement-cases.py OUTDIR

Why one light kind per scene: the kernels compile only the kinds a scene
uses, so a record field whose loading depends on another kind being present
is wrong only in scenes without that kind (CS184's CBempty.dae, lit by a
lone <point>, lost its lights' no-falloff flag that way). Each scene here
has exactly one kind of light, and the CS184 scenes are rendered both under
the course's estimator and with --consistent-lights.

The cases:
- CS184 COLLADA (`cs184-*.dae`, the course's dialect: Z up, <matrix>
  nodes, <polylist> quads, technique_common and CGL lights):
  a <point> with attenuation elements in the plane of an emissive lamp
  mesh (as CBempty.dae has it); point lights at every distance from a wall
  (on it, 1e-4, 1e-2 and 0.5 away); a lone CGL area light in the plane of
  its lamp mesh (the course's Cornell files); a lone directional light; a
  lone ambient (hemisphere) light; an emissive mesh alone.
- darts JSON (`darts-*.json`): a lone point light, a lone spot light, a
  lone directional light, and a point light on a wall.

Standard library only.
"""
import json
import os
import sys

# ---- CS184 COLLADA ------------------------------------------------------------

# The room: Z up as Blender writes it; floor z = 0, ceiling z = 2, walls at
# x = +-1 and y = 1 (the back), open towards -y where the camera is.
ROOM = {
    "floor": ([(-1, -1, 0), (1, -1, 0), (1, 1, 0), (-1, 1, 0)], "white"),
    "ceiling": ([(-1, -1, 2), (-1, 1, 2), (1, 1, 2), (1, -1, 2)], "white"),
    "back": ([(-1, 1, 0), (1, 1, 0), (1, 1, 2), (-1, 1, 2)], "white"),
    "left": ([(-1, -1, 0), (-1, 1, 0), (-1, 1, 2), (-1, -1, 2)], "red"),
    "right": ([(1, -1, 0), (1, -1, 2), (1, 1, 2), (1, 1, 0)], "green"),
    "block": ([(-0.5, 0.2, 0.01), (0.1, 0.2, 0.01), (0.1, 0.2, 0.9), (-0.5, 0.2, 0.9)], "white"),
}
# Open scenes (lit from the sky) drop the ceiling and the walls but the back.
OPEN = {k: v for k, v in ROOM.items() if k in ("floor", "back", "block")}
# The lamp mesh of the course's Cornell files: a panel just under the ceiling,
# facing down, exported as Blender does: the mesh in Y-up coordinates under a
# node matrix that turns it to Z up with rounding terms of 1e-7 (CBempty.dae),
# so that its plane and a light placed in it meet only up to rounding.
LAMP = ([(0.3, 1.99, -0.2), (0.3, 1.99, 0.2), (-0.3, 1.99, 0.2), (-0.3, 1.99, -0.2)], "lamp")
BLENDER_Y_TO_Z = ("-1 2.69452e-14 1.50996e-7 -2.62268e-8 1.50996e-7 1.62921e-7 1 0.004315853 "
                  "2.34488e-15 1 -1.62921e-7 0 0 0 0 1")

DIFFUSE = {"white": (0.75, 0.75, 0.72), "red": (0.63, 0.07, 0.05), "green": (0.12, 0.45, 0.15)}


def fmt(values):
    return " ".join(repr(float(v)) for v in values)


def matrix(t=(0, 0, 0), s=(1, 1, 1)):
    """A row-major <matrix>: scale, then translate."""
    return fmt([s[0], 0, 0, t[0], 0, s[1], 0, t[1], 0, 0, s[2], t[2], 0, 0, 0, 1])


def dae(comment, quads, lights):
    """A CS184-dialect COLLADA file. quads: name -> (4 corners, material);
    lights: (id, technique xml, profile "common" or "CGL", node matrix)."""
    effects = []
    for name, rgb in DIFFUSE.items():
        effects.append(f'<effect id="{name}-fx"><profile_COMMON><technique sid="common"><phong>'
                       f'<diffuse><color>{fmt(rgb)} 1</color></diffuse></phong></technique></profile_COMMON></effect>')
    effects.append('<effect id="lamp-fx"><profile_COMMON><technique sid="common"><phong>'
                   '<emission><color>0 0 0 1</color></emission><diffuse><color>0.8 0.8 0.8 1</color></diffuse>'
                   '</phong></technique></profile_COMMON><extra><technique profile="CGL">'
                   '<emission><radiance>8 8 8</radiance></emission></technique></extra></effect>')
    materials = [f'<material id="{n}"><instance_effect url="#{n}-fx"/></material>' for n in list(DIFFUSE) + ["lamp"]]
    geometries, nodes = [], []
    for name, (corners, material) in quads.items():
        node_matrix = BLENDER_Y_TO_Z if name == "lamp" else matrix()
        flat = [c for p in corners for c in p]
        geometries.append(
            f'<geometry id="{name}-mesh"><mesh>'
            f'<source id="{name}-pos"><float_array id="{name}-pos-array" count="12">{fmt(flat)}</float_array>'
            f'<technique_common><accessor source="#{name}-pos-array" count="4" stride="3"/></technique_common></source>'
            f'<vertices id="{name}-vtx"><input semantic="POSITION" source="#{name}-pos"/></vertices>'
            f'<polylist material="{name}-symbol" count="1"><input semantic="VERTEX" source="#{name}-vtx" offset="0"/>'
            f'<vcount>4</vcount><p>0 1 2 3</p></polylist></mesh></geometry>')
        nodes.append(f'<node id="{name}-node"><matrix sid="transform">{node_matrix}</matrix>'
                     f'<instance_geometry url="#{name}-mesh"><bind_material><technique_common>'
                     f'<instance_material symbol="{name}-symbol" target="#{material}"/>'
                     f'</technique_common></bind_material></instance_geometry></node>')
    light_xml = []
    for lid, body, profile, m in lights:
        technique = (f"<technique_common>{body}</technique_common>" if profile == "common" else
                     f'<extra><technique profile="CGL">{body}</technique></extra>')
        light_xml.append(f'<light id="{lid}">{technique}</light>')
        nodes.append(f'<node id="{lid}-node"><matrix sid="transform">{m}</matrix><instance_light url="#{lid}"/></node>')
    # The course's orbit camera looks at the objects' centre along m (0, 0, -1); the wide
    # field makes the central 160x120 of its 800x600 frame (what -r 160 120 renders) hold the room.
    nodes.append(f'<node id="view-node"><matrix sid="transform">{matrix((0, -0.7, 1.25))}</matrix>'
                 '<instance_camera url="#view"/></node>')
    return f"""<?xml version="1.0" encoding="utf-8"?>
<!-- wavepath agreement case in the dialect of Berkeley CS184's COLLADA files
     (scripts/make-agreement-cases.py): {comment} -->
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
  <asset><up_axis>Z_UP</up_axis></asset>
  <library_cameras><camera id="view"><optics><technique_common><perspective><xfov>125</xfov><yfov>110</yfov>
  </perspective></technique_common></optics></camera></library_cameras>
  <library_lights>{''.join(light_xml)}</library_lights>
  <library_effects>{''.join(effects)}</library_effects>
  <library_materials>{''.join(materials)}</library_materials>
  <library_geometries>{''.join(geometries)}</library_geometries>
  <library_visual_scenes><visual_scene id="Scene">{''.join(nodes)}</visual_scene></library_visual_scenes>
  <scene><instance_visual_scene url="#Scene"/></scene>
</COLLADA>
"""


def point_light(lid, position, color=(2, 2, 2), m=None):
    body = (f"<point><color>{fmt(color)}</color><constant_attenuation>1</constant_attenuation>"
            "<linear_attenuation>0</linear_attenuation><quadratic_attenuation>0.0016</quadratic_attenuation></point>")
    return (lid, body, "common", m or matrix(position))


# Lights in the lamp's plane, placed by node matrices as Blender writes them (CBempty.dae's Area node).
IN_LAMP_PLANE = "-0.6 -1.20797e-7 0 -2.62268e-8 9.05975e-8 -0.4 0 0.004315853 0 0 1 1.99 0 0 0 1"


def cs184_cases():
    with_lamp = dict(ROOM, lamp=LAMP)
    return {
        "cs184-point-in-lamp-plane.dae": dae(
            "a technique_common point light with attenuation elements, in the plane of the emissive lamp mesh "
            "(CBempty.dae's arrangement)", with_lamp, [point_light("bulb", None, m=IN_LAMP_PLANE)]),
        "cs184-point-distances.dae": dae(
            "point lights at every distance from a wall: on it, 1e-4, 1e-2 and 0.5 away", ROOM,
            [point_light("on-wall", (0.5, 1.0, 1.2), (0.5, 0.5, 0.5)),
             point_light("near", (-0.5, 1 - 1e-4, 1.2), (0.5, 0.5, 0.5)),
             point_light("close", (0, 1 - 1e-2, 0.4), (0.5, 0.5, 0.5)),
             point_light("far", (0, 0.3, 1.5), (1, 1, 1))]),
        "cs184-area-in-lamp-plane.dae": dae(
            "a lone CGL area light in the plane of its lamp mesh (the course's Cornell files)", with_lamp,
            [("panel", "<area><color>6 6 6</color></area>", "CGL", IN_LAMP_PLANE)]),
        "cs184-directional.dae": dae(
            "a lone directional light over an open scene", OPEN,
            [("sun", "<directional><color>1 0.95 0.9</color></directional>", "common", matrix((0.4, 0.3, 1)))]),
        "cs184-ambient.dae": dae(
            "a lone ambient (hemisphere) light over an open scene", OPEN,
            [("sky", "<ambient><color>0.6 0.7 0.8</color></ambient>", "common", matrix())]),
        "cs184-emissive-mesh.dae": dae("an emissive mesh and no light", with_lamp, []),
    }


# ---- darts JSON -----------------------------------------------------------------


def darts(lights):
    return {
        "camera": {"transform": {"from": [0, 1.6, 4.5], "at": [0, 0.8, 0], "up": [0, 1, 0]}, "vfov": 45,
                   "resolution": [64, 48]},
        "sampler": {"samples": 64},
        "background": [0.0, 0.0, 0.0],
        "integrator": {"type": "path tracer mis", "max bounces": 4},
        "materials": [
            {"type": "lambertian", "name": "white", "albedo": 0.7},
            {"type": "lambertian", "name": "red", "albedo": [0.6, 0.1, 0.1]},
            {"type": "phong", "name": "glossy", "albedo": [0.6, 0.6, 0.5], "exponent": 30},
        ],
        "surfaces": [
            {"type": "quad", "size": [4, 4], "material": "white", "transform": {"rotate": [-90, 1, 0, 0]}},
            {"type": "quad", "size": [4, 3], "material": "red", "transform": {"translate": [0, 1.5, -1.5]}},
            {"type": "sphere", "radius": 0.5, "material": "glossy", "transform": {"translate": [0.4, 0.5, 0]}},
        ] + lights,
    }


def darts_cases():
    return {
        "darts-point.json": darts([  # a lone point light
            {"type": "point_light", "position": [-0.5, 2, 1], "intensity": [4, 4, 4]}]),
        "darts-point-on-wall.json": darts([  # on the back wall, and 1e-4 in front of it
            {"type": "point_light", "position": [-1, 1.2, -1.5], "intensity": [2, 2, 2]},
            {"type": "point_light", "position": [1, 1.2, -1.5 + 1e-4], "intensity": [2, 2, 2]}]),
        "darts-spot.json": darts([  # a lone spot light
            {"type": "spot_light", "position": [0, 2.5, 1.5], "direction": [0, -1, -0.6], "intensity": [10, 9, 8],
             "inner_angle": 15, "outer_angle": 35}]),
        "darts-directional.json": darts([  # a lone directional light
            {"type": "directional_light", "direction": [0.4, -1, -0.5], "irradiance": [2, 2, 2]}]),
    }


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__.strip().splitlines()[0] + "\nusage: make-agreement-cases.py OUTDIR")
    out = sys.argv[1]
    os.makedirs(out, exist_ok=True)
    for name, text in cs184_cases().items():
        with open(os.path.join(out, name), "w") as f:
            f.write(text)
    for name, scene in darts_cases().items():
        with open(os.path.join(out, name), "w") as f:
            json.dump(scene, f, indent=1)
            f.write("\n")


if __name__ == "__main__":
    main()
