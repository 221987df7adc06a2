"""The panel's view of the cache folder (addon/bakegi/cache_folder.py): only *.bgcache
files are counted and cleared."""

from bakegi import cache_folder


def test_usage_and_clear_touch_only_cache_files(tmp_path):
    assert cache_folder.usage(str(tmp_path / "missing")) == (0, 0)
    assert cache_folder.describe(str(tmp_path)) == "empty"
    (tmp_path / "meshless-1.bgcache").write_bytes(b"x" * 1500)
    (tmp_path / "antiradiance-2.bgcache").write_bytes(b"x" * 500)
    (tmp_path / "notes.txt").write_bytes(b"keep")
    assert cache_folder.usage(str(tmp_path)) == (2, 2000)
    assert cache_folder.describe(str(tmp_path)) == "2 files, 0.0 MB"
    assert cache_folder.clear(str(tmp_path)) == 2
    assert sorted(p.name for p in tmp_path.iterdir()) == ["notes.txt"]


def test_two_processes_baking_into_one_cache_folder_corrupt_nothing(native, tmp_path):
    """Two CLI bakes of the same scene into one cache folder at once (two Blender sessions
    sharing a cache): both finish, the folder holds one whole cache file (written by rename,
    checksummed), and a third bake loads it and gets the same values."""
    import os
    import subprocess
    import numpy as np
    from test_cancel import closed_box

    scene, points = closed_box(native)
    path = str(tmp_path / "box.bgs")
    scene.write(path, points)
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    library = os.environ.get("BAKEGI_LIBRARY") or os.path.join(root, "build", "libbakegi.so")
    cli = os.path.join(os.path.dirname(os.path.abspath(library)), "bakegi")
    cache = str(tmp_path / "cache")
    command = [cli, "bake", path, "--method", "meshless", "--set", "levels=2",
               "--set", "gather_rays=32", "--set", "error_probes=0", "--cache-dir", cache]
    runs = [subprocess.Popen(command + ["--out", str(tmp_path / f"{i}.npy")],
                             stdout=subprocess.PIPE, stderr=subprocess.PIPE) for i in range(2)]
    for run in runs:
        _, err = run.communicate(timeout=300)
        assert run.returncode == 0, err.decode()
    files = sorted(os.listdir(cache))
    assert len(files) == 1 and files[0].endswith(".bgcache"), files
    third = subprocess.run(command + ["--out", str(tmp_path / "2.npy")], capture_output=True,
                           timeout=300, text=True)
    assert third.returncode == 0, third.stderr
    assert '"meshless_cache": "hit"' in third.stdout
    values = [np.load(tmp_path / f"{i}.npy") for i in range(3)]
    np.testing.assert_array_equal(values[0], values[1])
    np.testing.assert_array_equal(values[0], values[2])
