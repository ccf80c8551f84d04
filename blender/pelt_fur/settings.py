"""The add-on's preference (where pelt is) and the scene's fur settings (what the comb and the
bake use)."""

import os
import shutil

import bpy
from bpy.props import (BoolProperty, EnumProperty, FloatProperty, IntProperty,
                       PointerProperty, StringProperty)


class PeltPreferences(bpy.types.AddonPreferences):
    bl_idname = __package__

    pelt_path: StringProperty(
        name="pelt executable",
        description="Path of pelt (empty: the PELT environment variable, then PATH)",
        subtype='FILE_PATH',
        default="",
    )

    def draw(self, context):
        self.layout.prop(self, "pelt_path")


class PeltFurSettings(bpy.types.PropertyGroup):
    comb_attribute: StringProperty(
        name="Comb attribute",
        description="Colour attribute that holds the comb: written by Comb from hair, "
                    "exported as COLOR_0 (a painted one works the same)",
        default="pelt_comb",
    )
    max_length: FloatProperty(
        name="Max length",
        description="Hair length stored as full fur length (alpha 1); longer hairs clamp. "
                    "0: the longest hair",
        default=0.0, min=0.0, unit='LENGTH',
    )
    neighbours: IntProperty(
        name="Hairs per vertex",
        description="How many of the nearest hair roots each vertex averages "
                    "(inverse-square distance weights)",
        default=4, min=1, max=64,
    )
    config: StringProperty(
        name="Bake config",
        description="pelt bake config (JSON): fur length, shells, textures. Empty: none",
        subtype='FILE_PATH', default="",
    )
    topology: EnumProperty(
        name="Topology",
        items=[('full', "Full", "Normal groups and fin edges"),
               ('groups', "Groups", "Normal groups only"),
               ('off', "Off", "The comb alone")],
        default='full',
    )
    quantize: EnumProperty(
        name="Comb storage",
        items=[('float', "Float", ""), ('u16', "16-bit", ""), ('u8', "8-bit", "")],
        default='float',
    )
    compress: BoolProperty(
        name="Compress",
        description="Quantized, meshopt-compressed output for shipping (pelt bake --compress)",
        default=False,
    )
    extra_args: StringProperty(
        name="More flags",
        description="More pelt bake flags, as on a command line",
        default="",
    )
    last_report: StringProperty(
        name="Last bake",
        description="What the last bake reported",
        default="",
    )


def find_pelt(context):
    """The pelt executable (the preference, else $PELT, else PATH) and None, or None and why
    there is none."""
    prefs = context.preferences.addons[__package__].preferences
    for where, candidate in (("the add-on's pelt path",
                              bpy.path.abspath(prefs.pelt_path) if prefs.pelt_path else ""),
                             ("PELT", os.environ.get("PELT", ""))):
        if candidate:
            if os.path.isfile(candidate):
                return candidate, None
            return None, f"pelt not found: {where} is {candidate}, which is no file"
    found = shutil.which("pelt")
    if found is None:
        return None, ("pelt not found: set the add-on's pelt path, the PELT environment "
                      "variable, or put pelt on PATH")
    return found, None


def register():
    bpy.utils.register_class(PeltPreferences)
    bpy.utils.register_class(PeltFurSettings)
    bpy.types.Scene.pelt_fur = PointerProperty(type=PeltFurSettings)


def unregister():
    del bpy.types.Scene.pelt_fur
    bpy.utils.unregister_class(PeltFurSettings)
    bpy.utils.unregister_class(PeltPreferences)
