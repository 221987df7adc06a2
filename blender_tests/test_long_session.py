"""A long session in one Blender process: 100 bakes alternating methods and targets (corner
and vertex colour attributes, a lightmap, a grid), each followed by Remove Bake. Resident
memory after the 10th bake is the baseline (allocators, caches and the add-on's first use
settle by then); what it grows by over the other 90 must stay under 5% (a leak of a
precomputation, a job, a core scene or an image per bake would exceed it many times). The
memory after every bake is printed for the record (docs/reliability.md)."""

import os
import shutil
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import common  # noqa: E402

BAKES = 100
BASELINE_AFTER = 10
MAX_GROWTH = 0.05


def resident_bytes():
    with open("/proc/self/statm") as f:
        return int(f.read().split()[1]) * os.sysconf("SC_PAGE_SIZE")


class LongSession(common.SmallCornellCase):

    def test_a_hundred_bakes_keep_memory_flat(self):
        folder = tempfile.mkdtemp(prefix="bakegi_long_session_")
        self.addCleanup(shutil.rmtree, folder, ignore_errors=True)
        bakes = [
            dict(method="pathtrace", samples=4, target="CORNER"),
            dict(method="meshless", target="POINT",
                 method_settings={"levels": 1, "gather_rays": 16}),
            dict(method="antiradiance", target="CORNER", method_settings={"bins": 12}),
            dict(method="pathtrace", samples=2, target="LIGHTMAP", texels_per_meter=8.0,
                 lightmap_folder=folder),
            dict(method="pathtrace", samples=8, target="GRID", grid_cell_size=0.5,
                 grid_rays=16, grid_folder=folder),
        ]
        memory = []
        for i in range(BAKES):
            kwargs = dict(bakes[i % len(bakes)])
            self.bakegi.bake(objects="VISIBLE", estimate_error=False, **kwargs)
            if kwargs["target"] != "GRID":
                self.bakegi.remove_bake()
            memory.append(resident_bytes())
        baseline = memory[BASELINE_AFTER - 1]
        growth = (memory[-1] - baseline) / baseline
        print(f"long session: {BAKES} bakes, resident {memory[0] / 2**20:.1f} MiB after the "
              f"first, {baseline / 2**20:.1f} MiB after the {BASELINE_AFTER}th, "
              f"{memory[-1] / 2**20:.1f} MiB after the last: growth {100 * growth:+.2f}% "
              f"(peak {max(memory) / 2**20:.1f} MiB)")
        print("long session resident MiB per bake:",
              " ".join(f"{m / 2**20:.0f}" for m in memory))
        self.assertLess(growth, MAX_GROWTH)


if __name__ == "__main__":
    common.run_tests(__name__)
