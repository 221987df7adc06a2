// `bakegi`: bake a scene file, sweep quality settings against a reference, inspect a file,
// compare two results. Uses only the C API (bakegi.h) and the shared error metric.
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "bakegi/bakegi.h"
#include "commands.h"
#include "core_handles.h"
#include "exit_codes.h"
#include "file_error.h"
#include "interrupt.h"
#include "json_value.h"
#include "method_catalog.h"
#include "usage_error.h"

namespace {

constexpr const char* kUsage = R"(usage: bakegi <command> [arguments]

commands:
  bake scene.bgs --out values.npy [settings] [--report report.json]
       [--lightmaps layout.bgl --exr-dir DIR [--padding N] [--float]
        [--compression zip|piz|none]]
      Bakes the scene file's bake points; writes float32 (n, 3) .npy and prints the
      core's report (JSON) on stdout. Progress goes to stderr; Ctrl-C cancels.
      With --lightmaps (the lightmap layout exported with the scene file, whose bake
      points must be the layout's) and --exr-dir, also writes DIR/lightmap_<i>.exr for
      every lightmap i (DIR is created if missing), padded by N texels (default 4), half
      floats (--float: 32-bit), ZIP-compressed by default, and prints a line per file on
      stderr; --out is then optional.
  sweep scene.bgs --samples 1,2,4,... --reference ref.npy --out sweep.json [settings]
        [--repeat R]
      Bakes at each sample count, records wall seconds, error against the reference,
      memory, rays and bake points per run as JSON. --repeat keeps the fastest of R runs.
  info scene.bgs
      Triangles, lights and bake points in the file, whether the core accepts the scene,
      and the library version.
  compare values.npy reference.npy
      Prints the error of values against reference as one line of JSON: "nrmse" and
      "weighted_relative_rmse" (the project's metrics, on luminance) and "relative_rmse"
      (the older per-channel one that `sweep` reports as "error").
  points scene.bgs [--positions p.npy] [--normals n.npy] [--object-ids ids.npy]
      Writes the file's bake points as float32 arrays.
  subset scene.bgs --count K --out subset.bgs [--indices idx.npy] [--seed S]
      Writes the scene with K of its bake points chosen at random (seeded; in file order)
      and their indices in the file as float32, for references on large scenes.
  relight scene.bgs --out values.npy [--move x,y,z] [--scale k] [--repeat R] [--check]
          [settings]
      Bakes once, moves every light by (x,y,z) metres and scales its power by k, then
      relights from the first bake's precomputation (antiradiance, meshless), keeping the
      fastest of R relights; --check also bakes the changed scene from scratch and compares.
      Prints JSON with the seconds of the full bake and of the relight.
  converge scene.bgs --method antiradiance --iterations K [--reference-iterations R]
           --out convergence.json [settings]
      Antiradiance Fig. 5: error after 1..K iterations of the symmetric and asymmetric
      schemes against an R-iteration solution (default 300), by relighting one bake.
  grid bake scene.bgs --out grid.bgivg [--cell S] [--max-vertices N] [--rays R]
            [--bounds x0,y0,z0,x1,y1,z1] [--quantized] [--report r.json] [settings]
      Bakes an Irradiance Vector Grid over the bounds (default: the scene's) with cells of
      about S metres (default: 32 on the longest axis), at most N vertices (default 64^3),
      R rays per vertex hemisphere (default 64); --quantized stores 24-bit directions and
      R9G9B9E5 colours (docs/ivg.md). Prints the report (JSON) on stdout.
  grid apply grid.bgivg scene.bgs --out values.npy [--tricubic] [--absolute] [--repeat R]
            [--with-emitted]
      Lights the scene file's bake points from the grid (no bake) and prints the seconds
      (the fastest of R runs) and points as JSON. --absolute: |n| directional weights
      instead of the paper's n^2 (docs/ivg.md). --with-emitted: adds the world's and
      emitters' direct light the grid carries (what the web page draws from it).
  grid info grid.bgivg
      Bounds, resolution, vertices inside geometry and what made the grid.
  web export scene.bgs --out FOLDER [--grid grid.bgivg] [--camera x,y,z,qx,qy,qz,qw,yfov,aspect]
             [--client DIR]
      Writes the scene for the web page: scene.gltf + scene.bin (glTF 2.0, progressive
      meshes), grid.bgivg with its visibility volume grid_visibility.bin, and the page's
      files from DIR (the add-on's web/ folder).
  serve FOLDER [--port P] [--vectors V] [--vertices N] [--float]
      Serves a web export on 127.0.0.1:P (default 8080; 0 picks a free port): its files,
      and its grid and geometry as interleaved packets of V grid vectors (default 512,
      after the 8 corners) and N vertices (default 4096); --float sends the grid's vectors
      as floats instead of quantized (docs/ivg.md).
  preview scene.bgs --camera x,y,z,qx,qy,qz,qw,yfov,shiftx,shifty,ortho,0 [--width W]
          [--height H] [--out rgba.npy] [--direct d.npy] [--indirect i.npy]
          [--levels l.npy] [--repeat R]
          [settings]
      One frame of the splatting preview (direct light + one splatted bounce; default
      640x480, top row first): writes (H, W, 4) radiance, (H, W, 3) E/pi arrays and the
      (H, W) subsplat level of each pixel (255: none), and
      prints each frame's report (timings per step, VPLs, subsplats per level). --repeat
      renders again with the G-buffer kept, as when only lights move.
  settings [METHOD] [--markdown | --json]
      The settings each method reads (all methods without METHOD): key, type, default,
      range or choices, role (shapes | lighting | execution) and meaning, from the core's
      schemas. --markdown writes docs/settings.md.

settings (passed to the core, which checks them against the method's schema):
  --method M          one of the methods below (the core's list)
  --samples N         samples per bake point
  --seed S            random seed (results are deterministic for a seed and thread count)
  --sample-offset K   first sample index, to make a long bake in chunks
  --threads T         0 = all cores
  --max-bounces B     path length cap
  --cache-dir D       antiradiance, meshless: save the precomputation in folder D and reuse
                      it when the scene and settings are the same (setting cache_dir)
  --set key=value     any other setting of the method ('bakegi settings METHOD' lists them)

error = relative RMSE over bake points, luminance-weighted (Rec. 709):
  sqrt(sum_i sum_c w_c (v_ic - r_ic)^2 / sum_i sum_c w_c r_ic^2), w = (0.2126, 0.7152, 0.0722)

exit codes: 0 ok, 1 bake failed or scene refused, 2 bad command line, 3 file error,
            130 cancelled (Ctrl-C)
)";

// The methods as the core lists them, so that the help never names one the core lacks.
void print_method_list(FILE* out) {
  const std::string fallback = bakegi::cli::default_method();
  std::fputs("\nmethods:", out);
  for (const std::string& name : bakegi::cli::method_names()) {
    std::fprintf(out, " %s%s", name.c_str(), name == fallback ? " (default)" : "");
  }
  std::fputs("\n", out);
}

}  // namespace

int main(int argc, char** argv) {
  using namespace bakegi::cli;
  if (argc < 2 || !std::strcmp(argv[1], "--help") || !std::strcmp(argv[1], "-h") ||
      !std::strcmp(argv[1], "help")) {
    FILE* out = argc < 2 ? stderr : stdout;
    std::fputs(kUsage, out);
    print_method_list(out);
    return argc < 2 ? kExitUsage : kExitOk;
  }
  if (!std::strcmp(argv[1], "--version")) {
    std::printf("bakegi %s\n", bakegi_version_string());
    return kExitOk;
  }
  install_interrupt_handler();
  const std::string command = argv[1];
  const std::vector<std::string> args(argv + 2, argv + argc);
  try {
    if (command == "bake") return run_bake_command(args);
    if (command == "sweep") return run_sweep_command(args);
    if (command == "info") return run_info_command(args);
    if (command == "compare") return run_compare_command(args);
    if (command == "points") return run_points_command(args);
    if (command == "relight") return run_relight_command(args);
    if (command == "converge") return run_converge_command(args);
    if (command == "subset") return run_subset_command(args);
    if (command == "settings") return run_settings_command(args);
    if (command == "grid") return run_grid_command(args);
    if (command == "web") return run_web_command(args);
    if (command == "serve") return run_serve_command(args);
    if (command == "preview") return run_preview_command(args);
    throw UsageError("unknown command '" + command + "'");
  } catch (const UsageError& e) {
    std::fprintf(stderr, "bakegi: %s\n(run 'bakegi --help' for usage)\n", e.what());
    return kExitUsage;
  } catch (const CoreError& e) {
    std::fprintf(stderr, "bakegi: %s\n", e.what());
    if (e.status() == BAKEGI_ERROR_CANCELLED) return kExitCancelled;
    if (e.status() == BAKEGI_ERROR_IO) return kExitIo;
    return kExitBakeFailed;
  } catch (const FileError& e) {
    std::fprintf(stderr, "bakegi: %s\n", e.what());
    return kExitIo;
  } catch (const JsonError& e) {
    std::fprintf(stderr, "bakegi: the core's report is not valid JSON: %s\n", e.what());
    return kExitBakeFailed;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bakegi: %s\n", e.what());
    return kExitBakeFailed;
  }
}
