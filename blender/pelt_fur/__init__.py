"""pelt fur: a Blender add-on that turns a groom or a painted comb into a baked, previewed
pelt asset. Copy or link this folder into Blender's add-ons folder and enable "pelt fur";
see docs/blender.md.

- Object > pelt fur > Comb from hair (`bpy.ops.pelt.comb_from_hair`): the comb colour
  attribute from the mesh's hair particle systems and the Curves hair objects on it.
- Object > pelt fur > Export baked (`bpy.ops.pelt.export_baked`): glTF export, `pelt bake`,
  pelt's warnings and errors in Blender's UI, optionally `pelt view` on the result.
"""

bl_info = {
    "name": "pelt fur",
    "author": "the pelt authors",
    "version": (0, 1, 0),
    "blender": (3, 4, 0),
    "location": "Properties > Object > pelt fur",
    "description": "Comb from hair, bake with pelt, preview the furred asset",
    "category": "Import-Export",
}

from . import comb, export, settings, ui  # noqa: E402

_MODULES = (settings, comb, export, ui)


def register():
    for m in _MODULES:
        m.register()


def unregister():
    for m in reversed(_MODULES):
        m.unregister()
