"""bakegi's path tracer agrees with a converged Cycles bake on the Cornell box.

The reference (blender_tests/data/<version>/cornell_indirect.npy, made by
make_references.py) is Cycles' indirect light per face corner of the small
Cornell box, with its own noise recorded in the sidecar (about 0.45 %). bakegi
bakes the same scene twice with different seeds; the two bakes give bakegi's
own noise (their relative RMSE / 2 is the noise of their average), and the
average is compared with the reference under DESIGN.md's metric.

Tolerances:
- agreement, relative RMSE <= 3 % (the issue's bar). Noise takes a known
  part of it: the reference's 0.45 % (65536 samples) and bakegi's average
  of two 8192-sample bakes (~1.0 %; Cycles measures 1.26 % at 8192 samples
  in all), in quadrature ~1.1 % (<= 1.6 % at the noise limit), which leaves
  >= 2.5 % for bias. Real errors are
  far outside: a factor of pi is 68 %, cutting paths at 4 bounces is -7 %
  in the mean (Cycles' own default, measured with make_references.py
  --bounce-study), a colour or albedo mix-up tens of %.
- noise of bakegi's average <= NOISE_LIMIT (1.5 %), checked so a pass is not
  luck of the draw. 2 x 8192 samples take about 50 s on 2 cores.
"""

import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import common  # noqa: E402  (sets sys.path for scenes/ and tools/)

import unittest  # noqa: E402

import cornell_box  # noqa: E402
import metrics  # noqa: E402

# Per-seed samples. Measured on this 2-core machine: see the report in the test output.
SAMPLES = int(os.environ.get("BAKEGI_TEST_CORNELL_SAMPLES", "8192"))
TOLERANCE = 0.03
NOISE_LIMIT = 0.015


class CornellBoxAgainstCycles(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.reference, cls.sidecar = common.load_reference("cornell_indirect")
        common.new_empty_scene()
        cls.bakegi = common.enable_addon()
        cornell_box.build_cornell_box(cls.sidecar["scene"]["subdivisions"])
        cls.names = [name for name, _ in cls.sidecar["objects"]]

    def bake(self, seed):
        report = self.bakegi.bake(method="pathtrace", samples=SAMPLES, seed=seed, target="CORNER", objects="VISIBLE")
        return common.read_color_attribute(self.names, domain="CORNER"), report

    def test_reference_matches_scene(self):
        counts = [count for _, count in self.sidecar["objects"]]
        import bpy

        self.assertEqual(counts, [len(bpy.data.objects[n].data.loops) for n in self.names])
        self.assertLessEqual(self.sidecar["noise_relative_rmse"], 0.01, "the stored reference is not converged")

    def test_pathtrace_agrees_with_cycles(self):
        first, report = self.bake(seed=0)
        second, _ = self.bake(seed=1)
        average = 0.5 * (first + second)
        noise = metrics.noise_from_halves(first, second)
        error = metrics.relative_rmse(average, self.reference)
        error_first = metrics.relative_rmse(first, self.reference)
        mean_ratio = metrics.luminance(average).mean() / metrics.luminance(self.reference).mean()
        print(
            f"cornell: {SAMPLES} samples x 2 seeds, {report['bake_points']} points, "
            f"{report['seconds'].get('total', 0):.2f} s per bake; relative RMSE vs Cycles "
            f"{100 * error:.2f}% (one seed {100 * error_first:.2f}%), bakegi noise {100 * noise:.2f}%, "
            f"reference noise {100 * self.sidecar['noise_relative_rmse']:.2f}%, mean ratio {mean_ratio:.4f}"
        )
        self.assertGreater(noise, 0.0, "two seeds gave identical bakes: the seed is ignored")
        self.assertLessEqual(noise, NOISE_LIMIT, "bakegi's bake is too noisy for a meaningful comparison")
        self.assertLessEqual(error, TOLERANCE)
        # Per object too, so a wrong wall cannot hide behind the others (looser: fewer points, more noise).
        start = 0
        for name, count in self.sidecar["objects"]:
            part = slice(start, start + count)
            start += count
            object_error = metrics.relative_rmse(average[part], self.reference[part])
            self.assertLessEqual(object_error, 2 * TOLERANCE, f"{name}: {100 * object_error:.2f}%")


# The Principled box: 2 x 4096 samples (about 10 s; noise of the average about 1.35 %) against
# a 16384-sample reference (about 0.9 %).
PRINCIPLED_SAMPLES = int(os.environ.get("BAKEGI_TEST_PRINCIPLED_SAMPLES", "4096"))
PRINCIPLED_TOLERANCE = 0.06
PRINCIPLED_NOISE_LIMIT = 0.02


class PrincipledCornellAgainstCycles(unittest.TestCase):
    """The same box with Principled BSDFs (roughness 0.5, a dielectric coat of F0 = 0.04),
    against the Principled of the running version's Cycles: v1 in 3.x (the specular added on
    the diffuse base), v2 in 4.x (layered over it, the base losing what the coat reflects).

    Tolerance 6 %: noise takes about 1.6 % (the reference's ~0.9 %, bakegi's ~1.35 %, in
    quadrature), and the core's glossy lobe (a Phong lobe of the hemispherical Fresnel
    average, export/materials.py) is measured 2-4 % off Cycles' GGX with angular Fresnel (most of it
    on the floor, which gets 8 % less in 4.x: docs/compatibility.md). Real errors are far
    outside: reading v2 as v1 (no layering) or dropping the coat moves the mean 15-20 %.
    """

    @classmethod
    def setUpClass(cls):
        cls.reference, cls.sidecar = common.load_reference("cornell_principled_indirect")
        common.new_empty_scene()
        cls.bakegi = common.enable_addon()
        cornell_box.build_cornell_box(cls.sidecar["scene"]["subdivisions"], surface="PRINCIPLED")
        cls.names = [name for name, _ in cls.sidecar["objects"]]

    def test_pathtrace_agrees_with_cycles_principled(self):
        bakes = []
        for seed in (0, 1):
            report = self.bakegi.bake(method="pathtrace", samples=PRINCIPLED_SAMPLES, seed=seed, target="CORNER",
                                      objects="VISIBLE")
            bakes.append(common.read_color_attribute(self.names, domain="CORNER"))
        average = 0.5 * (bakes[0] + bakes[1])
        noise = metrics.noise_from_halves(*bakes)
        error = metrics.relative_rmse(average, self.reference)
        mean_ratio = metrics.luminance(average).mean() / metrics.luminance(self.reference).mean()
        parts, start = [], 0
        for name, count in self.sidecar["objects"]:
            part = slice(start, start + count)
            start += count
            ratio = metrics.luminance(average[part]).mean() / metrics.luminance(self.reference[part]).mean()
            parts.append((name, metrics.relative_rmse(average[part], self.reference[part]), ratio))
        print(
            f"cornell principled: {PRINCIPLED_SAMPLES} samples x 2 seeds, {report['bake_points']} points; "
            f"relative RMSE vs Cycles {100 * error:.2f}%, bakegi noise {100 * noise:.2f}%, reference noise "
            f"{100 * self.sidecar['noise_relative_rmse']:.2f}%, mean ratio {mean_ratio:.4f}; per object "
            + ", ".join(f"{n} {100 * e:.1f}% ({r:.3f})" for n, e, r in parts))
        self.assertGreater(noise, 0.0, "two seeds gave identical bakes: the seed is ignored")
        self.assertLessEqual(noise, PRINCIPLED_NOISE_LIMIT, "bakegi's bake is too noisy for a meaningful comparison")
        self.assertLessEqual(error, PRINCIPLED_TOLERANCE)
        for name, object_error, _ in parts:
            self.assertLessEqual(object_error, 2 * PRINCIPLED_TOLERANCE, f"{name}: {100 * object_error:.2f}%")


if __name__ == "__main__":
    common.run_tests(__name__)
