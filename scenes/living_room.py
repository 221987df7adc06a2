"""The living room ("The Grey & White Room" by Wig42, Bitterli's Mitsuba scene; 143,163
triangles, 65 objects) lit by its sky through the windows: a furnished interior of the
real-scene suite (tools/real_scenes.py), imported from ../shared/scenes/living-room (not
copied into the project; see its SOURCE.md for the license and attribution).

Run:
    blender -b --factory-startup --python scenes/living_room.py -- --out living_room.blend
        [--living-room /path/to/living-room]

As imported, except:
- the world is the scene's own environment map, `original/textures/Sky 19.exr`, as an
  Environment Texture (bakegi reads a textured world as its mean colour, with a warning);
- the three glass objects (small vessels on a shelf, materials with transmission; the
  windows have no panes) are hidden, as when bakegi let no light through surfaces, so that
  the suite's references stay those of this scene (shown, they change the bake's mean by
  0.04%: docs/real_scenes.md, "See-through surfaces");
- the glTF camera is the scene camera.
The leaves' alpha mask is kept (cut out: light passes where it is clear).
"""

import argparse
import os
import sys

import bpy

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import cornell_box  # noqa: E402  (shared helpers)
DEFAULT_FOLDER = os.path.normpath(os.path.join(HERE, "..", "..", "shared", "scenes", "living-room"))


def living_room_folder(folder=None):
    return folder or os.environ.get("BAKEGI_LIVING_ROOM", DEFAULT_FOLDER)


def _lets_light_through(material):
    if material is None or not cornell_box.uses_nodes(material):
        return False
    for node in material.node_tree.nodes:
        if node.type == "BSDF_PRINCIPLED":
            socket = node.inputs.get("Transmission Weight") or node.inputs.get("Transmission")
            if socket is not None and socket.default_value > 0.5:
                return True
    return False


def build_living_room(folder=None):
    """Imports the room into an empty file, hides the glass vessels, sets the sky. Returns the names
    of the hidden glass objects. Raises FileNotFoundError (with the path) when absent."""
    folder = living_room_folder(folder)
    path = os.path.join(folder, "LivingRoom.gltf")
    sky = os.path.join(folder, "original", "textures", "Sky 19.exr")
    for needed in (path, sky):
        if not os.path.isfile(needed):
            raise FileNotFoundError(f"living room not found at {needed} (set BAKEGI_LIVING_ROOM)")
    import numpy

    if not hasattr(numpy, "bool"):
        numpy.bool = bool  # Blender 3.4's glTF importer uses np.bool, gone in numpy 1.24
    bpy.ops.wm.read_factory_settings(use_empty=True)
    bpy.ops.import_scene.gltf(filepath=path)
    scene = bpy.context.scene
    glass = sorted(o.name for o in scene.objects if o.type == "MESH" and
                   any(_lets_light_through(slot.material) for slot in o.material_slots))
    for name in glass:
        obj = bpy.data.objects[name]
        obj.hide_set(True)
        obj.hide_render = True
    world = bpy.data.worlds.new("Sky")
    cornell_box.use_nodes(world)
    background = world.node_tree.nodes["Background"]
    environment = world.node_tree.nodes.new("ShaderNodeTexEnvironment")
    environment.image = bpy.data.images.load(sky)
    world.node_tree.links.new(environment.outputs["Color"], background.inputs["Color"])
    scene.world = world
    cameras = [o for o in scene.objects if o.type == "CAMERA"]
    if cameras:
        scene.camera = cameras[0]
    bpy.context.view_layer.update()
    return glass


def main():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", required=True, help="the .blend to write")
    parser.add_argument("--living-room", default=None, help="folder holding LivingRoom.gltf")
    args = parser.parse_args(argv)
    glass = build_living_room(args.living_room)
    bpy.ops.wm.save_as_mainfile(filepath=os.path.abspath(args.out))
    print(f"living_room: hid the glass {glass}, saved {args.out}")


if __name__ == "__main__":
    main()
