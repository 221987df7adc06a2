"""`bakegi web export` and `bakegi serve` (issue 16, §4): a textured scene with a grid is
exported, served on a free loopback port, and read back packet by packet as the page does: the
geometry ends as the glTF's own faces, a face arrives only once its corners resolve to three
distinct vertices, and the grid's vectors arrive once each, corners first, equal to the file's
bytes."""

import json
import os
import struct
import subprocess
import urllib.error
import urllib.request
import zlib

import numpy as np
import pytest


def cli_path(native):
    path = os.path.join(os.path.dirname(native.load_library()._name), "bakegi")
    if not os.path.isfile(path):
        pytest.skip(f"no command-line program beside the library ({path})")
    return path


def box_scene(native):
    scene = native.Scene()
    texels = np.zeros((4, 8, 3), np.float32)  # a red/blue checker, 8 x 4 texels
    texels[:, ::2] = (0.8, 0.1, 0.1)
    texels[:, 1::2] = (0.1, 0.1, 0.8)
    texture = scene.add_texture(texels)
    material = scene.add_material((1.0, 1.0, 1.0), albedo_texture=texture)
    n = 8  # an 8 x 8 grid of squares on each of the box's six faces
    positions, indices = [], []
    for axis in range(3):
        for side in (0.0, 1.0):
            base = len(positions)
            for j in range(n + 1):
                for i in range(n + 1):
                    p = [0.0, 0.0, 0.0]
                    p[axis], p[(axis + 1) % 3], p[(axis + 2) % 3] = side, i / n, j / n
                    positions.append(p)
            for j in range(n):
                for i in range(n):
                    a = base + j * (n + 1) + i
                    quad = [(a, a + 1, a + n + 2), (a, a + n + 2, a + n + 1)]
                    for t in quad:  # inward-facing: flip on the far side
                        indices.extend(t if side == 0.0 else (t[0], t[2], t[1]))
    positions = np.array(positions, np.float32)
    triangles = np.array(indices, np.uint32).reshape(-1, 3)
    # Every face its own uv square: corners share positions but not uvs (seams everywhere).
    uvs = positions[triangles][:, :, :2].copy()
    uvs[len(uvs) // 2:] += 2.0
    scene.add_mesh(positions, triangles, corner_uvs=uvs, material=material)
    scene.add_light("POINT", position=(0.5, 0.5, 0.5), color=(1.0, 1.0, 1.0))
    return scene


@pytest.fixture(scope="module")
def served(native, tmp_path_factory):
    folder = tmp_path_factory.mktemp("web")
    scene = box_scene(native)
    scene_path = str(folder / "box.bgs")
    scene.write(scene_path)
    with native.Grid.create(*scene.bounds(), cell_size=0.2) as layout, \
            native.Settings(method="pathtrace", samples=16) as settings:
        job = native.GridJob(scene, layout, settings, rays=16)
        job.wait()
        grid = job.grid()
        grid.write(str(folder / "box.bgivg"), encoding="QUANTIZED")
        grid.close()
        job.close()
    cli = cli_path(native)
    out = folder / "site"
    subprocess.run([cli, "web", "export", scene_path, "--grid", str(folder / "box.bgivg"),
                    "--out", str(out)], check=True, capture_output=True)
    server = subprocess.Popen([cli, "serve", str(out), "--port", "0", "--vectors", "20",
                               "--vertices", "50"], stdout=subprocess.PIPE, text=True)
    line = server.stdout.readline()
    if "http://127.0.0.1:" not in line:
        server.kill()
        pytest.fail(f"the server did not start: {line!r}")
    url = line.split("at ")[1].split()[0]
    yield url, out
    server.terminate()
    server.wait(timeout=10)


def fetch(url):
    with urllib.request.urlopen(url, timeout=10) as response:
        return response.read()


def test_packets_rebuild_the_scene_as_the_page_does(served):
    url, folder = served
    manifest = json.loads(fetch(url + "stream/manifest.json"))
    gltf = json.loads((folder / "scene.gltf").read_text())
    binary = (folder / "scene.bin").read_bytes()
    assert gltf["asset"]["version"] == "2.0"
    (primitive_info,) = manifest["primitives"]
    vertices = primitive_info["vertex_count"]
    received = np.zeros((vertices, 3), np.float32)
    received_uvs = np.zeros((vertices, 2), np.float32)
    received_reads = np.zeros((vertices, 1), np.float32)
    parent = {}
    count, faces = 0, []
    grid_seen, kinds = [], []
    for k, packet_info in enumerate(manifest["packets"]):
        data = fetch(url + f"stream/packet/{k}")
        assert len(data) == packet_info["bytes"]
        kind, entries = struct.unpack_from("<II", data, 0)
        kinds.append(kind)
        if kind == 1:
            (encoding,) = struct.unpack_from("<I", data, 8)
            assert encoding == 1  # quantized
            grid_seen.extend(struct.unpack_from(f"<{entries}I", data, 12))
            assert len(data) == 12 + 4 * entries + 42 * entries
            continue
        if kind == 3:
            # The page's visibility volume: the export's file, whose codes inflate to two bytes
            # per subvoxel, each cell cut in s^3, s = 2 ceil(32 / cells), 2 to 8.
            visibility = (folder / gltf["extras"]["bakegi"]["grid_visibility"]).read_bytes()
            assert data[8:8 + entries] == visibility and len(data) == (8 + entries + 3) // 4 * 4
            assert visibility[:8] == b"BGIVIS1\0"
            subdivision, sx, sy, sz = struct.unpack_from("<4I", visibility, 8)
            resolution = manifest["grid"]["resolution"]
            expected = min(8, max(2, 2 * -(-32 // max(resolution))))
            assert subdivision == expected and [sx, sy, sz] == [expected * r for r in resolution]
            assert len(zlib.decompress(visibility[44:])) == 2 * sx * sy * sz
            continue
        offset = 8
        for _ in range(entries):
            index, first, n, has_normals, has_uvs, has_reads_grid, face_count, lookups = \
                struct.unpack_from("<8I", data, offset)
            offset += 32
            assert index == 0 and first == count and not has_normals and has_uvs
            assert has_reads_grid  # a grid was exported: every vertex says whether it reads it
            received[first:first + n] = np.frombuffer(data, np.float32, 3 * n,
                                                      offset).reshape(-1, 3)
            offset += 12 * n
            received_uvs[first:first + n] = np.frombuffer(data, np.float32, 2 * n,
                                                          offset).reshape(-1, 2)
            offset += 8 * n
            received_reads[first:first + n, 0] = np.frombuffer(data, np.float32, n, offset)
            offset += 4 * n
            count += n
            new_faces = np.frombuffer(data, np.uint32, 3 * face_count, offset).reshape(-1, 3)
            offset += 12 * face_count
            pairs = np.frombuffer(data, np.uint32, 2 * lookups, offset).reshape(-1, 2)
            offset += 8 * lookups
            parent.update({int(v): int(p) for v, p in pairs})

            def resolve(v):
                while v >= count:
                    v = parent[v]  # a KeyError means a lookup entry was not sent
                return v

            for face in new_faces:
                corners = {resolve(int(v)) for v in face}
                assert len(corners) == 3, face  # valid when it arrives
            faces.extend(new_faces.tolist())
        assert offset == len(data)
    # The grid's corners first, then geometry, interleaved, the visibility volume right after
    # the corners.
    assert kinds[:3] == [1, 2, 3] and kinds.count(3) == 1
    assert manifest["grid"]["visibility"] is True
    # The geometry in the end: the glTF's vertices and faces, in its order.
    accessors, views = gltf["accessors"], gltf["bufferViews"]
    prim = gltf["meshes"][0]["primitives"][0]

    def accessor(index, dtype, columns):
        view = views[accessors[index]["bufferView"]]
        components = {"VEC3": 3, "VEC2": 2}.get(accessors[index]["type"], 1)
        return np.frombuffer(binary, dtype, accessors[index]["count"] * components,
                             view.get("byteOffset", 0)).reshape(-1, columns)

    assert count == vertices
    assert np.array_equal(received, accessor(prim["attributes"]["POSITION"], np.float32, 3))
    assert np.array_equal(np.array(faces, np.uint32), accessor(prim["indices"], np.uint32, 3))
    assert len(faces) == 6 * 8 * 8 * 2
    assert np.array_equal(received_uvs, accessor(prim["attributes"]["TEXCOORD_0"], np.float32, 2))
    reads = accessor(prim["attributes"]["_BAKEGI_READS_GRID"], np.float32, 1)
    assert np.array_equal(received_reads, reads)
    # Inside the lit box every corner sees the grid's vertices, also those on the box's edges
    # (asked a little inside their faces, as the add-on's bake points are): none reads 0.
    assert manifest["primitives"][0]["has_reads_grid"] is True and np.all(reads == 1.0)
    # The texture: a PNG beside the glTF, 8 x 4, sRGB-encoded red and blue.
    material = gltf["materials"][prim["material"]]
    image = gltf["images"][gltf["textures"][
        material["pbrMetallicRoughness"]["baseColorTexture"]["index"]]["source"]]
    png = (folder / image["uri"]).read_bytes()
    assert png[:8] == b"\x89PNG\r\n\x1a\n"
    assert struct.unpack(">II", png[16:24]) == (8, 4)
    # The grid: every vertex once, its eight corners first.
    grid = manifest["grid"]
    nx, ny, nz = grid["resolution"]
    assert sorted(grid_seen) == list(range(nx * ny * nz))
    corners = {x + nx * (y + ny * z) for x in (0, nx - 1) for y in (0, ny - 1)
               for z in (0, nz - 1)}
    assert set(grid_seen[:8]) == corners


def test_bad_requests_get_answers_not_crashes(served):
    url, _ = served
    for path, code in (("stream/packet/100000", 404), ("stream/manifest.json?encoding=jpeg", 400),
                       ("stream/manifest.json?vectors=0", 400), ("no-such-file", 404)):
        with pytest.raises(urllib.error.HTTPError) as error:
            fetch(url + path)
        assert error.value.code == code, path
    assert json.loads(fetch(url + "stream/manifest.json?encoding=factored"))["grid"][
        "bytes_per_vector"] == 144
