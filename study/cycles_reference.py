"""Renders an hrpp scene export with Blender's Cycles, set up to compute the integral hrpp render
computes: the same triangles, vertex normals, camera and image size, Lambertian materials
(Diffuse BSDF, roughness 0) with emission added (two-sided, or from the front alone), the same constant environment (the
scene's, or for a scene without light hrpp's default environment and sun), paths of the same
length (Cycles' max bounces = hrpp's --max-depth - 1: 0 means direct light only in both), a box pixel
filter one pixel wide, no clamping, no glossy blur, no light threshold, no denoising, no
adaptive sampling; the EXR holds linear radiance.

Run by Blender (Debian's blender package), not by python3:
  blender --background --factory-startup --python study/cycles_reference.py -- \\
      --scene SCENE.json --out ref.exr [--size 64x64] [--spp 1024] [--max-depth 8] [--seed 0] \\
      [--camera 0] [--default-environment 0.5] [--default-sun 1.5]
SCENE.json comes from `hrpp scene SCENE --export-json SCENE.json`. A mirrored camera (pbrt's
left-handed camera space) is rendered unmirrored: its image is this one flipped left to right,
which study/cycles.py does. Scenes with metal, glass,
textures or point, spot and directional lights are refused: their models differ between the two
renderers. study/cycles.py runs this for you.
"""
import argparse
import json
import sys

import bpy
import mathutils


def fail(msg):
    print(f"cycles_reference: {msg}", file=sys.stderr)
    sys.exit(1)


def parse_args():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    ap = argparse.ArgumentParser(prog="cycles_reference.py")
    ap.add_argument("--scene", required=True)
    ap.add_argument("--out", required=True)
    ap.add_argument("--size", default="64x64")
    ap.add_argument("--spp", type=int, default=1024)
    ap.add_argument("--max-depth", type=int, default=8)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--camera", type=int, default=0)
    ap.add_argument("--default-environment", type=float, default=0.5)
    ap.add_argument("--default-sun", type=float, default=1.5)
    return ap.parse_args(argv)


def check_supported(s):
    for m in s["materials"]:
        textured = (m["textured"] or m.get("metallic_roughness_textured")
                    or m.get("emissive_textured"))
        if (m["metallic"] > 0.0 or m["transmission"] > 0.5 or textured
                or m.get("specular", 0.0) > 0.0):
            fail(f"material '{m['name']}': metal, glass, a specular layer or a texture (only "
                 "Lambertian materials with emission compare like for like)")
    for light in s["lights"]:
        if light["type"] not in ("area", "environment"):
            fail(f"a {light['type']} light (only emissive triangles and environments)")


def make_material(m):
    mat = bpy.data.materials.new(m["name"] or "material")
    mat.use_nodes = True
    nt = mat.node_tree
    nt.nodes.clear()
    out = nt.nodes.new("ShaderNodeOutputMaterial")
    diffuse = nt.nodes.new("ShaderNodeBsdfDiffuse")
    diffuse.inputs["Color"].default_value = (*m["base_color"], 1.0)
    diffuse.inputs["Roughness"].default_value = 0.0
    e = m["emission"]
    if max(e) > 0.0:
        strength = max(e)
        emission = nt.nodes.new("ShaderNodeEmission")
        emission.inputs["Color"].default_value = (e[0] / strength, e[1] / strength,
                                                  e[2] / strength, 1.0)
        emission.inputs["Strength"].default_value = strength
        add = nt.nodes.new("ShaderNodeAddShader")
        nt.links.new(diffuse.outputs[0], add.inputs[0])
        if m.get("two_sided_emission", True):
            nt.links.new(emission.outputs[0], add.inputs[1])
        else:  # only the front (the side the triangle's winding faces) emits
            geometry = nt.nodes.new("ShaderNodeNewGeometry")
            mix = nt.nodes.new("ShaderNodeMixShader")
            nt.links.new(geometry.outputs["Backfacing"], mix.inputs["Fac"])
            nt.links.new(emission.outputs[0], mix.inputs[1])
            nt.links.new(mix.outputs[0], add.inputs[1])
        nt.links.new(add.outputs[0], out.inputs["Surface"])
    else:
        nt.links.new(diffuse.outputs[0], out.inputs["Surface"])
    return mat


def unique_triangles(p):
    """Triangle ids, less exact duplicates (the same three vertices): a ray leaving one of two
    coincident triangles hits the other in Cycles (it only skips the triangle it left), which
    would shade the surface black; in hrpp the offset origin clears both, so a duplicate changes
    nothing there and dropping it computes the same integral."""
    seen, keep = set(), []
    for t in range(len(p) // 9):
        key = tuple(sorted(tuple(p[9 * t + 3 * k:9 * t + 3 * k + 3]) for k in range(3)))
        if key not in seen:
            seen.add(key)
            keep.append(t)
    if len(keep) < len(p) // 9:
        print(f"cycles_reference: dropped {len(p) // 9 - len(keep)} duplicate triangles")
    return keep


def make_mesh(s):
    p = s["positions"]
    tris = unique_triangles(p)
    verts = [tuple(p[9 * t + 3 * k:9 * t + 3 * k + 3]) for t in tris for k in range(3)]
    faces = [(3 * i, 3 * i + 1, 3 * i + 2) for i in range(len(tris))]
    mesh = bpy.data.meshes.new("hrpp")
    mesh.from_pydata(verts, [], faces)
    for m in s["materials"]:
        mesh.materials.append(make_material(m))
    mesh.polygons.foreach_set("material_index", [s["material_of"][t] for t in tris])
    normals = s.get("normals", [])
    if any(normals):
        # hrpp interpolates vertex normals where a triangle has them (all zero: flat).
        loops = []
        for t in tris:
            tri = normals[9 * t:9 * t + 9]
            if any(tri):
                loops += [tuple(tri[0:3]), tuple(tri[3:6]), tuple(tri[6:9])]
            else:
                loops += [(0.0, 0.0, 0.0)] * 3  # Blender: keep the face normal
        if hasattr(mesh, "use_auto_smooth"):  # Blender 3.x: custom normals need auto smooth
            mesh.use_auto_smooth = True
        else:  # Blender 4.1+: smooth faces take custom normals, flat ones their face normal
            mesh.polygons.foreach_set("use_smooth", [any(normals[9 * t:9 * t + 9]) for t in tris])
        mesh.normals_split_custom_set(loops)
    mesh.update()
    obj = bpy.data.objects.new("hrpp", mesh)
    bpy.context.scene.collection.objects.link(obj)


def make_camera(c, aspect):
    data = bpy.data.cameras.new("camera")
    data.sensor_fit = "VERTICAL"
    data.angle_y = c["yfov"]
    data.clip_start = 1e-4
    data.clip_end = 1e9
    cam = bpy.data.objects.new("camera", data)
    f = mathutils.Vector(c["forward"]).normalized()
    r = f.cross(mathutils.Vector(c["up"])).normalized()
    u = r.cross(f)
    pos = c["position"]
    cam.matrix_world = mathutils.Matrix(((r.x, u.x, -f.x, pos[0]), (r.y, u.y, -f.y, pos[1]),
                                         (r.z, u.z, -f.z, pos[2]), (0.0, 0.0, 0.0, 1.0)))
    bpy.context.scene.collection.objects.link(cam)
    bpy.context.scene.camera = cam


# hrpp's DefaultLighting::kSunDirection (host/render/render_config.h): the way its light travels.
SUN_DIRECTION = (-0.4, -1.0, -0.6)


def make_sun(irradiance):
    data = bpy.data.lights.new("sun", type="SUN")
    data.energy = irradiance  # W/m^2: irradiance on a surface facing it
    data.angle = 0.0
    sun = bpy.data.objects.new("sun", data)
    sun.rotation_mode = "QUATERNION"
    sun.rotation_quaternion = mathutils.Vector(SUN_DIRECTION).normalized().to_track_quat("-Z", "Y")
    bpy.context.scene.collection.objects.link(sun)


def make_world(s, a):
    env = [0.0, 0.0, 0.0]
    for light in s["lights"]:
        if light["type"] == "environment":
            env = [x + y for x, y in zip(env, light["color"])]
    emits = any(max(m["emission"]) > 0.0 for m in s["materials"]) or max(env) > 0.0
    if not emits:  # hrpp render's --default-environment and --default-sun
        env = [a.default_environment] * 3
        if a.default_sun > 0.0:
            make_sun(a.default_sun)
    world = bpy.data.worlds.new("world")
    world.use_nodes = True
    bg = world.node_tree.nodes["Background"]
    bg.inputs["Color"].default_value = (*env, 1.0)
    bg.inputs["Strength"].default_value = 1.0
    bpy.context.scene.world = world


def set_render(a, width, height):
    scene = bpy.context.scene
    scene.render.engine = "CYCLES"
    cy = scene.cycles
    cy.device = "CPU"
    cy.samples = a.spp
    cy.use_adaptive_sampling = False
    cy.use_denoising = False
    cy.seed = a.seed
    bounces = max(0, a.max_depth - 1)
    cy.max_bounces = bounces
    cy.diffuse_bounces = bounces
    cy.glossy_bounces = bounces
    cy.transmission_bounces = bounces
    cy.transparent_max_bounces = bounces
    cy.sample_clamp_direct = 0.0
    cy.sample_clamp_indirect = 0.0
    cy.blur_glossy = 0.0
    cy.light_sampling_threshold = 0.0
    cy.pixel_filter_type = "BOX"
    cy.filter_width = 1.0
    scene.render.resolution_x = width
    scene.render.resolution_y = height
    scene.render.resolution_percentage = 100
    scene.render.film_transparent = False
    scene.view_settings.view_transform = "Standard"
    scene.view_settings.look = "None"
    scene.render.image_settings.file_format = "OPEN_EXR"
    scene.render.image_settings.color_depth = "32"
    scene.render.image_settings.exr_codec = "NONE"
    scene.render.filepath = a.out


def main():
    a = parse_args()
    try:
        width, height = (int(x) for x in a.size.lower().split("x"))
    except ValueError:
        fail(f"--size {a.size}: expected WxH")
    with open(a.scene) as f:
        s = json.load(f)
    if s.get("format") != "hrpp scene export 1":
        fail(f"{a.scene}: not an hrpp scene export (hrpp scene SCENE --export-json FILE)")
    check_supported(s)
    if not 0 <= a.camera < len(s["cameras"]):
        fail(f"--camera {a.camera}: the scene has {len(s['cameras'])}")
    bpy.ops.wm.read_factory_settings(use_empty=True)
    make_mesh(s)
    make_camera(s["cameras"][a.camera], width / height)
    make_world(s, a)
    set_render(a, width, height)
    bpy.ops.render.render(write_still=True)
    print(f"cycles_reference: wrote {a.out} ({a.size}, {a.spp} spp, seed {a.seed})")


main()
