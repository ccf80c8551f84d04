"""Renders a baked .glb in Blender (Cycles, CPU) as a viewer without pelt's runtime sees it:
the mesh with its glTF material, KHR_materials_sheen included, framed from the front-left.
For the picture in docs/extension/PELT_fur/README.md.

    blender -b --factory-startup --python tools/blender-sheen-render.py -- IN.glb OUT.png [WxH]
"""
import math
import sys

import numpy as np

if not hasattr(np, "bool"):
    np.bool = np.bool_  # Blender 3.4's glTF add-on with NumPy >= 1.24

import bpy
from mathutils import Vector

args = sys.argv[sys.argv.index("--") + 1:]
src, out = args[0], args[1]
w, h = (int(x) for x in (args[2] if len(args) > 2 else "480x270").split("x"))

bpy.ops.wm.read_factory_settings(use_empty=True)
bpy.ops.import_scene.gltf(filepath=src)
scene = bpy.context.scene

# The imported meshes' bounds in world space.
corners = [o.matrix_world @ Vector(c) for o in scene.objects if o.type == "MESH" for c in o.bound_box]
lo = Vector([min(c[i] for c in corners) for i in range(3)])
hi = Vector([max(c[i] for c in corners) for i in range(3)])
centre, radius = (lo + hi) / 2, (hi - lo).length / 2

cam = bpy.data.objects.new("camera", bpy.data.cameras.new("camera"))
scene.collection.objects.link(cam)
cam.data.lens_unit = "FOV"
cam.data.angle = math.radians(35)
# glTF is Y-up; Blender's importer turns it Z-up. Look from the front-left, a little above.
d = Vector((-0.6, -1.0, 0.35)).normalized()
cam.location = centre + d * radius / math.tan(math.radians(35) / 2) * 1.05
cam.rotation_euler = (centre - cam.location).to_track_quat("-Z", "Y").to_euler()
scene.camera = cam

sun = bpy.data.objects.new("sun", bpy.data.lights.new("sun", "SUN"))
sun.data.energy = 3.0
sun.rotation_euler = (math.radians(50), 0, math.radians(-30))
scene.collection.objects.link(sun)
world = bpy.data.worlds.new("world")
world.color = (0.05, 0.05, 0.06)
world.use_nodes = True
world.node_tree.nodes["Background"].inputs[0].default_value = (0.15, 0.16, 0.18, 1.0)
scene.world = world

scene.render.engine = "CYCLES"
scene.cycles.device = "CPU"
scene.cycles.samples = 64
scene.cycles.use_denoising = False
scene.render.resolution_x, scene.render.resolution_y = w, h
scene.render.film_transparent = False
scene.render.filepath = out
bpy.ops.render.render(write_still=True)
