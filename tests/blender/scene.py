"""Run by tests/blender.rs: `blender -b --factory-startup --python scene.py -- OUT`, with the
add-on in $BLENDER_USER_SCRIPTS/addons/pelt_fur and $PELT set. Builds the test scenes, runs the
add-on's operators and writes what tests/blender.rs checks into OUT:

- hair.glb, hair.json: a wavy grid with hair particles combed toward +X (object-aligned
  velocity plus some along the normal), `comb_from_hair`, `export_baked`; per vertex its
  position and the root-segment direction of its nearest hair, both in glTF axes, and whether
  a root lies within one edge length;
- curves.glb, curves.json: the same groom converted to a Curves hair object on the grid;
- painted.glb, painted.json: a grid with a byte colour attribute painted per vertex (no
  flags anywhere), `export_baked`; per vertex its position and painted direction, glTF axes;
- failure.json: two exports with preview (pelt view is started once: `view_calls`), then an
  export whose bake fails (a bake config that is not JSON): the error the
  operator raised, and whether the earlier output at that path is unchanged; and the error
  when the add-on's pelt path names no file;
- plain.glb, plain.json: a grid without a comb or hair: Comb from hair's error, and what
  the panel shows after its export (pelt's warning).
"""

import json
import math
import os
import random
import sys

import addon_utils
import bpy
from mathutils import Vector

OUT = sys.argv[sys.argv.index("--") + 1]


def error_of(operator, **kwargs):
    """The error `operator` raises (as Blender reports it), or None if it succeeds."""
    try:
        operator(**kwargs)
    except RuntimeError as e:
        return str(e)
    return None


def gltf_axes(v):
    """Blender (x, y, z) to glTF (x, z, -y)."""
    return [v[0], v[2], -v[1]]


def reset():
    bpy.ops.wm.read_factory_settings(use_empty=True)
    addon_utils.enable("pelt_fur", default_set=True)


def wavy_grid(name, size=2.0, cuts=20):
    bpy.ops.mesh.primitive_grid_add(x_subdivisions=cuts, y_subdivisions=cuts, size=size)
    obj = bpy.context.active_object
    obj.name = name
    for v in obj.data.vertices:
        v.co.z = 0.15 * math.sin(2.0 * v.co.x) * math.cos(1.5 * v.co.y)
    obj.data.update()
    # Placed and turned: the comb must come out in the object's own space.
    obj.location = (3.0, -1.0, 0.5)
    obj.rotation_euler = (0.0, 0.0, 0.7)
    return obj, size / cuts


def hair_scene(as_curves):
    reset()
    obj, edge = wavy_grid("groomed")
    mod = obj.modifiers.new("hair", 'PARTICLE_SYSTEM')
    ps = mod.particle_system.settings
    ps.type = 'HAIR'
    ps.count = 400
    ps.hair_length = 0.2
    ps.use_advanced_hair = True
    ps.normal_factor = 0.4
    ps.object_align_factor = (1.0, 0.0, 0.0)
    # Each hair strays a little: neighbours disagree, as in a real groom.
    ps.factor_random = 0.15
    ps.display_step = 3
    bpy.context.scene.pelt_fur.max_length = 0.0
    # The ground truth: each vertex's nearest root and its root segment, from the particles.
    depsgraph = bpy.context.evaluated_depsgraph_get()
    ev = obj.evaluated_get(depsgraph)
    psys = ev.particle_systems[0]
    to_local = obj.matrix_world.inverted()
    roots = []
    for p in range(len(psys.particles)):
        a = to_local @ psys.co_hair(ev, particle_no=p, step=0)
        b = to_local @ psys.co_hair(ev, particle_no=p, step=1)
        roots.append((a, (b - a).normalized()))
    vertices = []
    for v in obj.data.vertices:
        root, direction = min(roots, key=lambda r: (r[0] - v.co).length)
        vertices.append({
            "position": gltf_axes(v.co),
            "hair": gltf_axes(direction),
            "near_root": (root - v.co).length <= edge,
        })
    name = "hair"
    if as_curves:
        # The same groom as a Curves hair object on the grid (Blender's new hair), the
        # particle system gone.
        bpy.ops.curves.convert_from_particle_system()
        curves = next(o for o in bpy.data.objects if o.type == 'CURVES')
        curves.data.surface = obj
        obj.modifiers.remove(mod)
        bpy.context.view_layer.objects.active = obj
        name = "curves"
    bpy.ops.pelt.comb_from_hair()
    path = os.path.join(OUT, name + ".glb")
    bpy.ops.pelt.export_baked(filepath=path)
    with open(os.path.join(OUT, name + ".json"), "w") as f:
        json.dump({"edge": edge, "roots": len(roots), "vertices": vertices}, f)


def painted_scene():
    reset()
    obj, _ = wavy_grid("painted", cuts=8)
    mesh = obj.data
    attr = mesh.color_attributes.new("paint", 'BYTE_COLOR', 'POINT')
    rng = random.Random(7)
    vertices = []
    for i, v in enumerate(mesh.vertices):
        # An artist's bytes: a direction in Blender's axes, as 8-bit sRGB.
        rgb = [rng.randrange(256) for _ in range(3)]
        attr.data[i].color_srgb = (rgb[0] / 255, rgb[1] / 255, rgb[2] / 255, 1.0)
        d = [c / 255 * 2 - 1 for c in rgb]
        vertices.append({"position": gltf_axes(v.co), "painted": gltf_axes(d)})
    mesh.color_attributes.active_color_index = 0
    mesh.color_attributes.render_color_index = 0
    path = os.path.join(OUT, "painted.glb")
    bpy.ops.pelt.export_baked(filepath=path)
    with open(os.path.join(OUT, "painted.json"), "w") as f:
        json.dump({"vertices": vertices}, f)
    # Preview: `pelt view` opens once; a second export of the same path leaves that window to
    # reload. A stand-in pelt (the add-on's pelt path preference) logs view calls and bakes
    # with the real one.
    stand_in = os.path.join(OUT, "pelt-stand-in.sh")
    views = os.path.join(OUT, "views.log")
    with open(stand_in, "w") as f:
        f.write('#!/bin/sh\nif [ "$1" = view ]; then echo "$@" >> "%s"; exec sleep 60; fi\n'
                'exec "%s" "$@"\n' % (views, os.environ["PELT"]))
    os.chmod(stand_in, 0o755)
    prefs = bpy.context.preferences.addons["pelt_fur"].preferences
    prefs.pelt_path = stand_in
    bpy.ops.pelt.export_baked(filepath=path, preview=True)
    bpy.ops.pelt.export_baked(filepath=path, preview=True)
    from pelt_fur import preview
    for window in preview._windows.values():
        window.kill()
        window.wait()
    with open(views) as f:
        view_calls = f.read().splitlines()
    prefs.pelt_path = ""
    # A failing bake: the earlier output stays, pelt's message comes back.
    before = open(path, "rb").read()
    bad = os.path.join(OUT, "bad-config.json")
    with open(bad, "w") as f:
        f.write("{ not json")
    bpy.context.scene.pelt_fur.config = bad
    error = error_of(bpy.ops.pelt.export_baked, filepath=path)
    panel = bpy.context.scene.pelt_fur.last_report
    prefs.pelt_path = os.path.join(OUT, "no-such-pelt")
    missing = error_of(bpy.ops.pelt.export_baked, filepath=path)
    prefs.pelt_path = ""
    with open(os.path.join(OUT, "failure.json"), "w") as f:
        json.dump({
            "error": error,
            "panel": panel,
            "unchanged": open(path, "rb").read() == before,
            "leftovers": sorted(n for n in os.listdir(OUT) if n.startswith(".pelt-")),
            "view_calls": view_calls,
            "missing_pelt": missing,
        }, f)


def plain_scene():
    """A mesh without any comb: pelt bakes it with a warning, which the panel shows."""
    reset()
    wavy_grid("plain", cuts=4)
    no_hair = error_of(bpy.ops.pelt.comb_from_hair)
    bpy.ops.pelt.export_baked(filepath=os.path.join(OUT, "plain.glb"))
    with open(os.path.join(OUT, "plain.json"), "w") as f:
        json.dump({"panel": bpy.context.scene.pelt_fur.last_report, "no_hair": no_hair}, f)


hair_scene(as_curves=False)
hair_scene(as_curves=True)
painted_scene()
plain_scene()
