# Renders a Cornell-box OBJ (with its MTL) in Blender's Cycles on the CPU at
# the settings of wavepath's render benchmark, as the "mature CPU production
# renderer" baseline: diffuse materials from Kd, emitters from Ke, the camera
# of scenes/cornell-box.json, WxH pixels, SPP samples, at most BOUNCES bounces,
# no denoising, no adaptive sampling, THREADS threads. Prints one line:
#   cycles: <seconds> s, <Msamples/s> Msamples/s
# Run by scripts/bench-render.sh as
#   blender -b --factory-startup --python scripts/cycles_baseline.py -- OBJ OUT.png W H SPP BOUNCES THREADS
import sys
import time

import bpy


def main():
    args = sys.argv[sys.argv.index("--") + 1:]
    obj, out, width, height, spp, bounces, threads = args[0], args[1], *map(int, args[2:7])
    bpy.ops.wm.read_factory_settings(use_empty=True)
    # OBJ is Y-up, Blender Z-up: the importer maps (x, y, z) to (x, -z, y).
    bpy.ops.wm.obj_import(filepath=obj, forward_axis="NEGATIVE_Z", up_axis="Y")
    for mat in bpy.data.materials:
        principled = mat.node_tree.nodes.get("Principled BSDF")
        kd = principled.inputs["Base Color"].default_value[:3] if principled else (0.8, 0.8, 0.8)
        ke = principled.inputs["Emission"].default_value[:3] if principled else (0.0, 0.0, 0.0)
        mat.node_tree.nodes.clear()
        output = mat.node_tree.nodes.new("ShaderNodeOutputMaterial")
        if max(ke) > 0.0:
            # The importer clamps Ke to colours <= 1: take the MTL's value again.
            ke = emission_of(obj, mat.name) or ke
            shader = mat.node_tree.nodes.new("ShaderNodeEmission")
            peak = max(ke)
            shader.inputs["Color"].default_value = (ke[0] / peak, ke[1] / peak, ke[2] / peak, 1.0)
            shader.inputs["Strength"].default_value = peak
        else:
            shader = mat.node_tree.nodes.new("ShaderNodeBsdfDiffuse")
            shader.inputs["Color"].default_value = (*kd, 1.0)
        mat.node_tree.links.new(shader.outputs[0], output.inputs["Surface"])

    # The camera of scenes/cornell-box.json: from (278, 273, -800) towards
    # +Z with +Y up, vertical fov 39.3 degrees; in Blender's axes from
    # (278, 800, 273) towards -Y with +Z up.
    cam_data = bpy.data.cameras.new("camera")
    cam_data.sensor_fit = "VERTICAL"
    cam_data.angle_y = 39.3 * 3.141592653589793 / 180.0
    cam_data.clip_start = 0.1  # the box is hundreds of units across: no clipping
    cam_data.clip_end = 1.0e6
    cam = bpy.data.objects.new("camera", cam_data)
    bpy.context.scene.collection.objects.link(cam)
    cam.location = (278.0, 800.0, 273.0)
    cam.rotation_euler = (3.141592653589793 / 2.0, 0.0, 3.141592653589793)
    scene = bpy.context.scene
    scene.camera = cam
    world = bpy.data.worlds.new("black")
    world.color = (0.0, 0.0, 0.0)
    scene.world = world

    scene.render.engine = "CYCLES"
    scene.cycles.device = "CPU"
    scene.cycles.samples = spp
    scene.cycles.use_adaptive_sampling = False
    scene.cycles.use_denoising = False
    scene.cycles.max_bounces = bounces
    scene.cycles.diffuse_bounces = bounces
    scene.cycles.glossy_bounces = bounces
    scene.cycles.transmission_bounces = bounces
    scene.cycles.caustics_reflective = True
    scene.cycles.caustics_refractive = True
    scene.cycles.sample_clamp_direct = 0.0
    scene.cycles.sample_clamp_indirect = 0.0
    scene.render.threads_mode = "FIXED"
    scene.render.threads = threads
    scene.render.resolution_x = width
    scene.render.resolution_y = height
    scene.render.resolution_percentage = 100
    scene.render.filepath = out
    scene.view_settings.view_transform = "Standard"
    start = time.time()
    bpy.ops.render.render(write_still=True)
    seconds = time.time() - start
    print(f"cycles: {seconds:.3f} s, {width * height * spp / seconds * 1e-6:.4f} Msamples/s", flush=True)


def emission_of(obj_path, material):
    """Ke of `material` in the MTL files the OBJ names, or None."""
    import os
    mtls = []
    with open(obj_path) as f:
        for line in f:
            if line.startswith("mtllib"):
                mtls.append(os.path.join(os.path.dirname(obj_path), line.split(None, 1)[1].strip()))
    for mtl in mtls:
        current = None
        with open(mtl) as f:
            for line in f:
                parts = line.split()
                if not parts:
                    continue
                if parts[0] == "newmtl":
                    current = parts[1]
                elif parts[0] == "Ke" and current == material:
                    return tuple(float(v) for v in parts[1:4])
    return None


main()
