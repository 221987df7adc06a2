# SPDX-License-Identifier: GPL-3.0-or-later
"""One bake from start to end: the single code path of the operator and of bakegi.bake().

    session = BakeSession(context, BakeRequest(method="pathtrace", samples=64, ...))
    session.prepare()      # export (raises BakeGIError; changes nothing in Blender)
    session.start()        # the core bakes on its own threads
    session.poll()         # -> Progress(fraction, stage, eta_seconds, done)
    session.finish()       # waits, writes the attribute, hooks materials -> report dict
    session.cancel()       # stops the core; Blender data untouched

run() does all of it synchronously (background mode and scripts).
"""

import os
import threading
import time
from dataclasses import dataclass, replace

from . import error_check, live, native
from .export import points as export_points, scene as export_scene, targets as export_targets
from .ui import preferences
from .write import attributes, file_names, grid_file, lightmap_image, material_hook, uv_maps
from .native import BakeGIError


# The stage a lightmap bake shows while the core writes its EXR (after the job's stages).
WRITING_LIGHTMAP = "writing the lightmap"


@dataclass
class Progress:
    fraction: float
    stage: str
    eta_seconds: float  # < 0 while unknown
    done: bool

    def text(self):
        eta = f", about {_duration(self.eta_seconds)} left" if self.eta_seconds >= 0 else ""
        stage = f" {self.stage}" if self.stage else ""
        return f"BakeGI: {self.fraction * 100:.0f}%{stage}{eta} (Esc to cancel)"


def _duration(seconds):
    if seconds >= 90:
        return f"{seconds / 60:.0f} min"
    return f"{max(seconds, 0):.0f} s"


class BakeSession:
    def __init__(self, context, request):
        """request: a request.BakeRequest (checked here; the core checks its settings). Its
        threads None take the add-on preferences' threads; their memory budget applies unless
        the request's method_settings has one."""
        machine = preferences.current(context)
        if request.threads is None:
            request = request.with_threads(machine.threads)
        request = request.with_core_default()
        request.validate()
        self.request = request
        self.linked_duplicates = request.linked_duplicates
        self._single_users = []  # (object, shared mesh, its copy) made by prepare()
        self.context = context
        self.method = request.method
        self.samples = request.samples
        self.seed = request.seed
        self.target = request.target
        self.objects = request.objects
        self.threads = request.threads
        self.hook_materials = request.hook_materials
        # Keep the finished job for live indirect (live.py) instead of releasing it.
        self.live = bool(request.live)
        self.scene_name = context.scene.name
        # Further core settings of the method (e.g. antiradiance "bins"); the core checks them.
        self.method_settings = dict(request.method_settings)
        if machine.memory_budget_mb > 0:
            self.method_settings.setdefault("memory_budget_mb", machine.memory_budget_mb)
        # The core's own checks of every setting, now: a bad value must not wait until the
        # scene is exported (or its lightmap texels rasterized) to be refused.
        with native.Settings(**self.settings) as settings:
            settings.check()
        budget = self.method_settings.get("memory_budget_mb")
        # The texel samples are held to the bake's budget too (a bad value was refused by
        # the check above).
        self.lightmap = (replace(request.lightmap, memory_budget_mb=budget)
                         if isinstance(budget, int) and not isinstance(budget, bool) and budget >= 1
                         else request.lightmap)
        self.lightmap_folder = request.lightmap_folder
        self.grid = request.grid
        self.grid_folder = request.grid_folder
        self.lightmap_full_float = bool(request.lightmap_full_float)
        self.exported = None
        self.job = None
        # Lightmaps: the worker thread that rasterizes the texels, then starts the job.
        self._starter = None
        self._starter_error = None
        self._cancelled = False
        # A lightmap bake's EXR: resolved and written by the core on a worker thread once the
        # job is done (a 2048² atlas takes a quarter of a second; Esc stops it), into a staging
        # file that finish() renames over the lightmap's file.
        self._writer = None
        self._writer_error = None
        self._staged_lightmap = None
        self.seconds = {}
        self._started_at = None
        self._created_at = time.perf_counter()

    @property
    def estimates_error(self):
        """Whether the core will check this bake (every full bake unless error_probes is 0;
        not the 'direct' method)."""
        return (self.method != "direct" and self.target != "GRID" and
                self.method_settings.get("error_probes", 1) != 0)

    @property
    def settings(self):
        """The core's settings: the request's, with the preferences' memory budget."""
        return {**self.request.core_settings(), **self.method_settings}

    def prepare(self):
        """Exports the scene. The context is used only here (and by finish() when no data
        is given): a modal operator's context does not outlive the call that passed it."""
        if self.linked_duplicates == "SINGLE_USER" and self.target in ("CORNER", "POINT"):
            self._single_users = export_targets.make_single_users(self.context, self.objects)
        try:
            self.exported = export_scene.export_scene(self.context, self.target, self.objects,
                                                lightmap=self.lightmap, defer_texels=True,
                                                display_probes=self.estimates_error)
        except BaseException:
            self._take_back_changes()
            raise
        self.seconds["export"] = self.exported.seconds

    def start(self):
        """Starts the bake and returns; the core works on its own threads. A lightmap bake
        first rasterizes its texels (seconds on a large scene) on a worker thread, so that
        the UI keeps its progress and Esc from the start."""
        if self.exported is None:
            self.prepare()
        self._started_at = time.perf_counter()
        if self.exported.points is None and self.target == "LIGHTMAP":
            self._starter = threading.Thread(target=self._build_texels_and_start,
                                             name="bakegi-lightmap-texels", daemon=True)
            self._starter.start()
            return
        try:
            self._start_job()
        except BakeGIError as error:
            self._take_back_changes()
            self._release_export()
            raise self._named(error) from None
        except BaseException:
            self._take_back_changes()
            self._release_export()
            raise

    def _start_job(self):
        with native.Settings(**self.settings) as settings:
            if self.target == "GRID":
                bounds = self.grid.bounds or self.exported.scene.bounds()
                with native.Grid.create(bounds[0], bounds[1], self.grid.cell_size,
                                        self.grid.max_vertices) as layout:
                    self.job = native.GridJob(self.exported.scene, layout, settings,
                                              self.grid.rays)
            else:
                self.job = native.Job(self.exported.scene, self.exported.points, settings)

    def _build_texels_and_start(self):
        """Worker thread: no bpy here, only the core (ctypes releases the GIL)."""
        try:
            points = self.exported.lightmaps.build()
            self.exported.points = points
            lightmaps = self.exported.lightmaps
            self.exported.counts.update(bake_points=len(points),
                                        lightmap_covered_texels=lightmaps.covered_texels,
                                        lightmap_rejected_samples=lightmaps.rejected_samples)
            if not self._cancelled:
                self._start_job()
        except BaseException as error:  # handed to finish() on the main thread
            self._starter_error = error

    def _join_starter(self):
        """Waits for the lightmap worker; raises what it raised."""
        if self._starter is not None:
            self._starter.join()
            self._starter = None
        if self._starter_error is not None:
            error, self._starter_error = self._starter_error, None
            raise error

    def poll(self):
        if self._starter is not None and self._starter.is_alive():
            return Progress(0.0, self.exported.lightmaps.stage, -1.0, False)
        if self.job is None:  # the worker failed: finish() raises its error
            return Progress(1.0, "", -1.0, True)
        job = self.job
        fraction = min(max(job.progress, 0.0), 1.0)
        elapsed = time.perf_counter() - self._started_at
        eta = elapsed * (1.0 - fraction) / fraction if 0.02 <= fraction < 1.0 else -1.0
        done = job.is_done
        if done and self.target == "LIGHTMAP" and not self._cancelled:
            if self._writer is None and self._staged_lightmap is None:
                self._writer = threading.Thread(target=self._write_lightmap_file,
                                                name="bakegi-lightmap-write", daemon=True)
                self._writer.start()
            if self._writer is not None and self._writer.is_alive():
                return Progress(1.0, WRITING_LIGHTMAP, -1.0, False)
        return Progress(fraction, job.stage, eta, done)

    def _write_lightmap_file(self):
        """Worker thread, or finish() when no poll started it: the core resolves the bake
        into the atlas and writes it as a staging EXR beside the lightmap's file (no bpy;
        ctypes releases the GIL). A failed or cancelled write leaves no file."""
        try:
            self.job.wait()
            staged = lightmap_image.staging_path(self.lightmap_folder)
            lightmap_image.write_lightmap_file(self.exported, self.job.result(), staged,
                                               self.lightmap_full_float)
            self._staged_lightmap = staged
        except BaseException as error:  # handed to finish() on the main thread
            self._writer_error = error

    def _join_writer(self):
        """The staging EXR of a lightmap bake (written now if no poll started the writer);
        raises what the writer raised."""
        if self._writer is None and self._staged_lightmap is None and self._writer_error is None:
            self._write_lightmap_file()
        if self._writer is not None:
            self._writer.join()
            self._writer = None
        if self._writer_error is not None:
            error, self._writer_error = self._writer_error, None
            raise error
        return self._staged_lightmap

    def cancel(self, wait=True):
        """Stops the bake; nothing in Blender is changed. wait=False returns at once and
        lets a helper thread wait for the core's threads to wind down (the UI stays
        responsive)."""
        self._cancelled = True
        self._take_back_changes()  # bpy: here, on the main thread
        # A lightmap worker (the texels before the job, or the EXR after it; never both):
        # the core stops its texel work within a texel row (it used to run on for seconds
        # after Esc) and its EXR within a block of scanlines; the texel worker may still
        # start a job: wind both down.
        workers = (self._starter, self._writer)
        self._starter = self._writer = None
        worker = next((w for w in workers if w is not None and w.is_alive()), None)
        if worker is not None:
            self.exported.lightmaps.lightmaps.cancel()
            def wind_down():
                worker.join()
                self._discard_staged_lightmap()
                self._stop_job(True)
                self._release_export()
            if wait:
                wind_down()
            else:
                threading.Thread(target=wind_down, name="bakegi-cancel", daemon=True).start()
            return
        self._discard_staged_lightmap()
        self._stop_job(wait)
        self._release_export()

    def _stop_job(self, wait):
        job, self.job = self.job, None
        if job is not None:
            job.cancel()
            if wait:
                job.close()
            else:
                threading.Thread(target=job.close, name="bakegi-cancel", daemon=True).start()

    def finish(self, data=None):
        """Waits for the job, writes the result into `data` (bpy.data; default: the
        context's) and hooks materials; returns the report. On failure raises BakeGIError
        and leaves Blender untouched."""
        adopted = False
        written = False
        lightmap_report = {}
        grid_report = None
        try:
            try:
                self._join_starter()
                self.job.wait()
            except BakeGIError as error:
                raise self._named(error) from None
            self.seconds["bake"] = time.perf_counter() - self._started_at
            # (A lightmap's result went to its EXR writer: not fetched again.)
            rgb = self.job.result() if self.target not in ("LIGHTMAP", "GRID") else None
            core_report = self.job.report()
            t0 = time.perf_counter()
            data = data if data is not None else self.context.blend_data
            image = None
            if self.target == "GRID":
                grid_report = self._write_grid()
            elif self.target == "LIGHTMAP":
                lightmap_report = self._write_lightmap(data)
                image = data.images.get(lightmap_report["image"])
            else:
                attributes.write_results(data, self.exported.targets, rgb)
            written = True
            hooked = (material_hook.hook_materials(data, self.exported.materials,
                                               self.exported.targets, image,
                                               self.lightmap.uv_map)
                      if self.hook_materials and self.target != "GRID" else [])
            self.seconds["writeback"] = time.perf_counter() - t0
            if self.live:
                # The job and the exported meshes now belong to live indirect.
                job, self.job = self.job, None
                self.exported.points.close()
                adopted = True
                live.adopt(self.scene_name, job, self.exported.scene, self.exported.targets,
                           hooked)
            elif live.is_active_for(self.scene_name):
                # This bake replaced what live indirect would overwrite.
                live.stop()
        finally:
            if self._writer is not None:  # (it has the job; it stops once the job failed)
                self._writer.join()
                self._writer = None
            if self.job is not None:
                self.job.close()
                self.job = None
            targets = self.exported.targets if self.exported else []
            if not written:
                self._discard_staged_lightmap()
                self._take_back_changes()
            exported_lightmaps = self.exported.lightmaps if self.exported else None
            if not adopted:
                self._release_export()
        self.seconds["total"] = time.perf_counter() - self._created_at
        report = self._report(core_report, targets, hooked)
        if exported_lightmaps is not None:
            report["lightmap"] = {**lightmap_report, **self._lightmap_counts(exported_lightmaps)}
        if grid_report is not None:
            report["grid"] = grid_report
            if data is not None and self.scene_name in data.scenes:
                import bpy
                # Relative to a saved .blend (//...), so the pair can move together.
                path = grid_report["path"]
                remembered = bpy.path.relpath(path) if bpy.data.filepath else path
                data.scenes[self.scene_name][grid_file.GRID_PATH_PROPERTY] = remembered
        return report

    def _write_grid(self):
        """Writes the grid job's grid next to the .blend (atomically, by the core)."""
        import bpy
        os.makedirs(self.grid_folder, exist_ok=True)
        path = os.path.join(self.grid_folder, grid_file.grid_file_name(
            bpy.data.filepath, self.scene_name, self._file_identity(bpy.data)))
        with self.job.grid() as grid:
            info = grid.info()
            grid.write(path, quantized=self.grid.quantized,
                       info={"scene": self.scene_name, "method": self.method,
                             "rays_per_hemisphere": self.grid.rays,
                             "bake_seconds": self.seconds.get("bake", 0.0)})
        return {**info, "path": path, "quantized": self.grid.quantized,
                "rays_per_hemisphere": self.grid.rays, "file_bytes": os.path.getsize(path),
                "description": grid_file.describe(info)}

    def _discard_staged_lightmap(self):
        staged, self._staged_lightmap = self._staged_lightmap, None
        if staged is not None:
            try:
                os.remove(staged)
            except OSError:
                pass

    def _write_lightmap(self, data):
        import bpy  # the session runs inside Blender; the rest of this module does not need it
        path = os.path.join(self.lightmap_folder, lightmap_image.lightmap_file_name(
            bpy.data.filepath, self.scene_name, self._file_identity(data)))
        staged = self._join_writer()
        self._staged_lightmap = None
        try:
            os.replace(staged, path)  # atomic: the old lightmap stays until here
        except OSError as error:
            try:
                os.remove(staged)
            except OSError:
                pass
            raise BakeGIError("BAKEGI_ERROR_IO", f"cannot write the lightmap {path}: "
                              f"{error.strerror}") from None
        image, dropped = lightmap_image.place_lightmap(data, self.exported, path,
                                                       self.scene_name, bpy.data.filepath)
        if dropped:
            self.exported.warnings.append(
                f"the lightmap atlas was rewritten without {', '.join(sorted(dropped))}; "
                "bake them together with these objects to keep their lightmaps")
        return {"path": path, "image": image.name,
                "file_bytes": os.path.getsize(path) if os.path.exists(path) else 0}

    def _file_identity(self, data):
        """The baked scene's identifier in its file names (write/file_names.py)."""
        scene = data.scenes.get(self.scene_name)
        return file_names.file_identity(scene) if scene is not None else "unnamed"

    @staticmethod
    def _lightmap_counts(exported_lightmaps):
        lm = exported_lightmaps
        return {"width": lm.width, "height": lm.height, "texels": lm.width * lm.height,
                "covered_texels": lm.covered_texels, "rejected_samples": lm.rejected_samples,
                "density_scale": lm.density_scale,
                "uv_maps_created": [o for o, _ in lm.created_uv_maps],
                "texels_per_meter": lm.options.texels_per_meter,
                "max_side": lm.options.max_side, "padding": lm.options.padding,
                "uv_map": lm.options.uv_map}

    def _take_back_changes(self):
        """A bake that wrote nothing takes back what it changed before baking: the meshes it
        made single-user and the lightmap UV maps it made."""
        if self._single_users:
            import bpy  # (a modal operator's context may be gone by now)
            export_targets.undo_single_users(bpy.data, self._single_users)
            self._single_users = []
        self._remove_created_uv_maps()

    def _remove_created_uv_maps(self):
        """The lightmap UV maps this bake made, removed."""
        lightmaps = self.exported.lightmaps if self.exported is not None else None
        if lightmaps is None or not lightmaps.created_uv_maps:
            return
        import bpy
        uv_maps.remove(bpy.data, lightmaps.created_uv_maps, lightmaps.options.uv_map)
        lightmaps.created_uv_maps = []

    def run(self):
        """The whole bake, synchronously."""
        if self.job is None:
            self.start()
        return self.finish()

    def _named(self, error):
        message = (self.exported.named(error.message) if self.exported is not None
                   else error.message)
        if "no light" in message and self.exported is not None:
            # Say which lights the export left out (ray visibility, render toggles), which
            # is why the core saw none.
            dropped = [w for w in self.exported.warnings + self.exported.skipped
                       if "left out" in w or "adds no light" in w or "disabled in renders" in w]
            if dropped:
                message += " (the export: " + "; ".join(dropped[:3]) + ")"
        return BakeGIError(error.status, message)

    def _release_export(self):
        if self.exported is not None:
            self.exported.close()

    def _report(self, core, targets, hooked):
        report = dict(core)
        lightmaps = self.exported.lightmaps if self.exported is not None else None
        if lightmaps is not None:
            for stage, seconds in lightmaps.seconds.items():
                self.seconds[f"lightmap_{stage}"] = seconds
        core_seconds = report.get("seconds")
        core_seconds = core_seconds if isinstance(core_seconds, dict) else {}
        # The add-on's stages (export, bake, writeback, total: the whole call) beside the
        # core's own; a core stage of the same name is kept as core_<name>.
        seconds = {(f"core_{k}" if k in self.seconds else k): v
                   for k, v in core_seconds.items()}
        seconds.update(self.seconds)
        report["seconds"] = seconds
        report["method"] = self.method
        report["settings"] = {**(core.get("settings") or {}), **self.settings,
                              "target": self.target,
                              "objects": self.objects if isinstance(self.objects, str) else
                              [t.object_name for t in targets]}
        report["bake_points"] = (self.exported.counts.get("bake_points", 0) if self.exported
                                 else sum(t.count for t in targets))
        report["objects"] = [t.object_name for t in targets]
        report["hooked_materials"] = hooked
        report["counts"] = dict(self.exported.counts) if self.exported else {}
        core_warnings = core.get("warnings") if isinstance(core.get("warnings"), list) else []
        named = self.exported.named if self.exported is not None else (lambda w: w)
        report["warnings"] = (list(self.exported.warnings) + list(self.exported.skipped) +
                              [named(w) for w in core_warnings])
        self._check_error(report, targets)
        return report

    def _check_error(self, report, targets):
        """report["error_check"]: the core's self-check in words (error_check.py), its
        warnings added to the report's."""
        if self.exported is None or "error_estimate" not in report:
            return
        if self.target == "GRID":  # no meshes were baked: the core's warning says it all
            return
        # The bake points' object ids: the target's index for attributes, the exported
        # object's index for lightmap texels.
        by_id = (list(self.exported.object_names) if self.target == "LIGHTMAP"
                 else [t.object_name for t in targets])
        named = {entry.get("object") for entry in report["error_estimate"].get("objects") or []}
        facts = {}
        import bpy
        for index in named:
            if isinstance(index, int) and 0 <= index < len(by_id):
                obj = bpy.data.objects.get(by_id[index])
                if obj is not None and obj.type == "MESH":
                    facts[obj.name] = export_points.mesh_facts(obj.data)
        verdict = error_check.assess(report, by_id, facts, self.method, self.samples)
        if verdict is not None:
            report["error_check"] = verdict
            # First: the operator shows at most 20 warnings, and these matter most.
            report["warnings"] = verdict["warnings"] + report["warnings"]
