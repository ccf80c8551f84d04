"""Export baked: the selection (or the active object) through Blender's glTF exporter and
`pelt bake`, with the flags Blender's conventions need, so an artist never types them:

- `--comb-axes x,z,-y`: the exporter turns positions and normals from Blender's Z-up into
  glTF's Y-up, but cannot know that a colour is a direction;
- `--comb-color-space srgb` for a byte colour attribute (painted by hand: Blender stores
  8-bit sRGB and the exporter writes it linearized), `linear` for a float one (Comb from hair
  writes the encoded value itself).

pelt's warnings and errors come back through `self.report` and the panel; the export and
the bake happen in a temporary folder beside the output, and the baked file is renamed over
the output only when the bake succeeds, so a failure leaves any earlier output as it was.
"""

import json
import os
import shlex
import subprocess
import tempfile

import bpy
from bpy.props import BoolProperty, StringProperty
from bpy_extras.io_utils import ExportHelper

from . import comb, preview
from .settings import find_pelt

# Blender (x, y, z) -> glTF (x, z, -y): what the exporter does to positions.
COMB_AXES = "x,z,-y"


def comb_attribute(mesh, wanted):
    """The colour attribute exported as the comb: `wanted` where the mesh has it, else the
    mesh's render colour (painted by hand); None if it has none."""
    attr = mesh.color_attributes.get(wanted)
    if attr is None and mesh.color_attributes.render_color_index >= 0:
        attr = mesh.color_attributes[mesh.color_attributes.render_color_index]
    return attr


def color_space(objects, wanted):
    """`srgb` or `linear` for the meshes' comb attributes; an error string if they differ."""
    kinds = {}
    for o in objects:
        attr = comb_attribute(o.data, wanted)
        if attr is not None:
            kinds.setdefault(attr.data_type, []).append(o.name)
    if len(kinds) > 1:
        listed = "; ".join(f"{k}: {', '.join(v)}" for k, v in sorted(kinds.items()))
        return None, ("the combs mix byte and float colour attributes, which decode "
                      f"differently ({listed}); export them separately")
    return ('srgb' if 'BYTE_COLOR' in kinds else 'linear'), None


def exporter_color_options():
    """The glTF exporter's options that write the active/render colour as COLOR_0: Blender 4.2
    and later choose with `export_vertex_color` (whose default exports only colours a material
    uses), earlier versions with `export_colors`."""
    props = bpy.ops.export_scene.gltf.get_rna_type().properties.keys()
    if "export_vertex_color" in props:
        options = {"export_vertex_color": 'ACTIVE'}
        if "export_all_vertex_colors" in props:
            options["export_all_vertex_colors"] = False
        return options
    return {"export_colors": True}


def bake_command(pelt, src, out, report, settings, space):
    cmd = [pelt, "bake", "-q", src, "-o", out, "--report", report,
           "--comb-axes", COMB_AXES, "--comb-color-space", space,
           "--topology", settings.topology, "--quantize", settings.quantize]
    if settings.config:
        cmd += ["--config", bpy.path.abspath(settings.config)]
    if settings.compress:
        cmd += ["--compress"]
    return cmd + shlex.split(settings.extra_args)


class PELT_OT_export_baked(bpy.types.Operator, ExportHelper):
    """Export the selection as glTF, bake it with pelt and write the furred .glb"""
    bl_idname = "pelt.export_baked"
    bl_label = "Export baked"
    bl_options = {'REGISTER'}

    filename_ext = ".glb"
    filter_glob: StringProperty(default="*.glb", options={'HIDDEN'})
    preview: BoolProperty(
        name="Preview",
        description="Open pelt view on the result (a later export reloads that window)",
        default=False,
    )

    def execute(self, context):
        settings = context.scene.pelt_fur
        pelt, missing = find_pelt(context)
        if pelt is None:
            return self.fail(settings, missing)
        objects = [o for o in context.selected_objects if o.type == 'MESH']
        if not objects and context.active_object and context.active_object.type == 'MESH':
            objects = [context.active_object]
        if not objects:
            return self.fail(settings, "nothing to export: select a mesh")
        space, error = color_space(objects, settings.comb_attribute)
        if error:
            return self.fail(settings, error)
        target = bpy.path.abspath(self.filepath)
        folder = os.path.dirname(target) or "."
        os.makedirs(folder, exist_ok=True)
        # Exported and baked in a folder beside the target (one file system), the result
        # renamed over the target only when the bake succeeded.
        with tempfile.TemporaryDirectory(prefix=".pelt-", dir=folder) as tmp:
            src = os.path.join(tmp, "export.glb")
            self.export_gltf(context, objects, settings, src)
            out = os.path.join(tmp, "baked.glb")
            report = os.path.join(tmp, "report.json")
            cmd = bake_command(pelt, src, out, report, settings, space)
            run = subprocess.run(cmd, capture_output=True, text=True)
            if run.returncode != 0:
                message = (run.stderr.strip() or run.stdout.strip()
                           or f"pelt bake exited with {run.returncode}")
                return self.fail(settings, message.replace(src, "export.glb"))
            warnings = [w.replace(src, "export.glb") for w in read_warnings(report)]
            os.replace(out, target)
        for w in warnings:
            self.report({'WARNING'}, w)
        summary = f"baked {len(objects)} object(s) to {target}"
        settings.last_report = "\n".join([summary] + warnings)
        self.report({'INFO'}, summary)
        if self.preview:
            error = preview.show(pelt, target)
            if error:
                self.report({'WARNING'}, error)
        return {'FINISHED'}

    def export_gltf(self, context, objects, settings, path):
        """Exports `objects` alone, each mesh's comb attribute as COLOR_0; restores the
        selection and each mesh's render colour afterwards."""
        selected = list(context.selected_objects)
        active = context.view_layer.objects.active
        indices = {}
        for o in objects:
            attr = comb_attribute(o.data, settings.comb_attribute)
            colors = o.data.color_attributes
            if attr is not None and o.data.name not in indices:
                indices[o.data.name] = (colors.active_color_index, colors.render_color_index)
                comb.make_exported(o.data, attr.name)
        try:
            for o in context.view_layer.objects:
                o.select_set(o in objects)
            context.view_layer.objects.active = objects[0]
            bpy.ops.export_scene.gltf(
                filepath=path, export_format='GLB', use_selection=True, export_normals=True,
                export_yup=True, export_apply=True, **exporter_color_options())
        finally:
            for o in context.view_layer.objects:
                o.select_set(o in selected)
            context.view_layer.objects.active = active
            for name, (active_index, render_index) in indices.items():
                colors = bpy.data.meshes[name].color_attributes
                colors.active_color_index = active_index
                colors.render_color_index = render_index

    def fail(self, settings, message):
        settings.last_report = message
        self.report({'ERROR'}, message)
        return {'CANCELLED'}


def read_warnings(report):
    """The warnings pelt's JSON report lists for the input."""
    with open(report, encoding="utf-8") as f:
        data = json.load(f)
    return [w for i in data.get("inputs", []) for w in i.get("warnings", [])]


def register():
    bpy.utils.register_class(PELT_OT_export_baked)


def unregister():
    bpy.utils.unregister_class(PELT_OT_export_baked)
