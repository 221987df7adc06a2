#!/usr/bin/env python3
"""The web page tested for real (issue 16, item 7): Blender builds the Cornell box, bakes a
grid with bakegi, writes the web folder (Export for Web) and renders the reference: the same
camera, BakeGI_Indirect from that grid as Apply Grid reads it (each point reads the grid vertices
its rays see, which the page approximates with the export's visibility volume; n^2 weights,
trilinear), shown flat by Workbench with the Standard view
transform. Then addon/web/test/run.mjs streams the folder with `bakegi serve` into Debian's
Chromium (playwright-core) and checks the page against it. A second scene (a box on a floor
under a sun 45 degrees from the zenith) checks the page's shadows and the sun's direction: a
floor point in the box's shadow against one in the open; a tile textured red and blue
beside it, that textures reach the page; and a pane of clear glass in the sun, that the page
draws it see-through, casting no shadow.

    /usr/bin/python3 tools/web_test.py [--work out/web_tests] [--build build] [--fig6]
        [--cells 16] [--size 480x360] [--junit out.xml]

Needs: the system's Blender, node with addon/web's packages (npm ci), the built page
(npm run build), chromium. Exit status 0 when every check passes.
"""

import argparse
import os
import shutil
import subprocess
import sys
import time
import xml.etree.ElementTree as ET

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, HERE)
from sweep_cornell import addon_environment  # noqa: E402

BLENDER_SIDE = """
import sys, bpy, bakegi
sys.path.insert(0, {scenes!r})
import cornell_box
cornell_box.build_cornell_box(subdivisions=16)
scene = bpy.context.scene
scene.render.resolution_x, scene.render.resolution_y = {width}, {height}
scene.render.resolution_percentage = 100
report = bakegi.bake(target="GRID", method="pathtrace", grid_cell_size=2.0 / {cells},
                     grid_rays=64, grid_folder={work!r}, objects="VISIBLE")
print("grid", report["grid"]["path"], report["grid"]["resolution"], flush=True)
print("web", bakegi.export_web({site!r}), flush=True)
bakegi.apply_grid("VISIBLE", interpolation="TRILINEAR", directional="SQUARED",
                  visibility=True, darken_buried=True, hook_materials=False)
for obj in scene.objects:
    if obj.type == "MESH":
        attributes = obj.data.color_attributes
        attributes.active_color = attributes["BakeGI_Indirect"]
scene.render.engine = "BLENDER_WORKBENCH"
shading = scene.display.shading
shading.light = "FLAT"
shading.color_type = "VERTEX"
scene.display.render_aa = "8"
scene.view_settings.view_transform = "Standard"
scene.view_settings.look = "None"
scene.view_settings.exposure = 0.0
scene.view_settings.gamma = 1.0
scene.render.image_settings.file_format = "PNG"
scene.render.image_settings.color_mode = "RGBA"
scene.render.film_transparent = False
scene.world.color = (0.0, 0.0, 0.0)
scene.render.filepath = {reference!r}
bpy.ops.render.render(write_still=True)
"""

SHADOW_SIDE = """
import bpy, bakegi, json
for thing in list(bpy.data.objects):
    bpy.data.objects.remove(thing)
scene = bpy.context.scene
# A dim sky: the page draws its direct light from the grid (which carries it) and says so.
scene.world = bpy.data.worlds.new("Sky")  # a plain colour (or nodes' default grey)
scene.world.color = (0.02, 0.02, 0.02)
bpy.ops.mesh.primitive_plane_add(size=6.0)
bpy.ops.mesh.primitive_cube_add(size=0.8, location=(0.0, 0.0, 0.4))
# A second box beside a small area light that shines down at it from the side (+x): the
# floor behind the box (-x) is in its shadow, the floor on the light's side is not.
bpy.ops.mesh.primitive_cube_add(size=0.4, location=(1.5, -1.5, 0.2))
area = bpy.data.objects.new("Area", bpy.data.lights.new("Area", "AREA"))
area.data.energy = 4.0
area.data.size = 0.2
area.location = (2.0, -1.5, 0.5)
scene.collection.objects.link(area)
# A textured tile in the sun: a 2 x 1 image, red on its left half, blue on its right (u from 0
# to 1 along +x), so that the page must carry the texture through glTF to show both.
# A wall 6 cm thin, 0.6 m high, across the sun (its -x face sunlit, its +x face towards the
# camera), far thinner than the grid's 0.5 m cells: it stands 5 cm inside the cell whose
# vertices lie at x = -1.75 (its sunlit side) and -1.25 (its shaded side).
bpy.ops.mesh.primitive_cube_add(size=1.0, location=(-1.7, -1.5, 0.3), scale=(0.06, 2.0, 0.6))
bpy.ops.mesh.primitive_plane_add(size=0.8, location=(-1.5, 1.5, 0.01))
image = bpy.data.images.new("Tile", 2, 1)
image.pixels = [1.0, 0.0, 0.0, 1.0, 0.0, 0.0, 1.0, 1.0]
image.pack()
material = bpy.data.materials.new("Tile")
material.use_nodes = True
texture = material.node_tree.nodes.new("ShaderNodeTexImage")
texture.image = image
texture.interpolation = "Closest"
material.node_tree.links.new(texture.outputs["Color"],
                             material.node_tree.nodes["Principled BSDF"].inputs["Base Color"])
bpy.context.active_object.data.materials.append(material)
# A third box, lit from the side (+x) by a spot light with Cast Shadow off aimed 45 degrees
# down at it: the floor behind the box (-x) gets its light as the floor beside it does.
bpy.ops.mesh.primitive_cube_add(size=0.4, location=(1.5, 2.5, 0.2))
spot = bpy.data.objects.new("Unshadowed", bpy.data.lights.new("Unshadowed", "SPOT"))
spot.data.energy = 25.0
spot.data.spot_size = 1.5707963267948966
spot.data.spot_blend = 0.0
spot.data.shadow_soft_size = 0.0
if hasattr(spot.data, "cycles") and hasattr(spot.data.cycles, "cast_shadow"):
    spot.data.cycles.cast_shadow = False  # Blender 3.x
else:
    spot.data.use_shadow = False  # 4.0 on
spot.location = (2.0, 2.5, 0.5)
spot.rotation_euler = (0.0, 0.7853981633974483, 0.0)  # its -Z towards (-1, 0, -1)
scene.collection.objects.link(spot)
# A pane of clear glass (Principled transmission 1) held 0.6 m over the floor in the sun: the
# floor it would shade if it were opaque (Blender (0.1, -2.5, 0)) stays sunlit.
bpy.ops.mesh.primitive_plane_add(size=0.6, location=(-0.5, -2.5, 0.6))
glass = bpy.data.materials.new("Glass")
glass.use_nodes = True
bsdf = glass.node_tree.nodes["Principled BSDF"]
(bsdf.inputs.get("Transmission Weight") or bsdf.inputs["Transmission"]).default_value = 1.0
bsdf.inputs["Roughness"].default_value = 0.0
bpy.context.active_object.data.materials.append(glass)
# A sun shining towards +x, 45 degrees from the zenith (a sun points along its local -Z).
lamp = bpy.data.objects.new("Sun", bpy.data.lights.new("Sun", "SUN"))
lamp.data.energy = 3.0
lamp.data.angle = 0.0
lamp.rotation_euler = (0.0, -0.7853981633974483, 0.0)
lamp.location = (0.0, 0.0, 3.0)
scene.collection.objects.link(lamp)
camera = bpy.data.objects.new("Camera", bpy.data.cameras.new("Camera"))
camera.location = (0.0, 0.0, 8.0)
camera.data.angle = 0.9
scene.collection.objects.link(camera)
scene.camera = camera
scene.render.resolution_x, scene.render.resolution_y = {width}, {height}
bakegi.bake(target="GRID", method="pathtrace", grid_cell_size=0.5, grid_rays=16,
            grid_folder={work!r}, objects="VISIBLE")
print("web", bakegi.export_web({site!r}), flush=True)
# The box (0.8 m high, its far side at x = 0.4) shades the floor from x = 0.4 to 1.2; a
# point in that shadow, and one in the open on the lit side (a sun turned the wrong way
# would light the first or shade the second).
# The tile's red and blue halves at the middle of each texel. The points are in the page's
# frame, glTF's: Blender's (x, y, z) is (x, z, -y) there.
# Behind the third box from the unshadowed spot, and beside the box (Blender (1.15, 2.5, 0) and
# (1.5, 1.95, 0)), both in the sun and in the spot's cone.
# The area light's shadowed and lit floor points, both in the sun (Blender (1.15, -1.5, 0) and
# (2.5, -1.5, 0)); low and weak, it adds under a tenth of the sun's light at the first box's
# shadow.
# A floor point far from the boxes and the lights (Blender (-2.25, 2.25, 0)), under the open
# sky: the grid's light there (white albedo) is the sky's radiance (its bounce off the boxes,
# seen at grazing angles, under a hundredth of it); a grid holding only bounced light gives
# next to nothing.
json.dump({{"sky": 0.02, "sky_floor": [-2.25, 0.0, -2.25],
           "shadowed": [0.8, 0.0, 0.0], "open": [-1.5, 0.0, 0.0],
           "red": [-1.7, 0.01, -1.5], "blue": [-1.3, 0.01, -1.5],
           "area_shadowed": [1.15, 0.0, 1.5], "area_lit": [2.5, 0.0, 1.5],
           "wall_lit": [-2.0, 0.0, 1.5], "wall_shadowed": [-1.45, 0.0, 1.5],
           "unshadowed_behind": [1.15, 0.0, -2.5], "unshadowed_beside": [1.5, 0.0, -1.95],
           "under_glass": [0.1, 0.0, 2.5]}}, open({points!r}, "w"))
"""


def run(command, env=None, timeout=1200):
    print("$", " ".join(command), flush=True)
    return subprocess.run(command, env=env, timeout=timeout)


def junit(path, name, ok, seconds, log):
    suite = ET.Element("testsuite", name="web", tests="1", failures=str(int(not ok)), errors="0",
                       time=f"{seconds:.1f}")
    case = ET.SubElement(suite, "testcase", classname="web", name=name, time=f"{seconds:.1f}")
    if not ok:
        ET.SubElement(case, "failure", message="see the web test log").text = log[-4000:]
    ET.ElementTree(suite).write(path, encoding="utf-8", xml_declaration=True)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--work", default=os.path.join(ROOT, "out", "web_tests"))
    parser.add_argument("--build", default=os.path.join(ROOT, "build"))
    parser.add_argument("--cells", type=int, default=16)
    parser.add_argument("--size", default="480x360")
    parser.add_argument("--fig6", action="store_true")
    parser.add_argument("--junit")
    args = parser.parse_args()
    started = time.time()
    work = os.path.abspath(args.work)
    site = os.path.join(work, "site")
    shutil.rmtree(site, ignore_errors=True)
    os.makedirs(work, exist_ok=True)
    width, height = (int(v) for v in args.size.split("x"))
    reference = os.path.join(work, "light_blender.png")
    script = os.path.join(work, "blender_side.py")
    with open(script, "w") as f:
        f.write(BLENDER_SIDE.format(scenes=os.path.join(ROOT, "scenes"), width=width,
                                    height=height, cells=args.cells, work=work, site=site,
                                    reference=reference))
    build = os.path.abspath(args.build)
    blender = run(["blender", "-b", "--factory-startup", "--addons", "bakegi",
                   "--python-exit-code", "1", "--python", script],
                  env=addon_environment(work, build))
    ok = blender.returncode == 0 and os.path.isfile(reference)
    log = "" if ok else "Blender could not make the scene, its grid, web folder or reference"
    shadow_site = os.path.join(work, "site_shadow")
    shadow_points = os.path.join(work, "shadow_points.json")
    shutil.rmtree(shadow_site, ignore_errors=True)
    if ok:
        script = os.path.join(work, "blender_shadow.py")
        with open(script, "w") as f:
            f.write(SHADOW_SIDE.format(width=width, height=height, work=work, site=shadow_site,
                                       points=shadow_points))
        blender = run(["blender", "-b", "--factory-startup", "--addons", "bakegi",
                       "--python-exit-code", "1", "--python", script],
                      env=addon_environment(work, build))
        ok = blender.returncode == 0 and os.path.isfile(shadow_points)
        log = "" if ok else "Blender could not make the shadow scene or its web folder"
    if ok:
        command = ["node", os.path.join(ROOT, "addon", "web", "test", "run.mjs"), "--cli",
                   os.path.join(build, "bakegi"), "--folder", site, "--out", work,
                   "--reference", reference, "--size", args.size,
                   "--shadow-folder", shadow_site, "--shadow-points", shadow_points]
        if args.fig6:
            command.append("--fig6")
        browser = run(command)
        ok = browser.returncode == 0
        log = "the browser checks failed (see above and results.json)"
    if args.junit:
        junit(args.junit, "streams_and_matches_blender", ok, time.time() - started, log)
    print("WEB OK" if ok else f"WEB FAILED: {log}")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
