"""The UI for real: Blender with a window (under Xvfb), the operator run from it.

    xvfb-run -a blender --factory-startup --enable-event-simulate -p 0 0 800 600 --python blender_tests/test_ui.py

Steps, driven by an application timer (the window keeps drawing in between):
1. build the small Cornell box, in the default layout's 3D viewport look
   through the camera in Material Preview with the scene's light and world;
2. screenshot the viewport once EEVEE has compiled its shaders;
3. start Bake Indirect with INVOKE_DEFAULT (the timer-driven modal), wait
   until it finishes, screenshot again;
4. check that the ceiling got brighter by about what the bake predicts: the
   classic light points down, so the ceiling has no direct light and shows
   only albedo x baked indirect. The prediction is the ceiling's mean of
   albedo x Cycles' indirect (the stored reference) x 2 (the scene's +1 stop
   exposure); the measured increase must be at least half of it and at
   most twice it (8-bit screenshots, EEVEE's display transform, corners
   interpolated over faces). Before the bake the ceiling must be dark;
5. start a long bake, press Esc (simulated event), and check the scene is
   exactly as before that bake.
Screenshots are saved in $BAKEGI_TEST_OUTPUT for the docs.
"""

import json
import os
import sys
import tempfile
import time
import traceback

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import common  # noqa: E402

import bpy  # noqa: E402
import numpy  # noqa: E402
from bpy_extras.view3d_utils import location_3d_to_region_2d  # noqa: E402

import cornell_box  # noqa: E402
import metrics  # noqa: E402

DEADLINE_SECONDS = 420
BAKE_WAIT_SECONDS = 120
BAKE_SAMPLES = 256


def srgb_to_linear(c):
    c = numpy.asarray(c, dtype=numpy.float64)
    return numpy.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4)


class UiTest:
    def __init__(self):
        self.cases = []
        self.start = time.perf_counter()
        self.output = common.output_dir()
        self.steps = self.run()

    # --- plumbing -------------------------------------------------------
    def tick(self):
        """Application timer: advance the test by one step; the value returned is the next delay."""
        try:
            if time.perf_counter() - self.start > DEADLINE_SECONDS:
                raise TimeoutError(f"the UI test did not finish in {DEADLINE_SECONDS} s")
            return next(self.steps)
        except StopIteration:
            self.finish()
        except Exception:
            self.cases.append({"name": "test_ui", "status": "error", "seconds": 0.0, "message": traceback.format_exc()})
            print(traceback.format_exc())
            self.finish()
        return None

    def finish(self):
        summary = common.write_results(self.cases, time.perf_counter() - self.start)
        for case in self.cases:
            print(f"{case['status'].upper()}: {case['name']} ({case['seconds']:.1f} s) {case['message']}")
        sys.stdout.flush()
        os._exit(1 if summary["failures"] + summary["errors"] else 0)

    def record(self, name, started, failures):
        status = "failed" if failures else "passed"
        self.cases.append({"name": name, "status": status, "seconds": round(time.perf_counter() - started, 2),
                           "message": "; ".join(failures)})

    def bake_from_window(self, failures):
        """Bake Indirect as a click starts it (the timer-driven modal); yields until it ends."""
        from bakegi.ui import operators

        with self.override():
            result = bpy.ops.bakegi.bake_indirect("INVOKE_DEFAULT")
        if result != {"RUNNING_MODAL"}:
            failures.append(f"operator returned {result}")
        bake_started = time.perf_counter()
        while operators.runtime["running"] and time.perf_counter() - bake_started < BAKE_WAIT_SECONDS:
            yield 0.2
        if operators.runtime["running"]:
            failures.append(f"the operator still runs after {BAKE_WAIT_SECONDS} s")

    def override(self):
        return bpy.context.temp_override(window=self.window, area=self.area, region=self.region)

    def screenshot(self, name):
        path = os.path.join(self.output, name)
        with bpy.context.temp_override(window=self.window, area=self.area):
            bpy.ops.screen.screenshot_area(filepath=path)
        image = bpy.data.images.load(path, check_existing=False)
        width, height = image.size
        pixels = numpy.empty(width * height * 4, dtype=numpy.float32)
        image.pixels.foreach_get(pixels)
        bpy.data.images.remove(image)
        return pixels.reshape(height, width, 4)[:, :, :3]  # rows bottom-up, like window coordinates

    def wait_for_viewport(self):
        """Yield delays until EEVEE has compiled its shaders and the viewport image is stable."""
        previous = None
        for _ in range(120):
            yield 1.0
            if bpy.app.is_job_running("SHADER_COMPILATION"):
                continue
            pixels = self.screenshot("_probe.png")
            if previous is not None and numpy.abs(pixels - previous).max() < 2.0 / 255.0:
                return
            previous = pixels

    def ceiling_pixels(self):
        """Area-image pixel positions of ceiling points away from its edges (the light is not drawn)."""
        rv3d = self.area.spaces.active.region_3d
        offset = numpy.array([self.region.x - self.area.x, self.region.y - self.area.y])
        positions = []
        for x in numpy.linspace(-0.8, 0.8, 9):
            for y in numpy.linspace(-0.8, 0.8, 9):
                p = location_3d_to_region_2d(self.region, rv3d, (x, y, 1.999))
                if p is not None:
                    positions.append(numpy.round(numpy.array(p) + offset).astype(int))
        return positions

    @staticmethod
    def mean_linear(pixels, positions):
        values = [srgb_to_linear(pixels[y, x]) for x, y in positions
                  if 0 <= y < pixels.shape[0] and 0 <= x < pixels.shape[1]]
        return float(numpy.mean([metrics.luminance(v)[0] for v in values])), len(values)

    # --- the test -------------------------------------------------------
    def run(self):
        started = time.perf_counter()
        bakegi = common.enable_addon()
        from bakegi.ui import operators

        common.new_empty_scene()
        objects = cornell_box.build_cornell_box(cornell_box.TEST_SUBDIVISIONS)
        scene = bpy.context.scene
        scene.eevee.taa_samples = 8
        scene.bakegi.objects = "VISIBLE"
        scene.bakegi.samples = BAKE_SAMPLES
        yield 0.5

        self.window = bpy.context.window_manager.windows[0]
        # Close the splash screen (a file given on the command line would skip it, but the
        # scene is built here): Esc, through the event simulation the runner enables.
        self.window.event_simulate(type="ESC", value="PRESS")
        self.window.event_simulate(type="ESC", value="RELEASE")
        yield 0.5
        # The default layout's viewport (screen_full_area from a timer crashes Blender 3.4).
        self.area = max((a for a in self.window.screen.areas if a.type == "VIEW_3D"), key=lambda a: a.width * a.height)
        self.region = next(r for r in self.area.regions if r.type == "WINDOW")
        space = self.area.spaces.active
        space.shading.type = "MATERIAL"
        space.shading.use_scene_lights = True
        space.shading.use_scene_world = True
        space.overlay.show_overlays = False
        space.show_gizmo = False
        space.show_region_toolbar = False
        space.show_region_header = False
        space.show_region_ui = False
        space.show_region_tool_header = False
        space.region_3d.view_perspective = "CAMERA"
        with self.override():
            bpy.ops.view3d.view_center_camera()
        with self.override():
            bpy.ops.ed.undo_push(message="Cornell box")  # the state undo must return to
        yield from self.wait_for_viewport()

        positions = self.ceiling_pixels()
        before_pixels = self.screenshot("ui_before_bake.png")
        before, count = self.mean_linear(before_pixels, positions)

        before_bake_snapshot = common.scene_snapshot()
        with self.override():
            result = bpy.ops.bakegi.bake_indirect("INVOKE_DEFAULT")
        failures = [] if result == {"RUNNING_MODAL"} else [f"operator returned {result}"]
        saw_running = operators.runtime["running"]
        bake_started = time.perf_counter()
        while operators.runtime["running"] and time.perf_counter() - bake_started < BAKE_WAIT_SECONDS:
            yield 0.2
        bake_seconds = time.perf_counter() - bake_started
        if operators.runtime["running"]:
            failures.append(f"the operator still runs after {BAKE_WAIT_SECONDS} s")
        if common.ATTRIBUTE not in objects["Ceiling"].data.color_attributes:
            failures.append("no BakeGI_Indirect on the ceiling after the operator finished")
        yield from self.wait_for_viewport()
        after_pixels = self.screenshot("ui_after_bake.png")
        after, _ = self.mean_linear(after_pixels, positions)

        reference, sidecar = common.load_reference("cornell_indirect")
        start = 0
        for name, n in sidecar["objects"]:
            if name == "Ceiling":
                ceiling = reference[start:start + n]
            start += n
        albedo = numpy.array(cornell_box.WHITE)
        predicted = float(metrics.luminance(ceiling * albedo).mean()) * 2.0 ** scene.view_settings.exposure
        increase = after - before
        print(f"ui: {count} ceiling samples; linear luminance before {before:.4f}, after {after:.4f}, "
              f"predicted increase {predicted:.4f}; bake {bake_seconds:.1f} s (running seen: {saw_running})")
        if count < 20:
            failures.append(f"only {count} ceiling points on screen: the view is not the camera's")
        if before > 0.25 * predicted:
            failures.append(f"the ceiling is already bright before the bake ({before:.4f})")
        if not 0.5 * predicted <= increase <= 2.0 * predicted:
            failures.append(f"ceiling brightness rose by {increase:.4f}, predicted {predicted:.4f}")
        changed = numpy.abs(after_pixels - before_pixels).max(axis=2) > 8.0 / 255.0
        print(f"ui: {100 * changed.mean():.1f}% of the viewport's pixels changed")
        self.record("test_ui.bake_from_window_changes_material_preview", started, failures)

        # Undo (Ctrl+Z's operator, from the window) takes the bake back; redo brings it again.
        started = time.perf_counter()
        failures = []
        after_bake_snapshot = common.scene_snapshot()
        with self.override():
            bpy.ops.ed.undo()
        yield 0.5
        differences = common.snapshot_difference(before_bake_snapshot, common.scene_snapshot())
        if differences:
            failures.append("undo did not restore the scene: " + "; ".join(differences[:10]))
        with self.override():
            bpy.ops.ed.redo()
        yield 0.5
        differences = common.snapshot_difference(after_bake_snapshot, common.scene_snapshot())
        if differences:
            failures.append("redo did not bring the bake back: " + "; ".join(differences[:10]))
        self.record("test_ui.undo_and_redo_of_the_bake", started, failures)
        scene = bpy.context.scene  # undo reloads data: old references are stale

        # Esc cancels a running bake and leaves the scene exactly as it was.
        started = time.perf_counter()
        failures = []
        scene.bakegi.quality = "SAMPLES"  # a fixed count, so that the bake is long
        scene.bakegi.samples = 1 << 22
        before_snapshot = common.scene_snapshot()
        with self.override():
            result = bpy.ops.bakegi.bake_indirect("INVOKE_DEFAULT")
        if result != {"RUNNING_MODAL"}:
            failures.append(f"operator returned {result}")
        # Wait on state, not the clock: on a loaded machine the bake may take seconds to
        # start tracing (the guard only ends a hang).
        invoked_at = time.perf_counter()
        while (operators.runtime["running"] and "tracing" not in operators.runtime["text"]
               and time.perf_counter() - invoked_at < 120.0):
            yield 0.1
        if not operators.runtime["running"]:
            failures.append("the long bake ended before Esc: " + operators.runtime["text"])
        self.window.event_simulate(type="ESC", value="PRESS")
        self.window.event_simulate(type="ESC", value="RELEASE")
        escape_at = time.perf_counter()
        while operators.runtime["running"] and time.perf_counter() - escape_at < 60.0:
            yield 0.1
        cancel_seconds = time.perf_counter() - escape_at
        if operators.runtime["running"]:
            failures.append("the bake still runs 60 s after Esc")
        differences = common.snapshot_difference(before_snapshot, common.scene_snapshot())
        if differences:
            failures.append("the scene changed after Esc: " + "; ".join(differences[:10]))
        print(f"ui: Esc stopped the bake in {cancel_seconds:.2f} s")
        scene.bakegi.quality = "GOOD"
        self.record("test_ui.escape_cancels_and_changes_nothing", started, failures)
        self.screenshot("ui_after_cancel.png")

        yield from self.live_indirect(scene, objects)
        # The live section steps the undo history: data is reloaded, old references are stale.
        scene = bpy.context.scene
        objects = {name: bpy.data.objects[name] for name in objects}
        yield from self.lightmap(scene, objects, before, predicted, positions)
        yield from self.grid(scene, before, predicted, positions)
        yield from self.preview_engine(scene, positions)
        yield from self.sky_world(bpy.context.scene)
        os.remove(os.path.join(self.output, "_probe.png"))

    def sky_world(self, scene):
        """Bake Indirect from the window under a Sky Texture world: the export renders the
        world with Cycles (world_render.py) from inside the operator, and the bake reads it."""
        import json

        started = time.perf_counter()
        failures = []
        world = scene.world
        tree = world.node_tree
        sky = tree.nodes.new("ShaderNodeTexSky")
        background = next(n for n in tree.nodes if n.type == "BACKGROUND")
        tree.links.new(sky.outputs["Color"], background.inputs["Color"])
        scene.bakegi.method = "pathtrace"
        scene.bakegi.target = "CORNER"
        scene.bakegi.quality = "SAMPLES"
        scene.bakegi.samples = 16
        yield from self.bake_from_window(failures)
        report = json.loads(scene.bakegi.last_report or "{}")
        world_warnings = [w for w in report.get("warnings", []) if "world" in w]
        if world_warnings:
            failures.append(f"world warnings: {world_warnings}")
        if len(bpy.data.scenes) != 1:
            failures.append(f"{len(bpy.data.scenes)} scenes after the bake: the scratch scene stayed")
        print(f"ui: Sky Texture world baked from the window: {report.get('seconds', {})}")
        tree.nodes.remove(sky)
        self.record("test_ui.sky_world_baked_from_the_window", started, failures)

    def lightmap(self, scene, objects, before, predicted, positions):
        """Bake Indirect with the Lightmap Textures target from the window: Material Preview
        must show the indirect light through the lightmap atlas (the hook's image branch),
        raising the ceiling by about what the bake predicts, as for the color attribute."""
        started = time.perf_counter()
        failures = []
        with self.override():
            bpy.ops.bakegi.remove_bake()  # the attribute bake and its hook go first
        settings = scene.bakegi
        settings.live_indirect = False
        # The live step moved the light and doubled its power: put it back, so that the
        # prediction (the first bake's light) holds.
        light = bpy.data.objects["CeilingLight"]
        light.location.x -= 0.4
        light.data.energy /= 2.0
        settings.method = "antiradiance"
        settings.target = "LIGHTMAP"
        settings.texels_per_meter = 24.0
        yield from self.bake_from_window(failures)
        ceiling = bpy.data.objects["Ceiling"]
        if ceiling.get("bakegi_lightmap_weight") is None:
            failures.append("the ceiling has no lightmap tile after the bake")
        if common.ATTRIBUTE in ceiling.data.color_attributes:
            failures.append("the ceiling still has the color attribute")
        yield from self.wait_for_viewport()
        pixels = self.screenshot("ui_lightmap.png")
        after, _ = self.mean_linear(pixels, positions)
        increase = after - before
        print(f"ui: lightmap bake, ceiling luminance {after:.4f} (before any bake {before:.4f}), "
              f"predicted increase {predicted:.4f}; {settings.last_result}")
        if not 0.5 * predicted <= increase <= 2.0 * predicted:
            failures.append(f"with the lightmap the ceiling rose by {increase:.4f}, predicted "
                            f"{predicted:.4f}")
        self.record("test_ui.lightmap_shows_in_material_preview", started, failures)

    def grid(self, scene, before, predicted, positions):
        """Bake Grid from the window (Target: Irradiance Grid), then Apply Grid: Material
        Preview must show the grid's light on the room, raising the ceiling by about what the
        bake predicts, as the attribute and lightmap bakes do."""
        started = time.perf_counter()
        failures = []
        with self.override():
            bpy.ops.bakegi.remove_bake()  # the lightmap and its hook go first
        settings = scene.bakegi
        settings.method = "pathtrace"
        settings.target = "GRID"
        settings.grid_cell_size = 0.125
        settings.grid_rays = 32
        settings.grid_folder = tempfile.mkdtemp(prefix="bakegi_ui_grid_")
        settings.objects = "VISIBLE"
        yield from self.bake_from_window(failures)
        from bakegi.ui import report_text
        if not report_text.grid_details(json.loads(settings.last_report or "{}")):
            failures.append(f"the panel has no grid to show after Bake Grid: {settings.last_result}")
        with self.override():
            result = bpy.ops.bakegi.apply_grid()
        if result != {"FINISHED"}:
            failures.append(f"Apply Grid returned {result}")
        yield from self.wait_for_viewport()
        pixels = self.screenshot("ui_grid.png")
        after, _ = self.mean_linear(pixels, positions)
        increase = after - before
        print(f"ui: grid, ceiling luminance {after:.4f} (before any bake {before:.4f}), "
              f"predicted increase {predicted:.4f}; {settings.last_result}")
        if not 0.5 * predicted <= increase <= 2.0 * predicted:
            failures.append(f"with the grid the ceiling rose by {increase:.4f}, predicted "
                            f"{predicted:.4f}")
        self.record("test_ui.grid_shows_in_material_preview", started, failures)
        yield from self.grid_follow(scene)

    def grid_follow(self, scene):
        """Follow Moves from the window: with the toggle on, a lit box moved as a user would
        (a property change) is lit from the grid again by the timer once it rests, and the
        panel says so."""
        started = time.perf_counter()
        failures = []
        follow = sys.modules["bakegi.grid_follow"]
        scene.bakegi.grid_follow = True
        state = follow._states.get(scene.name)
        if state is None:
            failures.append("Apply Grid left nothing for Follow Moves to follow")
            self.record("test_ui.grid_follows_a_moved_box", started, failures)
            return
        box = next(o for o in bpy.data.objects if o.name in state.matrices and "Box" in o.name)
        before = common.read_color_attribute([box.name])
        updates_before = state.updates
        box.location.z += 0.5
        moved_at = time.perf_counter()
        while ((state.updates == updates_before or state.pending) and not state.message
               and time.perf_counter() - moved_at < 60.0):
            yield 0.02
        update_seconds = time.perf_counter() - moved_at
        after = common.read_color_attribute([box.name])
        text = follow.status_text(scene)
        if state.message:
            failures.append("Follow Moves stopped: " + state.message)
        elif state.updates == updates_before:
            failures.append("no re-apply 60 s after the box moved")
        elif numpy.array_equal(after, before):
            failures.append("the box's attribute did not change after it moved")
        if "update(s)" not in text:
            failures.append(f"the panel's follow line reads {text!r}")
        print(f"ui: Follow Moves re-applied the grid {update_seconds * 1000:.0f} ms after "
              f"'{box.name}' moved (at rest for {follow.DEBOUNCE_SECONDS * 1000:.0f} ms); {text}")
        box.location.z -= 0.5
        scene.bakegi.grid_follow = False
        self.record("test_ui.grid_follows_a_moved_box", started, failures)

    def live_indirect(self, scene, objects):
        """Live indirect from the window: a meshless bake with the toggle on, then a light
        moved as a user would (a property change); the timer must relight and write the
        attribute within seconds, and the panel must show the update time."""
        started = time.perf_counter()
        failures = []
        live = sys.modules["bakegi.live"]

        settings = scene.bakegi
        settings.method = "meshless"
        settings.meshless_levels = 3  # a quicker precompute: this checks the plumbing
        settings.use_cache = False
        settings.live_indirect = True
        yield from self.bake_from_window(failures)
        state = live.state()
        if state is None:
            failures.append("no live state after the meshless bake with Live Indirect on")
            self.record("test_ui.live_indirect_follows_a_moved_light", started, failures)
            return
        # The bake's own writes reach the depsgraph handler first: wait until live indirect
        # is idle (state, not the clock; the guards only end a hang).
        yield 0.1
        idle_from = time.perf_counter()
        while ((state.pending or state.running is not None) and not state.paused
               and time.perf_counter() - idle_from < 60.0):
            yield 0.05
        updates_before = state.updates
        before = common.read_color_attribute(["Floor", "BackWall"])
        light = bpy.data.objects["CeilingLight"]
        light.location.x += 0.4
        light.data.energy *= 2.0
        moved_at = time.perf_counter()
        while ((state.updates == updates_before or state.pending or state.running is not None)
               and not state.paused and time.perf_counter() - moved_at < 60.0):
            yield 0.02
        update_seconds = time.perf_counter() - moved_at
        after = common.read_color_attribute(["Floor", "BackWall"])
        if state.paused:
            failures.append("live indirect paused: " + state.paused)
        elif state.updates == updates_before:
            failures.append("no live update 60 s after the light moved")
        elif abs(after.sum() / before.sum() - 1.0) < 0.2:
            failures.append("the attribute did not follow the light (2x power)")
        text = live.status_text()
        if "updated in" not in text:
            failures.append(f"the panel's live line reads {text!r}")
        print(f"ui: live update written {update_seconds * 1000:.0f} ms after the light moved "
              f"(debounce {live.DEBOUNCE_SECONDS * 1000:.0f} ms, timer polls); {text}")
        yield from self.wait_for_viewport()
        self.screenshot("ui_live_after_move.png")
        # The relight is an undo step: Ctrl+Z steps back over it (and then over the move)
        # without losing the bake: the attribute stays on every target.
        moved_x = light.location.x
        with self.override():
            bpy.ops.ed.undo()
        yield 0.5
        if abs(bpy.data.objects["CeilingLight"].location.x - (moved_x - 0.4)) > 1e-4:
            failures.append("Ctrl+Z did not step back over the moved light's relight")
        for name in ("Floor", "BackWall"):
            if common.ATTRIBUTE not in bpy.data.objects[name].data.color_attributes:
                failures.append(f"undoing the live relight lost the bake on {name}")
        scene = bpy.context.scene  # undo reloads data: old references are stale
        settings = scene.bakegi
        settings.live_indirect = False
        if live.state() is not None:
            failures.append("turning Live Indirect off kept the precomputation")
        self.record("test_ui.live_indirect_follows_a_moved_light", started, failures)

    def preview_engine(self, scene, positions):
        """BakeGI Preview in the viewport's rendered shading: the ceiling (lit only by the
        bounce) shows light, and moving the light changes the picture without a bake."""
        started = time.perf_counter()
        failures = []
        space = self.area.spaces.active
        previous_engine = scene.render.engine
        scene.render.engine = "BAKEGI_PREVIEW"
        space.shading.type = "RENDERED"
        yield from self.wait_for_viewport()
        first = self.screenshot("ui_preview_engine.png")
        ceiling, count = self.mean_linear(first, positions)
        if count == 0 or not ceiling > 0.0:
            failures.append(f"the ceiling is black in BakeGI Preview ({ceiling}, {count} pixels)")
        light = bpy.data.objects["CeilingLight"]
        light.location.x += 0.6
        yield from self.wait_for_viewport()
        moved = self.screenshot("ui_preview_engine_moved.png")
        change = float(numpy.abs(moved - first).mean())
        if not change > 1.0 / 255.0:
            failures.append(f"moving the light changed the preview by {change:.5f} only")
        print(f"ui: BakeGI Preview ceiling {ceiling:.4f} over {count} pixels; moving the light "
              f"changed the picture by {change * 255:.1f}/255 on average")
        light.location.x -= 0.6
        space.shading.type = "MATERIAL"
        scene.render.engine = previous_engine
        self.record("test_ui.preview_engine_follows_a_moved_light", started, failures)


test = UiTest()
bpy.app.timers.register(test.tick, first_interval=1.0)
