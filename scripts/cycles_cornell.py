"""Renders a scene exported by `radiosity scenes --export` in Blender Cycles and writes a PFM
that `scripts/block_compare.py` compares with the path tracer's images (docs/pathtracing.md,
"Against Cycles"). A measuring aid, not run by the tests or the CI; Blender is not a project
dependency (Debian: apt-get install blender, 3.4.1 measured).

usage: blender -b --factory-startup -P scripts/cycles_cornell.py -- SCENE.obj OUT.pfm
           [--width 128] [--height 128] [--spp 64] [--seed 1] [--threads 1]
           [--filter box:1|blackman-harris:1.5|gaussian:W] [--pattern sobol|pmj]
           [--clamp-direct 0] [--clamp-indirect 10] [--bounces 12] [--diffuse-bounces 4]
           [--light-threshold 0.01] [--adaptive 0|1] [--caustics 0|1] [--denoise 0|1]
Without options each setting is Cycles' own default (Blender 3.4's factory settings), except
the size, the samples, the seed, the thread count and the denoiser (off).

The scene is built from the OBJ as the path tracer sees it: the same vertices (scene units), the
camera from the `# camera:` line, each material a diffuse BSDF of colour Kd, and Ke (emitted
radiance) as an emission shader on the front side only (the path tracer's emitters are
one-sided). A Cycles emission shader of strength 1 and colour C on a mesh shows radiance C when
seen directly (measured: the Cornell light's inner pixels read 11.09 in both renderers, the mean
of Ke plus its reflected light), so Ke is used as it is. The world is black. Measured with it:
docs/pathtracing.md, "Against Cycles". The PFM holds the linear radiance of the EXR Cycles writes (no view transform)."""
import math
import os
import struct
import sys

import bpy
from mathutils import Matrix, Vector


def options(argv):
    args = argv[argv.index("--") + 1:] if "--" in argv else []
    if len(args) < 2:
        sys.exit(__doc__)
    o = {"scene": args[0], "out": args[1]}
    rest = args[2:]
    for i in range(0, len(rest) - 1, 2):
        o[rest[i].lstrip("-").replace("-", "_")] = rest[i + 1]
    return o


def read_mtl(path):
    materials, current = {}, None
    for line in open(path):
        w = line.split()
        if not w:
            continue
        if w[0] == "newmtl":
            current = materials.setdefault(w[1], {"Kd": (0.8, 0.8, 0.8), "Ke": (0, 0, 0)})
        elif w[0] in ("Kd", "Ke") and current is not None:
            current[w[0]] = tuple(float(x) for x in w[1:4])
    return materials


def read_obj(path):
    vertices, faces, camera, mtllib, material = [], [], None, None, None
    for line in open(path):
        w = line.split()
        if not w:
            continue
        if line.startswith("# camera:"):
            c = line.split(":", 1)[1].split()
            camera = {
                "eye": tuple(map(float, c[1:4])),
                "look": tuple(map(float, c[5:8])),
                "up": tuple(map(float, c[9:12])),
                "fov": float(c[-2]),
            }
        elif w[0] == "mtllib":
            mtllib = w[1]
        elif w[0] == "usemtl":
            material = w[1]
        elif w[0] == "v":
            vertices.append(tuple(float(x) for x in w[1:4]))
        elif w[0] == "f":
            faces.append(([int(x.split("/")[0]) - 1 for x in w[1:]], material))
    materials = read_mtl(os.path.join(os.path.dirname(path), mtllib)) if mtllib else {}
    return vertices, faces, camera, materials


def make_material(name, kd, ke):
    m = bpy.data.materials.new(name)
    m.use_nodes = True
    nodes, links = m.node_tree.nodes, m.node_tree.links
    nodes.clear()
    output = nodes.new("ShaderNodeOutputMaterial")
    diffuse = nodes.new("ShaderNodeBsdfDiffuse")
    diffuse.inputs["Color"].default_value = (*kd, 1)
    diffuse.inputs["Roughness"].default_value = 0  # Lambert
    if max(ke) <= 0:
        links.new(diffuse.outputs["BSDF"], output.inputs["Surface"])
        return m
    # Front-side emission: strength 1 - backfacing, added to the diffuse part.
    emission = nodes.new("ShaderNodeEmission")
    emission.inputs["Color"].default_value = (*ke, 1)
    geometry = nodes.new("ShaderNodeNewGeometry")
    front = nodes.new("ShaderNodeMath")
    front.operation = "SUBTRACT"
    front.inputs[0].default_value = 1
    links.new(geometry.outputs["Backfacing"], front.inputs[1])
    links.new(front.outputs["Value"], emission.inputs["Strength"])
    add = nodes.new("ShaderNodeAddShader")
    links.new(diffuse.outputs["BSDF"], add.inputs[0])
    links.new(emission.outputs["Emission"], add.inputs[1])
    links.new(add.outputs["Shader"], output.inputs["Surface"])
    return m


def build_scene(o):
    for thing in list(bpy.data.objects):
        bpy.data.objects.remove(thing, do_unlink=True)
    vertices, faces, camera, materials = read_obj(o["scene"])
    mesh = bpy.data.meshes.new("scene")
    mesh.from_pydata(vertices, [], [f for f, _ in faces])
    names = sorted({m for _, m in faces})
    for name in names:
        mtl = materials.get(name, {"Kd": (0.8, 0.8, 0.8), "Ke": (0, 0, 0)})
        mesh.materials.append(make_material(name, mtl["Kd"], mtl["Ke"]))
    for polygon, (_, name) in zip(mesh.polygons, faces):
        polygon.material_index = names.index(name)
    mesh.update()
    obj = bpy.data.objects.new("scene", mesh)
    bpy.context.scene.collection.objects.link(obj)

    # Camera: looks down its local -Z with +Y up.
    eye, look, up = Vector(camera["eye"]), Vector(camera["look"]), Vector(camera["up"])
    back = (eye - look).normalized()
    right = up.cross(back).normalized()
    true_up = back.cross(right)
    cam_data = bpy.data.cameras.new("camera")
    cam_data.sensor_fit = "VERTICAL"
    cam_data.angle_y = math.radians(camera["fov"])
    cam_data.clip_start = 1e-3 * (eye - look).length
    cam_data.clip_end = 1e3 * (eye - look).length
    cam = bpy.data.objects.new("camera", cam_data)
    cam.matrix_world = Matrix((
        (right.x, true_up.x, back.x, eye.x),
        (right.y, true_up.y, back.y, eye.y),
        (right.z, true_up.z, back.z, eye.z),
        (0, 0, 0, 1)))
    bpy.context.scene.collection.objects.link(cam)
    bpy.context.scene.camera = cam

    world = bpy.context.scene.world or bpy.data.worlds.new("world")
    bpy.context.scene.world = world
    world.use_nodes = True
    world.node_tree.nodes["Background"].inputs["Color"].default_value = (0, 0, 0, 1)
    world.node_tree.nodes["Background"].inputs["Strength"].default_value = 0


def settings(o):
    scene = bpy.context.scene
    r, c = scene.render, scene.cycles
    r.engine = "CYCLES"
    c.device = "CPU"
    r.resolution_x = int(o.get("width", 128))
    r.resolution_y = int(o.get("height", 128))
    r.resolution_percentage = 100
    r.threads_mode = "FIXED"
    r.threads = int(o.get("threads", 1))
    c.samples = int(o.get("spp", 64))
    c.seed = int(o.get("seed", 1))
    c.use_denoising = o.get("denoise", "0") == "1"
    if c.use_denoising:
        c.denoiser = "OPENIMAGEDENOISE"
    c.use_adaptive_sampling = o.get("adaptive", "1") == "1"
    if "filter" in o:
        kind, width = o["filter"].split(":")
        c.pixel_filter_type = {"box": "BOX", "blackman-harris": "BLACKMAN_HARRIS",
                               "gaussian": "GAUSSIAN"}[kind]
        c.filter_width = float(width)
    if "pattern" in o:
        c.sampling_pattern = {"sobol": "SOBOL", "pmj": "PROGRESSIVE_MULTI_JITTER"}[o["pattern"]]
    if "clamp_direct" in o:
        c.sample_clamp_direct = float(o["clamp_direct"])
    if "clamp_indirect" in o:
        c.sample_clamp_indirect = float(o["clamp_indirect"])
    if "bounces" in o:
        c.max_bounces = int(o["bounces"])
    if "diffuse_bounces" in o:
        c.diffuse_bounces = int(o["diffuse_bounces"])
    if "light_threshold" in o:
        c.light_sampling_threshold = float(o["light_threshold"])
    if "caustics" in o:
        c.caustics_reflective = c.caustics_refractive = o["caustics"] == "1"
    scene.view_settings.view_transform = "Standard"
    scene.view_settings.look = "None"
    scene.view_settings.exposure = 0
    scene.view_settings.gamma = 1
    r.image_settings.file_format = "OPEN_EXR"
    r.image_settings.color_depth = "32"
    r.image_settings.exr_codec = "NONE"
    print("cycles settings: samples %d seed %d filter %s %.2f pattern %s clamp %g/%g bounces %d "
          "(diffuse %d) light threshold %g adaptive %s (threshold %g, min %d) denoise %s" % (
              c.samples, c.seed, c.pixel_filter_type, c.filter_width, c.sampling_pattern,
              c.sample_clamp_direct, c.sample_clamp_indirect, c.max_bounces, c.diffuse_bounces,
              c.light_sampling_threshold, c.use_adaptive_sampling, c.adaptive_threshold,
              c.adaptive_min_samples, c.use_denoising))


def write_pfm(exr, out):
    image = bpy.data.images.load(exr)
    image.colorspace_settings.name = "Non-Color"
    w, h = image.size
    pixels = image.pixels[:]  # RGBA, rows bottom to top, like PFM
    rgb = [pixels[i] for i in range(len(pixels)) if i % 4 != 3]
    with open(out, "wb") as f:
        f.write(b"PF\n%d %d\n-1.0\n" % (w, h))
        f.write(struct.pack("<%df" % len(rgb), *rgb))


def main():
    o = options(sys.argv)
    build_scene(o)
    settings(o)
    exr = o["out"] + ".exr"
    bpy.context.scene.render.filepath = exr
    bpy.ops.render.render(write_still=True)
    write_pfm(exr, o["out"])
    os.remove(exr)


main()
