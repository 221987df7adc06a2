# SPDX-License-Identifier: GPL-3.0-or-later
"""What a bake is asked to do: one typed BakeRequest from the panel (ui/properties.py,
BakeGISettings.request) and from scripting (api.bake) to the session (session.BakeSession).

The core checks its own settings (method_settings) against the method's schema
(docs/settings.md); validate() checks what the add-on itself decides: method, target,
counts, live and lightmap choices. No bpy: tested without Blender (python_tests/).
"""

from dataclasses import dataclass, field, replace
from typing import Any, Dict, Optional, Tuple

from . import native
from .native import BakeGIError

# Methods whose finished bake can be kept for live indirect (relit when lights change).
LIVE_METHODS = ("meshless",)
# Paths per point of a named sampling method when the request gives none.
FIXED_SAMPLES = 64
TARGET_DOMAINS = ("CORNER", "POINT", "LIGHTMAP", "GRID")
LINKED_DUPLICATES = ("SHARED", "SINGLE_USER")


@dataclass(frozen=True)
class LightmapOptions:
    """What a LIGHTMAP bake needs besides the scene (see lightmap_layout, write/uv_maps)."""

    uv_map: str = "BakeGI"
    texels_per_meter: float = 40.0
    max_side: int = 1024
    padding: int = 4
    uv_method: str = "SMART"
    reject_inside: bool = True
    memory_budget_mb: int = 4096  # what the texel samples may take (the session sets the bake's)


@dataclass(frozen=True)
class GridOptions:
    """What a GRID bake needs besides the scene (docs/ivg.md). bounds: ((x0, y0, z0),
    (x1, y1, z1)) in world space, or None for the visible scene's bounds (the session takes a
    grid object's box here). cell_size 0: 32 cells on the longest axis. max_vertices 0: 64^3.
    rays: per vertex hemisphere. quantized: the paper's 24-bit direction and R9G9B9E5 colour
    (42 bytes a vertex) instead of floats (216)."""

    bounds: Optional[Tuple[Tuple[float, float, float], Tuple[float, float, float]]] = None
    cell_size: float = 0.0
    max_vertices: int = 0
    rays: int = 64
    quantized: bool = True

    def validate(self):
        def refuse(message):
            raise BakeGIError("BAKEGI_ERROR_INVALID_ARGUMENT", message)

        if (isinstance(self.cell_size, bool) or not isinstance(self.cell_size, (int, float)) or
                not 0.0 <= self.cell_size < float("inf")):
            refuse(f"grid_cell_size must be a number >= 0 (0: 32 cells on the longest axis), "
                   f"not {self.cell_size!r}")
        for name, value, low, high in (("grid_rays", self.rays, 1, 65536),
                                       ("grid_max_vertices", self.max_vertices, 0, 1 << 30)):
            if isinstance(value, bool) or not isinstance(value, int) or not low <= value <= high:
                refuse(f"{name} must be an integer in [{low}, {high}], not {value!r}")
        if self.bounds is not None:
            try:
                lo, hi = ([float(x) for x in corner] for corner in self.bounds)
            except (TypeError, ValueError):
                refuse(f"grid bounds must be two (x, y, z) corners, not {self.bounds!r}")
            if len(lo) != 3 or len(hi) != 3 or any(h < l for l, h in zip(lo, hi)):
                refuse(f"grid bounds must be (min corner, max corner), not {self.bounds!r}")


@dataclass(frozen=True)
class BakeRequest:
    """One bake. objects: 'SELECTED', 'VISIBLE' or a list of objects (or names).
    threads None: the add-on preferences' (0 = every core); their memory budget applies
    unless method_settings names memory_budget_mb. lightmap_folder: where a LIGHTMAP bake
    writes its atlas (absolute). linked_duplicates (attribute targets): 'SHARED' bakes the
    first object of a shared mesh (the others show its light), 'SINGLE_USER' gives each its
    own copy first. live: keep the precomputation so light changes relight (meshless).
    method None: the core's default bake (native.default_method() with
    native.default_method_settings() under the given method_settings: the path tracer to 5%
    through its denoiser; with_core_default() names it). samples None: 64, or the default
    bake's cap on paths per point. The methods are the core's (native.method_names()): no
    list here."""

    method: Optional[str] = None
    samples: Optional[int] = None
    seed: int = 0
    target: str = "CORNER"
    objects: Any = "SELECTED"
    threads: Optional[int] = None
    hook_materials: bool = True
    method_settings: Dict[str, Any] = field(default_factory=dict)
    live: bool = False
    lightmap: LightmapOptions = field(default_factory=LightmapOptions)
    lightmap_folder: str = ""
    lightmap_full_float: bool = False
    linked_duplicates: str = "SHARED"
    grid: GridOptions = field(default_factory=GridOptions)
    grid_folder: str = ""

    def with_core_default(self):
        """This request with its method and samples named: the core's default bake where the
        method was None (its settings under the request's own), 64 samples where None."""
        if self.method:
            return self if self.samples is not None else replace(self, samples=FIXED_SAMPLES)
        recipe = dict(native.default_method_settings())
        samples = recipe.pop("samples", FIXED_SAMPLES)
        return replace(self, method=native.default_method(),
                       samples=samples if self.samples is None else self.samples,
                       method_settings={**recipe, **self.method_settings})

    def with_threads(self, threads):
        return replace(self, threads=threads)

    def validate(self):
        """Raises BakeGIError(INVALID_ARGUMENT) naming the first choice the add-on refuses."""
        def refuse(message):
            raise BakeGIError("BAKEGI_ERROR_INVALID_ARGUMENT", message)

        methods = native.method_names()
        if self.method is not None and self.method not in methods:
            refuse(f"method must be one of {methods}, not {self.method!r}")
        if self.target not in TARGET_DOMAINS:
            refuse(f"target must be one of {TARGET_DOMAINS}, not {self.target!r}")
        if self.live and self.target == "LIGHTMAP":
            refuse("live indirect writes the color attribute; bake it to face corners or "
                   "vertices, not to lightmaps")
        if self.live and self.target == "GRID":
            refuse("live indirect writes the color attribute; a grid is applied with Apply "
                   "Grid")
        if self.live and self.with_core_default().method not in LIVE_METHODS:
            refuse(f"live indirect needs a method that relights ({', '.join(LIVE_METHODS)}), "
                   f"not {self.method!r}")
        threads = 0 if self.threads is None else self.threads
        samples = FIXED_SAMPLES if self.samples is None else self.samples
        for name, value, low in (("samples", samples, 1), ("seed", self.seed, 0),
                                 ("threads", threads, 0)):
            if isinstance(value, bool) or not isinstance(value, int) or value < low:
                refuse(f"{name} must be an integer >= {low}, not {value!r}")
        if self.linked_duplicates not in LINKED_DUPLICATES:
            refuse(f"linked_duplicates must be one of {LINKED_DUPLICATES}, "
                   f"not {self.linked_duplicates!r}")
        if not isinstance(self.method_settings, dict):
            refuse(f"method_settings must be a dict, not {type(self.method_settings).__name__}")
        if self.target == "LIGHTMAP" and not self.lightmap_folder:
            refuse("a lightmap bake needs a folder to write its EXR file to")
        if self.target == "GRID":
            if not self.grid_folder:
                refuse("a grid bake needs a folder to write its .bgivg file to")
            self.grid.validate()

    def core_settings(self):
        """The settings the core receives (method_settings may add or override)."""
        named = self.with_core_default()
        return {"method": named.method, "samples": named.samples, "seed": self.seed,
                "threads": 0 if self.threads is None else self.threads, **named.method_settings}
