# Renders a glTF 2.0 file (.glb or .gltf) in Blender's Cycles on the CPU, as
# Blender shows a file it imports, to measure wavepath's glTF defaults against:
#   blender -b --factory-startup --python scripts/cycles_gltf.py -- FILE OUT.exr W H SPP BOUNCES THREADS [--one-sided] [--diffuse]
# (Blender 3.4 and later; on Debian 12 `apt-get install --no-install-recommends blender`).
# Blender's own glTF importer reads the file with its defaults (materials to
# the Principled BSDF, emissiveFactor x KHR_materials_emissive_strength to
# its Emission Strength, punctual lights in the importer's own units), and
# the file's first camera (by object name) frames it; a file without a camera
# is skipped (exit 3): Blender would have nothing to render it from, and any
# camera made up here would be neither Blender's nor wavepath's.
# The world is black: the importer adds neither a world nor a light, so what
# Blender shows is the file lit by its own emitters and lights alone.
# Cycles: WxH pixels, SPP samples, at most BOUNCES bounces of every kind, no
# denoising, no adaptive sampling, no clamping, no glossy blur (Cycles'
# defaults clamp indirect light at 10 and blur glossy paths, both biased),
# a one-pixel box filter (wavepath's pixels are boxes), the Standard view
# transform; OUT is a linear 32-bit float EXR that `wavepath compare
# --reference OUT.exr IMAGE.exr` reads. Prints one line:
#   cycles: <seconds> s, camera <name>
# Two switches take Blender's own conventions out, to tell where a difference
# comes from (docs/scene-format.md, the default sky): --one-sided makes
# emission leave the front of a face only, as in glTF and wavepath (Cycles
# emits from both); --diffuse replaces every Principled BSDF by a Lambertian
# Diffuse BSDF of its base colour (compare with wavepath rendering the file
# with KHR_materials_specular's specularFactor 0, which leaves glTF's BRDF
# Lambertian).
import sys
import time

import bpy
import numpy

# Debian 12's Blender 3.4 importer calls numpy.bool, which its numpy (1.24)
# no longer has: the builtin it aliased.
if "bool" not in numpy.__dict__:
    numpy.bool = bool


def main():
    args = sys.argv[sys.argv.index("--") + 1:]
    switches = {a for a in args if a.startswith("--")}
    args = [a for a in args if not a.startswith("--")]
    path, out, width, height, spp, bounces, threads = args[0], args[1], *map(int, args[2:7])
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.ops.import_scene.gltf(filepath=path)
    scene = bpy.context.scene
    cameras = sorted((o for o in scene.objects if o.type == "CAMERA"), key=lambda o: o.name)
    if not cameras:
        print(f"cycles: {path} has no camera: skipped", flush=True)
        sys.exit(3)
    scene.camera = cameras[0]
    for mat in bpy.data.materials:
        if mat.use_nodes:
            if "--diffuse" in switches:
                diffuse(mat.node_tree)
            if "--one-sided" in switches:
                one_sided(mat.node_tree)
    world = bpy.data.worlds.new("black")
    world.color = (0.0, 0.0, 0.0)
    world.use_nodes = False
    scene.world = world

    scene.render.engine = "CYCLES"
    cycles = scene.cycles
    cycles.device = "CPU"
    cycles.samples = spp
    cycles.use_adaptive_sampling = False
    cycles.use_denoising = False
    cycles.max_bounces = bounces
    cycles.diffuse_bounces = bounces
    cycles.glossy_bounces = bounces
    cycles.transmission_bounces = bounces
    cycles.volume_bounces = bounces
    cycles.transparent_max_bounces = bounces
    cycles.caustics_reflective = True
    cycles.caustics_refractive = True
    cycles.blur_glossy = 0.0
    cycles.sample_clamp_direct = 0.0
    cycles.sample_clamp_indirect = 0.0
    cycles.pixel_filter_type = "BOX"
    cycles.filter_width = 1.0
    scene.render.threads_mode = "FIXED"
    scene.render.threads = threads
    scene.render.resolution_x = width
    scene.render.resolution_y = height
    scene.render.resolution_percentage = 100
    scene.render.film_transparent = False
    scene.view_settings.view_transform = "Standard"
    scene.view_settings.look = "None"
    scene.view_settings.exposure = 0.0
    scene.view_settings.gamma = 1.0
    settings = scene.render.image_settings
    settings.file_format = "OPEN_EXR"
    settings.color_mode = "RGB"
    settings.color_depth = "32"
    settings.exr_codec = "NONE"
    scene.render.filepath = out
    scene.render.use_file_extension = False
    start = time.time()
    bpy.ops.render.render(write_still=True)
    print(f"cycles: {time.time() - start:.3f} s, camera {scene.camera.name}", flush=True)


def principled(tree):
    return next((n for n in tree.nodes if n.type == "BSDF_PRINCIPLED"), None)


def diffuse(tree):
    """The Principled BSDF's reflection becomes a Lambertian one of its base
    colour (linked or not); its emission inputs stay where they are."""
    bsdf = principled(tree)
    if bsdf is None:
        return
    lambert = tree.nodes.new("ShaderNodeBsdfDiffuse")
    color = bsdf.inputs["Base Color"]
    if color.is_linked:
        tree.links.new(color.links[0].from_socket, lambert.inputs["Color"])
    else:
        lambert.inputs["Color"].default_value = color.default_value[:]
    # The Principled node, black and smooth, keeps only its emission.
    for name in ("Base Color", "Specular", "Metallic", "Sheen", "Clearcoat", "Transmission"):
        socket = bsdf.inputs[name]
        for link in list(socket.links):
            tree.links.remove(link)
        socket.default_value = (0.0, 0.0, 0.0, 1.0) if name == "Base Color" else 0.0
    add = tree.nodes.new("ShaderNodeAddShader")
    output = next(n for n in tree.nodes if n.type == "OUTPUT_MATERIAL")
    tree.links.new(lambert.outputs[0], add.inputs[0])
    tree.links.new(bsdf.outputs[0], add.inputs[1])
    tree.links.new(add.outputs[0], output.inputs["Surface"])


def one_sided(tree):
    """Emission Strength times (1 - Backfacing)."""
    bsdf = principled(tree)
    if bsdf is None:
        return
    strength = bsdf.inputs["Emission Strength"]
    facing = tree.nodes.new("ShaderNodeMath")
    facing.operation = "SUBTRACT"
    facing.inputs[0].default_value = 1.0
    tree.links.new(tree.nodes.new("ShaderNodeNewGeometry").outputs["Backfacing"], facing.inputs[1])
    scaled = tree.nodes.new("ShaderNodeMath")
    scaled.operation = "MULTIPLY"
    if strength.is_linked:
        tree.links.new(strength.links[0].from_socket, scaled.inputs[1])
    else:
        scaled.inputs[1].default_value = strength.default_value
    tree.links.new(facing.outputs[0], scaled.inputs[0])
    tree.links.new(scaled.outputs[0], strength)


main()
