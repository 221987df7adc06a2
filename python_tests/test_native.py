"""The ctypes binding (bakegi.native) against the built library: it loads only a library whose
binary interface it matches, describes every method's settings, and bakes an analytic case."""

import ctypes
import math

import numpy as np
import pytest


def test_the_binding_matches_the_library(native):
    lib = native.load_library()
    assert lib.bakegi_abi_version() == native.ABI_VERSION
    for name, struct in (("bakegi_material_desc", native.MaterialDesc),
                         ("bakegi_mesh_desc", native.MeshDesc),
                         ("bakegi_light_desc", native.LightDesc),
                         ("bakegi_lightmap_info", native.LightmapInfo)):
        assert lib.bakegi_struct_size(name.encode()) == ctypes.sizeof(struct), name
    assert lib.bakegi_struct_size(b"bakegi_nothing") == 0


def test_a_mismatched_struct_is_refused_with_its_name(native, monkeypatch):
    lib = native.load_library()

    class Shorter(ctypes.Structure):
        _fields_ = [("x", ctypes.c_float)]

    monkeypatch.setattr(native, "LightDesc", Shorter)
    with pytest.raises(native.BakeGIError, match="bakegi_light_desc is .* bytes there and 4 here"):
        native._check_binary_interface(lib, "libbakegi.so")
    monkeypatch.setattr(native, "ABI_VERSION", native.ABI_VERSION + 1)
    with pytest.raises(native.BakeGIError, match="binary interface"):
        native._check_binary_interface(lib, "libbakegi.so")


def test_every_method_describes_its_settings(native):
    methods = native.describe_settings()["methods"]
    assert methods == ["pathtrace", "direct", "antiradiance", "meshless", "splatting", "grid"]
    for method in methods:
        schema = native.describe_settings(method)
        keys = [s["key"] for s in schema["settings"]]
        assert len(keys) == len(set(keys))
        assert {"method", "samples", "seed", "threads"} <= set(keys)
        for s in schema["settings"]:
            assert s["role"] in ("shapes", "lighting", "execution")
            if s["type"] in ("integer", "number"):
                assert s["min"] <= s["default"] <= s["max"], s
    antiradiance = {s["key"]: s for s in native.describe_settings("antiradiance")["settings"]}
    assert antiradiance["bins"]["default"] == 300
    assert antiradiance["scheme"]["choices"] == ["symmetric", "asymmetric"]
    with pytest.raises(native.BakeGIError, match="unknown method 'radiosity'"):
        native.describe_settings("radiosity")


def test_direct_light_of_a_point_light_on_a_plane_is_the_inverse_square_law(native):
    """E / pi = I cos(theta) / (pi d^2) under a point light of intensity I (W/sr) at height h:
    the "direct" method's output at points of a plane, exactly (no sampling noise for a point
    light with radius 0, no occluder)."""
    scene = native.Scene()
    scene.add_material((0.5, 0.5, 0.5))
    half = 50.0
    scene.add_mesh([(-half, -half, 0), (half, -half, 0), (half, half, 0), (-half, half, 0)],
                   [(0, 1, 2), (0, 2, 3)])
    intensity, height = 10.0, 2.0
    scene.add_light("POINT", position=(0, 0, height), color=(intensity,) * 3)
    xs = np.array([0.0, 1.0, 2.0, 4.0])
    positions = np.stack([xs, np.zeros_like(xs), np.full_like(xs, 1e-3)], axis=1)
    normals = np.tile([0.0, 0.0, 1.0], (len(xs), 1))
    points = native.Points(positions, normals, np.zeros(len(xs), np.uint32))
    job = native.Job(scene, points, native.Settings(method="direct", samples=1, error_probes=0))
    job.wait()
    got = job.result()[:, 1]
    d2 = xs ** 2 + (height - 1e-3) ** 2
    expected = intensity * ((height - 1e-3) / np.sqrt(d2)) / (math.pi * d2)
    np.testing.assert_allclose(got, expected, rtol=1e-4)


def test_a_lightmap_resolves_into_memory_bottom_up(native):
    """A floor lit by a point light above its lower-left quarter, baked into a lightmap and
    resolved into memory: (height, width, 4) with alpha 1, row 0 at v = 0 as Blender's
    Image.pixels holds it, so the brightest texel lies in the lower-left of the array."""
    scene = native.Scene()
    scene.add_material((0.5, 0.5, 0.5))
    mesh = scene.add_mesh([(0, 0, 0), (2, 0, 0), (2, 2, 0), (0, 2, 0)], [(0, 1, 2), (0, 2, 3)])
    # Above the centre of texel (column 4, row 2): ((4.5 / 16) * 2 m, (2.5 / 8) * 2 m).
    scene.add_light("POINT", position=(0.5625, 0.625, 0.5), color=(10.0,) * 3)
    uvs = np.array([(0, 0), (1, 0), (1, 1), (0, 0), (1, 1), (0, 1)], np.float32)
    lightmaps = native.Lightmaps()
    lightmaps.add(scene, mesh, uvs, 16, 8)
    job = native.Job(scene, lightmaps.points(),
                     native.Settings(method="direct", samples=1, error_probes=0))
    job.wait()
    pixels = lightmaps.resolve(0, job.result(), padding=2)
    assert pixels.shape == (8, 16, 4)
    assert np.all(pixels[..., 3] == 1.0)
    row, column = np.unravel_index(np.argmax(pixels[..., 1]), pixels.shape[:2])
    assert (row, column) == (2, 4)
    assert lightmaps.resolve(0, job.result(), padding=2, channels=3).shape == (8, 16, 3)
    with pytest.raises(native.BakeGIError, match="channels"):
        lightmaps.resolve(0, job.result(), channels=2)


def test_a_grid_bakes_evaluates_and_round_trips(native, tmp_path):
    """A closed box lit by a point light: the grid's light on the floor is close to a bake's
    there, a file written and read back gives the same values, and buried points are
    flagged (the core's own tests pin the physics; this pins the binding)."""
    scene = native.Scene()
    material = scene.add_material((0.5, 0.5, 0.5))
    positions = np.array([[x, y, z] for z in (0, 1) for y in (0, 1) for x in (0, 1)], np.float32)
    faces = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
    indices = np.array([[f[0], f[1], f[2], f[0], f[2], f[3]] for f in faces], np.uint32)
    scene.add_mesh(positions, indices.reshape(-1), material=material)
    scene.add_light("POINT", position=(0.5, 0.5, 0.5), color=(1.0, 1.0, 1.0))
    assert scene.bounds() == ((0.0, 0.0, 0.0), (1.0, 1.0, 1.0))
    with native.Grid.create(*scene.bounds(), cell_size=0.25) as layout, \
            native.Settings(method="pathtrace", samples=256) as settings:
        assert layout.info()["resolution"] == [4, 4, 4]
        job = native.GridJob(scene, layout, settings, rays=64)
        job.wait()
        grid = job.grid()
        assert job.report()["grid_vertices"] == 64
        floor = np.array([[0.3, 0.4, 0.01], [0.7, 0.6, 0.01]], np.float32)
        up = np.array([[0, 0, 1], [0, 0, 1]], np.float32)
        values = grid.evaluate(floor, up)
        with native.Points(floor, up) as points:
            baked = native.Job(scene, points, settings)
            baked.wait()
            assert abs(values.mean() / baked.result().mean() - 1.0) < 0.15
            assert not points.flag_inside(scene).any()
        path = str(tmp_path / "box.bgivg")
        grid.write(path, encoding="FLOAT", info={"test": True})
        with native.Grid.read(path) as read:
            assert np.array_equal(read.evaluate(floor, up), values)
            assert read.info_json() == {"test": True}
        with pytest.raises(native.BakeGIError, match="interpolation must be one of"):
            grid.evaluate(floor, up, "NEAREST")
        # Lamps alone: no emitted light to add; the page's grid reads as the grid.
        page, had_emitted = grid.with_emitted_light()
        with page:
            assert not had_emitted
            assert np.array_equal(page.evaluate(floor, up), values)
        grid.close()
        job.close()


def test_a_level_of_detail_keeps_a_plane_and_refuses_bad_indices(native):
    n = 10  # a 10 x 10 grid of squares: 200 triangles on the unit square
    positions = np.array([[i / n, j / n, 0.0] for j in range(n + 1) for i in range(n + 1)],
                         np.float32)
    quads = [(j * (n + 1) + i, j * (n + 1) + i + 1, (j + 1) * (n + 1) + i + 1,
              (j + 1) * (n + 1) + i) for j in range(n) for i in range(n)]
    triangles = np.array([t for a, b, c, d in quads for t in ((a, b, c), (a, c, d))], np.uint32)
    lod, deviation = native.simplify_mesh(positions, triangles, 0.1)
    assert 2 <= len(lod) <= 20 and lod.shape[1] == 3
    corners = positions[lod]
    area = 0.5 * np.linalg.norm(np.cross(corners[:, 1] - corners[:, 0],
                                         corners[:, 2] - corners[:, 0]), axis=1).sum()
    assert abs(area - 1.0) < 1e-4  # collapses on a plane keep it whole
    assert 0.0 <= deviation < 1e-4
    with pytest.raises(native.BakeGIError, match="past the"):
        native.simplify_mesh(positions, triangles + len(positions), 0.5)
