"""The pelt fur panel in the Properties editor (Object tab): the fur settings and both
buttons, and what the last bake reported."""

import bpy


class PELT_PT_fur(bpy.types.Panel):
    bl_label = "pelt fur"
    bl_idname = "PELT_PT_fur"
    bl_space_type = 'PROPERTIES'
    bl_region_type = 'WINDOW'
    bl_context = "object"

    @classmethod
    def poll(cls, context):
        return context.active_object is not None and context.active_object.type == 'MESH'

    def draw(self, context):
        s = context.scene.pelt_fur
        col = self.layout.column()
        col.label(text="Comb")
        col.prop(s, "comb_attribute")
        col.prop(s, "max_length")
        col.prop(s, "neighbours")
        col.operator("pelt.comb_from_hair", icon='PARTICLES')
        col.separator()
        col.label(text="Bake")
        col.prop(s, "config")
        col.prop(s, "topology")
        col.prop(s, "quantize")
        col.prop(s, "compress")
        col.prop(s, "extra_args")
        row = col.row()
        row.operator("pelt.export_baked", icon='EXPORT').preview = False
        row.operator("pelt.export_baked", text="Export and preview",
                     icon='HIDE_OFF').preview = True
        if s.last_report:
            box = col.box()
            for line in s.last_report.splitlines()[:12]:
                box.label(text=line)


def register():
    bpy.utils.register_class(PELT_PT_fur)


def unregister():
    bpy.utils.unregister_class(PELT_PT_fur)
