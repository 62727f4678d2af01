"""The same scene in Blender with Freestyle lines (make bench-bigmesh,
bench/bigmesh.sh):

  blender -b --factory-startup --python-exit-code 1 -t 1 -P bench/bigmesh_blender.py -- \\
      SCENE.txt MESH.stl OUT.png [--smooth-angle DEG]

SCENE.txt is `sumi eval scene.npr --scene`, MESH.stl `sumi export
scene.npr -o MESH.stl`: the triangles sumi renders, welded and given
welded as bench/stl_to_pov.py does (its read_stl), so POV-Ray and Blender
draw the same vertices; smooth shaded, or with --smooth-angle Blender's
auto smooth at that angle (stl_to_pov.py's rule). Camera, sun and image size are
sumi's; the material is a toon BSDF (sharp-edged diffuse bands, no
bounces: direct light only, so one sample has no noise) on the style's
base colour; Freestyle draws the visible silhouettes and creases of the
style's lines (a crease of sumi's crease(A) is one whose faces meet at more
than A degrees: Freestyle's crease angle 180 - A), and borders when the
kinds name boundary, at the style's width in pixels.

Cycles on the CPU, 1 sample: Freestyle renders with Cycles or EEVEE, and
EEVEE and Workbench need OpenGL, which a headless machine lacks. Prints
one line:
  BENCH import_s=... import_cpu=... render_s=... render_cpu=... verts=... tris=...
(wall and CPU seconds of reading and building the mesh, and of
bpy.ops.render.render: Cycles and then Freestyle)."""
import math
import os
import sys
import time

import bpy
import numpy as np
from mathutils import Vector

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from stl_to_pov import colour, light_direction, read_scene, read_stl, vec  # noqa: E402

argv = sys.argv[sys.argv.index("--") + 1:]
angle = None
if "--smooth-angle" in argv:
    i = argv.index("--smooth-angle")
    angle = float(argv[i + 1])
    del argv[i:i + 2]
scene_txt, stl, out = argv
sc = read_scene(scene_txt)
W, H = (int(x) for x in sc["output.size"].split())


def linear(c):
    """sRGB -> linear, as Blender's colour inputs take."""
    return [x / 12.92 if x <= 0.04045 else ((x + 0.055) / 1.055) ** 2.4 for x in c]


t0, c0 = time.perf_counter(), time.process_time()
bpy.ops.wm.read_factory_settings(use_empty=True)
scene = bpy.context.scene
verts, faces = read_stl(stl)
me = bpy.data.meshes.new("mesh")
me.vertices.add(len(verts))
me.vertices.foreach_set("co", verts.astype(np.float32).ravel())
me.loops.add(faces.size)
me.loops.foreach_set("vertex_index", faces.astype(np.int32).ravel())
me.polygons.add(len(faces))
me.polygons.foreach_set("loop_start", np.arange(0, faces.size, 3, dtype=np.int32))
me.polygons.foreach_set("loop_total", np.full(len(faces), 3, dtype=np.int32))
me.polygons.foreach_set("use_smooth", np.ones(len(faces), dtype=bool))
me.update()
if angle is not None:                        # Blender's own rule for hard edges
    me.use_auto_smooth = True
    me.auto_smooth_angle = math.radians(angle)
obj = bpy.data.objects.new("mesh", me)
scene.collection.objects.link(obj)
t1, c1 = time.perf_counter(), time.process_time()

mat = bpy.data.materials.new("toon")
mat.use_nodes = True
nodes, links = mat.node_tree.nodes, mat.node_tree.links
nodes.clear()
toon = nodes.new("ShaderNodeBsdfToon")
toon.component = "DIFFUSE"
toon.inputs["Color"].default_value = (*linear(colour(sc.get("style[0].base", "#ffffff"))), 1)
toon.inputs["Size"].default_value = 0.8
toon.inputs["Smooth"].default_value = 0.0
glow = nodes.new("ShaderNodeEmission")       # sumi's ambient: 0.1 of the base colour
glow.inputs["Color"].default_value = toon.inputs["Color"].default_value
glow.inputs["Strength"].default_value = float(sc.get("style[0].shade.ambient", "0.1"))
add = nodes.new("ShaderNodeAddShader")
out_node = nodes.new("ShaderNodeOutputMaterial")
links.new(toon.outputs["BSDF"], add.inputs[0])
links.new(glow.outputs["Emission"], add.inputs[1])
links.new(add.outputs["Shader"], out_node.inputs["Surface"])
mat.cycles.sample_as_light = False           # the glow lights nothing: one light, no noise
me.materials.append(mat)

cam_d = bpy.data.cameras.new("cam")
cam_d.sensor_fit = "VERTICAL"
cam_d.angle_y = math.radians(float(sc["camera.fov"]))
cam = bpy.data.objects.new("cam", cam_d)
scene.collection.objects.link(cam)
cam.location = vec(sc["camera.position"])
target = bpy.data.objects.new("target", None)
target.location = vec(sc["camera.look_at"])
scene.collection.objects.link(target)
track = cam.constraints.new("TRACK_TO")
track.target, track.track_axis, track.up_axis = target, "TRACK_NEGATIVE_Z", "UP_Y"
scene.camera = cam

sun_d = bpy.data.lights.new("sun", "SUN")
sun_d.energy = 3.0
sun_d.angle = 0.0
sun = bpy.data.objects.new("sun", sun_d)
scene.collection.objects.link(sun)
d = light_direction(sc)
if d is None:
    sys.exit("bigmesh_blender.py: only a sun (a light with a direction) or sumi's default light")
sun.rotation_mode = "QUATERNION"             # a sun shines down its -z
sun.rotation_quaternion = Vector((0, 0, -1)).rotation_difference(Vector(d))

world = bpy.data.worlds.new("w")
world.use_nodes = True
bg = world.node_tree.nodes["Background"]
bg.inputs["Color"].default_value = (*linear(colour(sc.get("output.background", "#ffffff"))), 1)
world.cycles_visibility.diffuse = False      # the background is seen, not a light
world.cycles_visibility.glossy = False
world.cycles_visibility.transmission = False
world.cycles_visibility.scatter = False
scene.world = world

r = scene.render
r.engine = "CYCLES"
scene.cycles.device = "CPU"
scene.cycles.samples = 1
scene.cycles.use_denoising = False
scene.cycles.use_adaptive_sampling = False
scene.cycles.max_bounces = 0
r.resolution_x, r.resolution_y, r.resolution_percentage = W, H, 100
scene.view_settings.view_transform = "Standard"
r.image_settings.file_format = "PNG"
r.filepath = os.path.abspath(out)
kinds = sc.get("style[0].lines.kinds", "silhouette")
r.use_freestyle = True
r.line_thickness_mode = "ABSOLUTE"
r.line_thickness = float(sc.get("style[0].lines.width", "1"))
vl = scene.view_layers[0]
vl.use_freestyle = True
fs = vl.freestyle_settings
fs.mode = "EDITOR"
ls = fs.linesets[0] if len(fs.linesets) else fs.linesets.new("lines")
ls.select_by_visibility, ls.visibility = True, "VISIBLE"
ls.select_by_edge_types = True
ls.select_silhouette = "silhouette" in kinds
ls.select_border = "boundary" in kinds
crease = [k for k in kinds.split() if k.startswith("crease(")]
ls.select_crease = bool(crease)
if crease:
    fs.crease_angle = math.radians(180 - float(crease[0][7:-1]))
if ls.linestyle is None:
    ls.linestyle = bpy.data.linestyles.new("ink")
ls.linestyle.color = linear(colour(sc.get("style[0].lines.color", "#000000")))
ls.linestyle.thickness = r.line_thickness
t2, c2 = time.perf_counter(), time.process_time()
bpy.ops.render.render(write_still=True)
t3, c3 = time.perf_counter(), time.process_time()
print("BENCH import_s=%.3f import_cpu=%.3f render_s=%.3f render_cpu=%.3f verts=%d tris=%d"
      % (t1 - t0, c1 - c0, t3 - t2, c3 - c2, len(me.vertices), len(me.polygons)))
