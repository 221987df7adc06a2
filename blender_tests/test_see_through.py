"""See-through surfaces in the bake, against Cycles: a blocker over the floor made half
transparent (Principled Alpha 0.5) or cut out by an image's alpha (a checker of holes) casts
the shadow Cycles' transparent shadows cast; a glass blocker (Principled Transmission 1) passes
1 - F(theta) of a lamp's light, Fresnel at the angle (Cycles' shadow rays stop at glass: a
lamp behind glass reaches it only as a caustic, so there the check is the model's own number); and a room lit by a
uniform sky through a glass window pane (a 1 cm slab) gets the light Cycles' paths bring in
through it (Cycles with Filter Glossy off: its default, 1, blurs the pane after a diffuse
bounce and halves that light)."""

import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import common  # noqa: E402

import bpy  # noqa: E402
import numpy  # noqa: E402

import light_units  # noqa: E402  (scenes/light_units.py)
import metrics  # noqa: E402

# Cycles' direct light at 1,024 samples: about 0.3% noise on these receivers
# (test_ray_visibility); bakegi's "direct" method at 2,048 samples, two seeds.
CYCLES_SAMPLES = 1024
BAKEGI_SAMPLES = 2048
RECEIVERS = ("Floor", "Wall")
# The glass window room: total light (direct + indirect), both renderers, two seeds each.
GLASS_SAMPLES = 2048  # the blocker's own light is not compared


def principled_material(name):
    material = bpy.data.materials.new(name)
    material.use_nodes = True
    node = next(n for n in material.node_tree.nodes if n.type == "BSDF_PRINCIPLED")
    node.inputs["Base Color"].default_value = (*light_units.RECEIVER_ALBEDO, 1.0)
    return material, node


def fresnel(cosine, eta):
    """The exact unpolarized dielectric Fresnel reflectance at |cos theta| (numpy)."""
    c = numpy.clip(cosine, 0.0, 1.0)
    g = numpy.sqrt(eta * eta - 1.0 + c * c)
    a = (g - c) / (g + c)
    b = (c * (g + c) - 1.0) / (c * (g - c) + 1.0)
    return 0.5 * a * a * (1.0 + b * b)


def checker_mask(cells=4, size=32):
    """A size x size RGBA image, white, whose alpha is a checker of cells x cells: holes and
    solid squares of equal area."""
    image = bpy.data.images.new("holes", size, size, alpha=True, float_buffer=True)
    ij = numpy.indices((size, size))
    alpha = ((ij[0] * cells // size + ij[1] * cells // size) % 2).astype(numpy.float32)
    pixels = numpy.ones((size, size, 4), numpy.float32)
    pixels[:, :, 3] = alpha
    image.pixels.foreach_set(pixels.ravel())
    image.alpha_mode = "STRAIGHT"
    return image


def add_planar_uvs(obj):
    """UVs of the blocker's x, y over its extent (0..1)."""
    mesh = obj.data
    layer = mesh.uv_layers.new(name="UVMap")
    xs = [v.co.x for v in mesh.vertices]
    ys = [v.co.y for v in mesh.vertices]
    for loop in mesh.loops:
        co = mesh.vertices[loop.vertex_index].co
        layer.data[loop.index].uv = ((co.x - min(xs)) / (max(xs) - min(xs)),
                                     (co.y - min(ys)) / (max(ys) - min(ys)))


def glass_window_room(pane):
    """A closed grey room [-2, 2] x [-2, 2] x [0, 3] under a uniform white sky, with a 2 x 1.5 m
    window in its +x wall, glazed with a 1 cm slab of clear Principled glass (`pane`) or open.
    Returns the floor (8 x 8 quads)."""
    import cornell_box
    cornell_box.clear_scene()
    scene = bpy.context.scene
    collection = scene.collection
    grey = cornell_box.diffuse_material("Grey", (0.6, 0.6, 0.6))
    v, f = [], []
    cornell_box.grid_faces((-2, -2, 0), (4, 0, 0), (0, 4, 0), 8, 8, v, f)
    floor = cornell_box.mesh_object("Floor", v, f, grey, collection)
    v, f = [], []
    cornell_box.grid_faces((-2, 2, 3), (4, 0, 0), (0, -4, 0), 4, 4, v, f)  # ceiling
    cornell_box.grid_faces((-2, -2, 0), (0, 4, 0), (0, 0, 3), 4, 3, v, f)  # -x wall
    cornell_box.grid_faces((-2, -2, 0), (0, 0, 3), (4, 0, 0), 3, 4, v, f)  # -y wall
    cornell_box.grid_faces((-2, 2, 0), (4, 0, 0), (0, 0, 3), 4, 3, v, f)  # +y wall
    cornell_box.mesh_object("Walls", v, f, grey, collection)
    v, f = [], []
    cornell_box.grid_faces((2, -2, 0), (0, 0, 3), (0, 4, 0), 6, 8, v, f)  # +x wall
    v, f = cornell_box.without_faces(v, f, lambda c: abs(c[1]) < 1.0 and 1.0 < c[2] < 2.5)
    cornell_box.mesh_object("WindowWall", v, f, grey, collection)
    cornell_box.set_black_world(scene, color=(1.0, 1.0, 1.0), strength=1.0)
    if pane:
        bpy.ops.mesh.primitive_cube_add(size=1.0, location=(2.025, 0.0, 1.75))
        glass = bpy.context.active_object
        glass.name = "Pane"
        glass.scale = (0.01, 2.1, 1.6)
        bpy.ops.object.transform_apply(scale=True)
        material, node = principled_material("Glass")
        (node.inputs.get("Transmission Weight") or node.inputs["Transmission"]).default_value = 1.0
        node.inputs["Roughness"].default_value = 0.0
        node.inputs["Base Color"].default_value = (1.0, 1.0, 1.0, 1.0)
        glass.data.materials.append(material)
    return floor


class SeeThrough(common.AddonCase):

    def setUp(self):
        common.new_empty_scene()
        self.built = light_units.build_light_scene("POINT")
        self.receivers = [self.built[name] for name in RECEIVERS]
        self.blocker = self.built["Blocker"]
        self.opaque_material = self.blocker.data.materials[0]

    def bake(self, seed=0, samples=BAKEGI_SAMPLES):
        blockers = [] if self.blocker.hide_render else [self.blocker]
        report = self.bakegi.bake(method="direct", samples=samples, seed=seed, target="CORNER",
                                  objects=self.receivers + blockers, estimate_error=False)
        values = common.read_color_attribute(self.receivers, domain="CORNER")
        return values, report

    def set_blocker_material(self, material):
        self.blocker.data.materials.clear()
        self.blocker.data.materials.append(material)

    def against_cycles(self, what):
        import cycles_bake
        see_through = self.blocker.data.materials[0]
        self.set_blocker_material(self.opaque_material)
        opaque = self.bake()[0]
        self.set_blocker_material(see_through)
        reference, seconds = cycles_bake.cycles_direct(self.receivers, CYCLES_SAMPLES)
        halves = [self.bake(seed)[0] for seed in (0, 1)]
        mean = 0.5 * (halves[0] + halves[1])
        error = metrics.relative_rmse(mean, reference)
        noise = metrics.noise_from_halves(halves[0], halves[1])
        error_opaque = metrics.relative_rmse(opaque, reference)
        print(f"{what}: Cycles {CYCLES_SAMPLES} samples {seconds:.1f} s; bakegi "
              f"{100 * error:.2f}% (its noise {100 * noise:.2f}%); read as opaque "
              f"{100 * error_opaque:.2f}%")
        # test_light_units' tolerance for direct light; an opaque blocker is far off.
        self.assertLessEqual(error, 0.02)
        self.assertGreater(error_opaque, 0.05)

    def test_a_half_transparent_blocker_against_cycles(self):
        material, node = principled_material("Veil")
        self.set_blocker_material(material)
        opaque_values = self.bake()[0]
        node.inputs["Alpha"].default_value = 0.5
        values, report = self.bake()
        self.assertGreater(values.sum(), opaque_values.sum())
        self.assertFalse([w for w in report["warnings"] if "Veil" in w], report["warnings"])
        self.against_cycles("alpha 0.5")

    def test_a_cut_out_blocker_against_cycles(self):
        material, node = principled_material("Holes")
        texture = material.node_tree.nodes.new("ShaderNodeTexImage")
        texture.image = checker_mask()
        material.node_tree.links.new(texture.outputs["Alpha"], node.inputs["Alpha"])
        add_planar_uvs(self.blocker)
        self.set_blocker_material(material)
        self.against_cycles("checker of holes")

    def test_a_glass_blocker_passes_its_transmission(self):
        """Under the blocker's middle the floor gets no direct light behind an opaque blocker,
        and behind a glass one what Fresnel lets through at each corner's angle to the lamp,
        1 - F(theta) (the share averages 1 - F_avg over the hemisphere)."""
        from bakegi.export import materials as material_reading
        self.blocker.hide_render = True
        free = self.bake(samples=256)[0]
        self.blocker.hide_render = False
        material, node = principled_material("Pane")
        (node.inputs.get("Transmission Weight") or node.inputs["Transmission"]).default_value = 1.0
        node.inputs["Roughness"].default_value = 0.0
        node.inputs["Base Color"].default_value = (1.0, 1.0, 1.0, 1.0)
        self.set_blocker_material(material)
        glass, report = self.bake()
        info = material_reading.read_material(material)
        f_avg = material_reading.fresnel_hemispherical_average(
            material_reading._principled_f0(node, info, "Pane"))
        self.assertAlmostEqual(info.transmission, 1.0 - f_avg, places=6)
        (node.inputs.get("Transmission Weight") or node.inputs["Transmission"]).default_value = 0.0
        opaque = self.bake(samples=256)[0]
        lum = metrics.REC709_LUMINANCE
        shadow = (opaque @ lum) < 0.02 * (free @ lum)
        self.assertGreater(shadow.sum(), 20, "the blocker casts no full shadow to test in")
        # The lamp's angle at each corner through the (horizontal) blocker.
        lamp = numpy.array(self.built["Light"].location)
        corners = numpy.concatenate([
            numpy.array([tuple(o.matrix_world @ o.data.vertices[loop.vertex_index].co)
                         for loop in o.data.loops]) for o in self.receivers])
        to_lamp = lamp - corners
        cosine = numpy.abs(to_lamp[:, 2]) / numpy.linalg.norm(to_lamp, axis=1)
        passed = 1.0 - fresnel(cosine, info.transmission_ior)
        weights = (free @ lum)[shadow]
        expected = float((weights * passed[shadow]).sum() / weights.sum())
        ratio = float((glass[shadow] @ lum).sum() / weights.sum())
        print(f"glass: {ratio:.4f} of the unblocked light under the blocker; Fresnel says "
              f"{expected:.4f} (1 - F_avg {1.0 - f_avg:.4f})")
        # Each of the 2,048 samples passes or not: the ratio's spread over these corners is
        # under 0.2%; 1% allows for the corners at the shadow's edge.
        self.assertAlmostEqual(ratio, expected, delta=0.01)
        self.assertTrue(any("Pane" in w and "thin glass" in w for w in report["warnings"]),
                        report["warnings"])

    def test_methods_other_than_the_path_tracer_say_so(self):
        """Antiradiance's links and meshless' basis carry light between surfaces without rays
        in parts: with a see-through surface in the scene their report says so; the path
        tracer's does not."""
        material, node = principled_material("Veil")
        node.inputs["Alpha"].default_value = 0.5
        self.set_blocker_material(material)
        objects = self.receivers + [self.blocker]
        for method in ("antiradiance", "pathtrace"):
            report = self.bakegi.bake(method=method, samples=16, target="CORNER",
                                      objects=objects, estimate_error=False)
            said = [w for w in report["warnings"] if "see-through surfaces" in w]
            if method == "pathtrace":
                self.assertFalse(said, report["warnings"])
            else:
                self.assertTrue(any(w.startswith(method) and "path tracer" in w for w in said),
                                report["warnings"])

    def test_a_glass_window_against_cycles(self):
        import cycles_bake
        means = {}
        for pane in (False, True):
            floor = glass_window_room(pane)
            baked = []
            for seed in (0, 1):
                total = 0.0
                for method in ("direct", "pathtrace"):
                    self.bakegi.bake(method=method, samples=GLASS_SAMPLES, seed=seed,
                                     target="CORNER", objects=[floor], estimate_error=False)
                    total = total + common.read_color_attribute([floor], domain="CORNER")
                baked.append(total)
            bpy.context.scene.cycles.blur_glossy = 0.0
            cycles = [cycles_bake.bake_diffuse([floor], {"DIRECT", "INDIRECT"}, GLASS_SAMPLES,
                                               seed=seed)[0] for seed in (0, 1)]
            mean, reference = 0.5 * (baked[0] + baked[1]), 0.5 * (cycles[0] + cycles[1])
            error = metrics.relative_rmse(mean, reference)
            noise = metrics.noise_from_halves(baked[0], baked[1])
            cycles_noise = metrics.noise_from_halves(cycles[0], cycles[1])
            lum = metrics.REC709_LUMINANCE
            means[pane] = (float((mean @ lum).mean()), float((reference @ lum).mean()))
            print(f"window {'glazed' if pane else 'open'}: floor mean bakegi {means[pane][0]:.4f}, "
                  f"Cycles {means[pane][1]:.4f}; error {100 * error:.2f}% (bakegi's noise "
                  f"{100 * noise:.2f}%, Cycles' {100 * cycles_noise:.2f}%)")
            # Both estimates' noise adds: the error is checked against three times it.
            self.assertLessEqual(error, 3.0 * (noise ** 2 + cycles_noise ** 2) ** 0.5 + 0.01)
            self.assertAlmostEqual(means[pane][0] / means[pane][1], 1.0, delta=0.04)
        # The pane passes about (1 - F_avg)^2 of the sky's light, in both.
        print(f"glazed / open: bakegi {means[True][0] / means[False][0]:.3f}, Cycles "
              f"{means[True][1] / means[False][1]:.3f}")
        self.assertGreater(means[True][0] / means[False][0], 0.75)


if __name__ == "__main__":
    common.run_tests(__name__)
