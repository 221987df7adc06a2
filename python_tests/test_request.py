"""bakegi.request: the one typed request from the panel and from bakegi.bake() to a session."""

import pytest

from bakegi.native import BakeGIError
from bakegi.request import BakeRequest, GridOptions, LightmapOptions


def test_the_defaults_are_a_valid_request(native):
    BakeRequest().validate()
    # No method named: the core's default, the same one the CLI and the C API use.
    assert BakeRequest().with_core_default().method == native.describe_settings()["default"]
    # ...with its recipe: the path tracer to 5% through the denoiser, at most 65,536 paths.
    settings = BakeRequest().core_settings()
    assert settings["method"] == "pathtrace"
    assert (settings["target_error"], settings["denoise"], settings["samples"]) == (0.05, 1, 65536)
    # What the caller gives stays; a named method gets its own defaults and 64 samples.
    given = BakeRequest(method_settings={"target_error": 0.02}, samples=1000).core_settings()
    assert (given["target_error"], given["denoise"], given["samples"]) == (0.02, 1, 1000)
    named = BakeRequest(method="pathtrace").core_settings()
    assert named["samples"] == 64 and "target_error" not in named and "denoise" not in named


def test_the_methods_are_the_cores(native):
    assert native.method_names() == ("pathtrace", "direct", "antiradiance", "meshless", "splatting",
                                    "grid")
    for method in native.method_names():
        BakeRequest(method=method).validate()


@pytest.mark.parametrize("changes, message", [
    ({"method": "radiosity"}, "method must be one of"),
    ({"target": "TEXTURE"}, "target must be one of"),
    ({"samples": 0}, "samples must be an integer >= 1"),
    ({"samples": True}, "samples must be an integer"),
    ({"seed": -1}, "seed must be an integer >= 0"),
    ({"threads": 2.5}, "threads must be an integer"),
    ({"live": True, "method": "pathtrace"}, "live indirect needs a method that relights"),
    ({"live": True, "method": "meshless", "target": "LIGHTMAP", "lightmap_folder": "/tmp"},
     "live indirect writes the color attribute"),
    ({"linked_duplicates": "COPY"}, "linked_duplicates must be one of"),
    ({"target": "LIGHTMAP"}, "needs a folder"),
    ({"method_settings": [("bins", 300)]}, "method_settings must be a dict"),
    ({"target": "GRID"}, "a grid bake needs a folder"),
    ({"target": "GRID", "grid_folder": "/tmp", "live": True, "method": "meshless"},
     "a grid is applied with Apply Grid"),
    ({"target": "GRID", "grid_folder": "/tmp", "grid": GridOptions(cell_size=-1.0)},
     "grid_cell_size must be a number >= 0"),
    ({"target": "GRID", "grid_folder": "/tmp", "grid": GridOptions(rays=0)},
     r"grid_rays must be an integer in \[1, 65536\]"),
    ({"target": "GRID", "grid_folder": "/tmp", "grid": GridOptions(max_vertices=2.5)},
     "grid_max_vertices must be an integer"),
    ({"target": "GRID", "grid_folder": "/tmp",
      "grid": GridOptions(bounds=((0, 0, 0), (1, -1, 1)))}, "grid bounds must be"),
])
def test_a_refused_choice_is_named(native, changes, message):
    with pytest.raises(BakeGIError, match=message) as caught:
        BakeRequest(**changes).validate()
    assert caught.value.status == "BAKEGI_ERROR_INVALID_ARGUMENT"


def test_core_settings_carry_the_method_settings_last():
    request = BakeRequest(method="pathtrace", samples=16, method_settings={"max_bounces": 4})
    assert request.core_settings() == {"method": "pathtrace", "samples": 16, "seed": 0,
                                       "threads": 0, "max_bounces": 4}
    assert request.with_threads(3).core_settings()["threads"] == 3
    assert request.threads is None  # requests do not change: with_threads made a new one


def test_lightmap_options_default_to_the_panels():
    options = LightmapOptions()
    assert (options.uv_map, options.texels_per_meter, options.max_side, options.padding) == \
        ("BakeGI", 40.0, 1024, 4)


def test_a_grid_request_is_valid_with_a_folder():
    request = BakeRequest(target="GRID", grid_folder="/tmp",
                          grid=GridOptions(bounds=((0, 0, 0), (1, 2, 3)), cell_size=0.1))
    request.validate()
    assert request.grid.rays == 64 and request.grid.quantized
