# SPDX-License-Identifier: GPL-3.0-or-later
"""The Material Preview hook: baked light shown in the viewport without changing how the
material renders.

hook(material, info) / unhook(material): the non-destructive Material Preview hook. The
hook adds nodes named "BakeGI_*" that compute albedo x BakeGI_Indirect (an Attribute
node reading the baked color attribute) and emit it through an Emission shader whose
strength is Light Path "Is Camera Ray" (so in Cycles the baked light is not fed to other
surfaces), added with an Add Shader to whatever was plugged into the Material Output's
Surface. The original link is stored on the material (ID property "bakegi_hook");
unhook removes the added nodes and restores that link exactly.

A material is hooked once, whatever number of objects use it. Objects that use a hooked
material but carry no BakeGI_Indirect attribute read black from the Attribute node, so
they look exactly as before.
"""

from .. import compat
from ..export.node_tree import active_output


ATTRIBUTE_NAME = "BakeGI_Indirect"
NODE_PREFIX = "BakeGI_"
HOOK_PROPERTY = "bakegi_hook"
# Version 2 of the hook reads the lightmap atlas too; version-1 hooks are rebuilt.
HOOK_VERSION = 2
# Object custom properties of a LIGHTMAP bake (read by the hook's Attribute nodes of type
# OBJECT): the object's tile in the atlas (atlas UV = uv * scale + offset) and 1.0 while the
# object has a lightmap (objects without one read 0, so their lightmap term vanishes).
LIGHTMAP_SCALE = "bakegi_lightmap_scale"
LIGHTMAP_OFFSET = "bakegi_lightmap_offset"
LIGHTMAP_WEIGHT = "bakegi_lightmap_weight"


# ---- the Material Preview hook -----------------------------------------------------------


def is_hooked(material):
    return material is not None and material.get(HOOK_PROPERTY) is not None


def _hook_version(material):
    record = material.get(HOOK_PROPERTY)
    try:
        return int(record.get("version", 1))
    except (AttributeError, TypeError, ValueError):
        return 1


def can_hook(material, info):
    return (material is not None and compat.uses_nodes(material)
            and active_output(material.node_tree) is not None and
            (info.color_source is not None or max(info.albedo) > 0.0))


def hook(material, info, lightmap_image=None, uv_map="BakeGI"):
    """Adds albedo x (BakeGI_Indirect + the object's lightmap texel) as camera-only emission.
    A material hooked already only gets the lightmap image and UV map set. Returns True if
    hooked now."""
    if is_hooked(material) and _hook_version(material) < HOOK_VERSION:
        unhook(material)
    if is_hooked(material):
        set_lightmap(material, lightmap_image, uv_map)
        return False
    if not can_hook(material, info):
        return False
    tree = material.node_tree
    output = active_output(tree)
    surface_input = output.inputs["Surface"]
    # The link into Surface as it is (possibly from a reroute), to restore it exactly.
    direct = surface_input.links[0] if surface_input.is_linked else None
    record = {"output": output.name, "from_node": "", "from_socket": -1}
    if direct is not None:
        record["from_node"] = direct.from_node.name
        record["from_socket"] = list(direct.from_node.outputs).index(direct.from_socket)

    x, y = output.location.x, output.location.y
    nodes, links = tree.nodes, tree.links

    def new(kind, name, dx, dy):
        node = nodes.new(kind)
        node.name = NODE_PREFIX + name
        node.label = "BakeGI " + name.replace("_", " ")
        node.location = (x + dx, y + dy)
        return node

    attribute = new("ShaderNodeAttribute", "Indirect", -900, -300)
    attribute.attribute_type = "GEOMETRY"
    attribute.attribute_name = ATTRIBUTE_NAME
    lightmap = _lightmap_nodes(new, links, lightmap_image, uv_map)
    indirect = new("ShaderNodeVectorMath", "Indirect_Sum", -700, -480)
    indirect.operation = "ADD"
    links.new(attribute.outputs["Color"], indirect.inputs[0])
    links.new(lightmap, indirect.inputs[1])
    times_albedo = new("ShaderNodeVectorMath", "Times_Albedo", -650, -300)
    times_albedo.operation = "MULTIPLY"
    links.new(indirect.outputs["Vector"], times_albedo.inputs[0])
    color_node = tree.nodes.get(info.color_source[0]) if info.color_source else None
    if color_node is not None and info.color_source[1] < len(color_node.outputs):
        links.new(color_node.outputs[info.color_source[1]], times_albedo.inputs[1])
        f = float(info.albedo_factor)
        if f != 1.0:
            times_factor = new("ShaderNodeVectorMath", "Times_Factor", -450, -300)
            times_factor.operation = "SCALE"
            links.new(times_albedo.outputs["Vector"], times_factor.inputs[0])
            times_factor.inputs["Scale"].default_value = f
            albedo_out = times_factor.outputs["Vector"]
        else:
            albedo_out = times_albedo.outputs["Vector"]
    else:
        times_albedo.inputs[1].default_value = tuple(info.albedo)
        albedo_out = times_albedo.outputs["Vector"]
    light_path = new("ShaderNodeLightPath", "Light_Path", -450, -520)
    emission = new("ShaderNodeEmission", "Emission", -250, -300)
    links.new(albedo_out, emission.inputs["Color"])
    links.new(light_path.outputs["Is Camera Ray"], emission.inputs["Strength"])
    add = new("ShaderNodeAddShader", "Add", -80, -120)
    if direct is not None:
        links.new(direct.from_socket, add.inputs[0])
    links.new(emission.outputs["Emission"], add.inputs[1])
    links.new(add.outputs["Shader"], surface_input)
    record["version"] = HOOK_VERSION
    material[HOOK_PROPERTY] = record
    return True


def _lightmap_nodes(new, links, image, uv_map):
    """The object's lightmap texel: UV map -> (uv * scale + offset) -> atlas image, times
    the object's lightmap weight (0 for objects without a lightmap). Returns its output."""
    uv = new("ShaderNodeUVMap", "Lightmap_UV", -1500, -650)
    uv.uv_map = uv_map
    scale = _object_attribute(new, "Lightmap_Scale", LIGHTMAP_SCALE, -1500, -800)
    offset = _object_attribute(new, "Lightmap_Offset", LIGHTMAP_OFFSET, -1500, -950)
    weight = _object_attribute(new, "Lightmap_Weight", LIGHTMAP_WEIGHT, -1100, -950)
    place = new("ShaderNodeVectorMath", "Lightmap_Place", -1300, -700)
    place.operation = "MULTIPLY_ADD"
    links.new(uv.outputs["UV"], place.inputs[0])
    links.new(scale.outputs["Vector"], place.inputs[1])
    links.new(offset.outputs["Vector"], place.inputs[2])
    texture = new("ShaderNodeTexImage", "Lightmap", -1100, -650)
    texture.interpolation = "Linear"
    texture.extension = "EXTEND"
    texture.image = image
    links.new(place.outputs["Vector"], texture.inputs["Vector"])
    weighted = new("ShaderNodeVectorMath", "Lightmap_Weighted", -850, -650)
    weighted.operation = "SCALE"
    links.new(texture.outputs["Color"], weighted.inputs[0])
    links.new(weight.outputs["Fac"], weighted.inputs["Scale"])
    return weighted.outputs["Vector"]


def _object_attribute(new, name, attribute_name, x, y):
    node = new("ShaderNodeAttribute", name, x, y)
    node.attribute_type = "OBJECT"
    node.attribute_name = attribute_name
    return node


def set_lightmap(material, image, uv_map):
    """Points a hooked material's lightmap nodes at `image` (None: keep the current one) and
    the lightmap UV map."""
    tree = material.node_tree
    texture = tree.nodes.get(NODE_PREFIX + "Lightmap") if tree is not None else None
    uv = tree.nodes.get(NODE_PREFIX + "Lightmap_UV") if tree is not None else None
    if texture is not None and image is not None:
        texture.image = image
    if uv is not None and uv_map and image is not None:
        uv.uv_map = uv_map


def lightmap_image(material):
    """The lightmap image a hooked material reads (or None)."""
    tree = material.node_tree if material is not None else None
    texture = tree.nodes.get(NODE_PREFIX + "Lightmap") if tree is not None else None
    return texture.image if texture is not None else None


def unhook(material):
    """Removes the hook's nodes and restores the original Surface link. Returns True if the
    material was hooked."""
    if material is None or material.node_tree is None:
        return False
    record = material.get(HOOK_PROPERTY)
    tree = material.node_tree
    for node in [n for n in tree.nodes if n.name.startswith(NODE_PREFIX)]:
        tree.nodes.remove(node)
    if record is None:
        return False
    output = tree.nodes.get(record.get("output", ""))
    from_node = tree.nodes.get(record.get("from_node", ""))
    index = int(record.get("from_socket", -1))
    if output is not None and from_node is not None and 0 <= index < len(from_node.outputs):
        tree.links.new(from_node.outputs[index], output.inputs["Surface"])
    del material[HOOK_PROPERTY]
    return True


def hook_materials(data, material_infos, targets, lightmap_image=None, uv_map="BakeGI"):
    """Hooks the materials (name_full -> MaterialInfo) used by the targets (and points hooked
    ones at lightmap_image, if given); returns the names of the materials hooked now."""
    from .attributes import look_up_targets  # (attributes imports this module)

    used = set()
    for t, obj, mesh in look_up_targets(data, targets):
        for m in list(mesh.materials) + [s.material for s in obj.material_slots]:
            if m is not None:
                used.add(m.name_full)
    hooked = []
    for material in data.materials:
        info = material_infos.get(material.name_full)
        if info is None or material.name_full not in used:
            continue
        if hook(material, info, lightmap_image, uv_map):
            hooked.append(material.name)
    return hooked
