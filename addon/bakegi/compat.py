# SPDX-License-Identifier: GPL-3.0-or-later
"""What differs between the Blender versions bakegi runs on, in one place.

Tested: 3.4 (the Blender program) and 4.2 LTS, 4.5 LTS, 5.0 (Blender as a Python module);
docs/compatibility.md has the table. The rest of the add-on asks this module instead of
testing bpy.app.version itself:

- Cycles' light conventions changed in 4.0 (area light radiance, the spot cone's cosine,
  sphere lights): `cycles_conventions()` names the Cycles whose units a bake matches, and
  light_units.py (bpy-free) applies them.
- Lights gained exposure, temperature and normalize in 4.5, soft falloff in 4.0:
  `light_settings()` reads them with the values older versions behave as.
- Materials and worlds always use nodes in 5.0 (`use_nodes` deprecated): `uses_nodes()`.
- Lightmap Pack's function lost its image arguments in 4.x: `lightmap_uvpack()`.
- Light linking (4.0+) is not modelled: `light_linking_in_use()` finds it to warn.
- EEVEE Next (4.2+) with Raytracing on spreads emission to other surfaces whatever Light
  Path says, the baked light's camera-only emission included: `eevee_raytracing_on()`.
- Files of unsaved .blend files go to the extension's user folder (4.2+ extensions) or to
  Blender's user data folder (legacy add-ons): `user_folder()`.
"""

import inspect
import os

import bpy

VERSION = tuple(bpy.app.version[:2])


def cycles_conventions():
    """(major, minor) of the Cycles whose light units this Blender renders with."""
    return VERSION


def uses_nodes(datablock):
    """Whether a material, world or light is shaded by its node tree."""
    tree = getattr(datablock, "node_tree", None)
    if tree is None:
        return False
    if VERSION >= (5, 0) and isinstance(datablock, (bpy.types.Material, bpy.types.World)):
        return True  # 5.0: always nodes; reading use_nodes only warns it is deprecated
    return bool(getattr(datablock, "use_nodes", False))


def light_settings(light):
    """The light settings that only some versions have, with the values that behave as the
    versions without them (no exposure, no temperature, normalized, soft falloff)."""
    return {
        "exposure": float(getattr(light, "exposure", 0.0)),
        "use_temperature": bool(getattr(light, "use_temperature", False)),
        "temperature": float(getattr(light, "temperature", 6500.0)),
        "normalize": bool(getattr(light, "normalize", True)),
        "use_soft_falloff": bool(getattr(light, "use_soft_falloff", True)),
    }


def light_linking_in_use(obj):
    """Whether an object (a light or an emitter) links or blocks its light to a collection."""
    linking = getattr(obj, "light_linking", None)
    if linking is None:
        return False
    return linking.receiver_collection is not None or linking.blocker_collection is not None


def eevee_raytracing_on(scene):
    """Whether EEVEE (Next, 4.2+) traces rays for indirect light in this scene. Measured with
    tools/eevee_double_light_probe.py: with it on, a surface whose emission is gated by Is
    Camera Ray lights its neighbours as much as an ungated one (4.2, 4.5, 5.0); with it off
    (the default) neither does. 3.4's EEVEE has no such setting."""
    eevee = getattr(scene, "eevee", None)
    return VERSION >= (4, 2) and bool(getattr(eevee, "use_raytracing", False))


def lightmap_uvpack(meshes, **preferences):
    """bl_operators.uvcalc_lightmap.lightmap_uvpack with the preferences this version takes
    (3.4 has PREF_APPLY_IMAGE and PREF_IMG_PX_SIZE, 4.x dropped them)."""
    from bl_operators.uvcalc_lightmap import lightmap_uvpack as pack

    accepted = inspect.signature(pack).parameters
    return pack(meshes, **{k: v for k, v in preferences.items() if k in accepted})


def user_folder(name):
    """A folder of the add-on's own (created) for files that have no .blend file to sit next
    to: the extension's user folder (bpy.utils.extension_path_user) when installed as a 4.2+
    extension, else <Blender's user datafiles>/bakegi."""
    package = __package__
    if package.startswith("bl_ext.") and hasattr(bpy.utils, "extension_path_user"):
        return bpy.utils.extension_path_user(package, path=name, create=True)
    path = os.path.join(bpy.utils.user_resource("DATAFILES", path="bakegi", create=True), name)
    os.makedirs(path, exist_ok=True)
    return path
