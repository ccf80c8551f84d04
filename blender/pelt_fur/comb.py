"""Comb from hair: the comb colour attribute a groom implies.

Per vertex, the direction of the root segments of the nearest hairs (the mesh's hair particle
systems, and Curves hair objects whose surface is this mesh), averaged with inverse-square
distance weights over the `neighbours` nearest roots, in the object's own space; their length
as alpha. The encoding is the one `pelt bake` decodes (docs/blender.md): RGB = direction / 2 +
1/2, A = hair length / max length (clamped to 1), stored unchanged in a float colour attribute
on the vertices, so the export writes it as linear COLOR_0 and the bake's Gram-Schmidt step
(Revie, Listing 2.7) lays it on the surface.
"""

import bpy
from mathutils import Vector, kdtree


def _hair(points):
    """(root, unit direction of the root segment, length) of one hair; None if it has none."""
    if len(points) < 2:
        return None
    root = points[0]
    # The first point off the root (a zero first segment takes the next one).
    tip = next((p for p in points[1:] if (p - root).length > 1e-9), None)
    if tip is None:
        return None
    length = sum((b - a).length for a, b in zip(points, points[1:]))
    return root, (tip - root).normalized(), length


def particle_hairs(evaluated, to_local):
    """The hairs of every hair particle system of `evaluated` (the evaluated object)."""
    hairs = []
    for psys in evaluated.particle_systems:
        s = psys.settings
        if s.type != 'HAIR':
            continue
        # The cached hair holds 2^display_step segments per hair; co_hair is in world space.
        steps = 2 ** s.display_step
        for p in range(len(psys.particles)):
            pts = [to_local @ psys.co_hair(evaluated, particle_no=p, step=k)
                   for k in range(steps + 1)]
            h = _hair(pts)
            if h:
                hairs.append(h)
    return hairs


def curves_hairs(context, obj, depsgraph, to_local):
    """The hairs of the Curves objects grown on `obj` (their `surface`)."""
    hairs = []
    for o in context.scene.objects:
        if o.type != 'CURVES' or getattr(o.data, "surface", None) != obj:
            continue
        data = o.evaluated_get(depsgraph).data
        m = to_local @ o.matrix_world
        for c in data.curves:
            first = c.first_point_index
            pts = [m @ Vector(data.points[i].position)
                   for i in range(first, first + c.points_length)]
            h = _hair(pts)
            if h:
                hairs.append(h)
    return hairs


def hairs_on(context, obj):
    """Every hair on mesh object `obj`, in its space: [(root, direction, length)]."""
    depsgraph = context.evaluated_depsgraph_get()
    to_local = obj.matrix_world.inverted()
    evaluated = obj.evaluated_get(depsgraph)
    return (particle_hairs(evaluated, to_local)
            + curves_hairs(context, obj, depsgraph, to_local))


def comb_colors(positions, hairs, neighbours, max_length):
    """RGBA per position (flat list): see the module documentation."""
    tree = kdtree.KDTree(len(hairs))
    for i, (root, _, _) in enumerate(hairs):
        tree.insert(root, i)
    tree.balance()
    scale = max_length if max_length > 0 else max(h[2] for h in hairs)
    out = []
    for co in positions:
        near = tree.find_n(co, min(neighbours, len(hairs)))
        direction = Vector((0.0, 0.0, 0.0))
        length = 0.0
        total = 0.0
        for _, i, dist in near:
            w = 1.0 / max(dist * dist, 1e-12)
            direction += w * hairs[i][1]
            length += w * hairs[i][2]
            total += w
        if direction.length < 1e-9:
            # Opposed hairs cancel: the nearest one decides.
            direction = hairs[near[0][1]][1].copy()
        direction.normalize()
        alpha = min(length / total / scale, 1.0) if scale > 0 else 0.0
        out.extend((0.5 * direction.x + 0.5, 0.5 * direction.y + 0.5,
                    0.5 * direction.z + 0.5, alpha))
    return out


def write_comb(mesh, name, colors):
    """Writes `colors` as float colour attribute `name` on the vertices, the one rendered and
    exported (COLOR_0)."""
    attr = mesh.color_attributes.get(name)
    if attr is not None and (attr.domain != 'POINT' or attr.data_type != 'FLOAT_COLOR'):
        mesh.color_attributes.remove(attr)
        attr = None
    if attr is None:
        attr = mesh.color_attributes.new(name, 'FLOAT_COLOR', 'POINT')
    attr.data.foreach_set("color", colors)
    make_exported(mesh, name)
    mesh.update()


def make_exported(mesh, name):
    """Makes colour attribute `name` the active and render colour (the one glTF exports)."""
    index = mesh.color_attributes.find(name)
    mesh.color_attributes.active_color_index = index
    mesh.color_attributes.render_color_index = index


class PELT_OT_comb_from_hair(bpy.types.Operator):
    """Write the comb colour attribute from the hair grown on the active mesh"""
    bl_idname = "pelt.comb_from_hair"
    bl_label = "Comb from hair"
    bl_options = {'REGISTER', 'UNDO'}

    @classmethod
    def poll(cls, context):
        o = context.active_object
        return o is not None and o.type == 'MESH' and o.mode == 'OBJECT'

    def execute(self, context):
        obj = context.active_object
        settings = context.scene.pelt_fur
        hairs = hairs_on(context, obj)
        if not hairs:
            self.report({'ERROR'}, f"{obj.name}: no hair: add a hair particle system, or a "
                        "Curves hair object with this mesh as its surface")
            return {'CANCELLED'}
        mesh = obj.data
        positions = [v.co for v in mesh.vertices]
        colors = comb_colors(positions, hairs, settings.neighbours, settings.max_length)
        write_comb(mesh, settings.comb_attribute, colors)
        self.report({'INFO'}, f"{obj.name}: comb '{settings.comb_attribute}' from "
                    f"{len(hairs)} hairs on {len(positions)} vertices")
        return {'FINISHED'}


def register():
    bpy.utils.register_class(PELT_OT_comb_from_hair)


def unregister():
    bpy.utils.unregister_class(PELT_OT_comb_from_hair)
