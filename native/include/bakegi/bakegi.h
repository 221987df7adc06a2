/*
 * bakegi.h — the only door into the bakegi core.
 *
 * Rules of this interface:
 *  - Every function returns a status (or a value that cannot fail); none throws,
 *    aborts or prints. On error, bakegi_last_error() returns a message for the
 *    calling thread that says what was wrong and where (e.g. "mesh 2, vertex 17:
 *    position is NaN").
 *  - Handles are opaque. Every *_create/_read has a matching *_destroy; passing
 *    NULL to *_destroy is allowed.
 *  - All quantities are radiometric and in SI units (metres, W, W/sr, W/m^2,
 *    W/(m^2 sr)); the conversion from Blender's light settings lives in the
 *    add-on (addon/bakegi/light_units.py), not here.
 *  - The output quantity of every bake is what Cycles writes for a Diffuse bake
 *    with only Indirect enabled and Color disabled: E_indirect / pi, so that the
 *    outgoing diffuse radiance is albedo x value (W/(m^2 sr)).
 *  - Input arrays are copied; the caller may free them after the call returns.
 */
#ifndef BAKEGI_H
#define BAKEGI_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#if defined(_WIN32)
#define BAKEGI_API __declspec(dllexport)
#else
#define BAKEGI_API __attribute__((visibility("default")))
#endif

/* ---- version ---------------------------------------------------------------------------- */

#define BAKEGI_VERSION_MAJOR 0
#define BAKEGI_VERSION_MINOR 1
#define BAKEGI_VERSION_PATCH 0

/* Packed as major * 10000 + minor * 100 + patch. */
BAKEGI_API uint32_t bakegi_version(void);
/* e.g. "0.1.0 (embree 3.13.5, tbb 2021.8)". Static storage. */
BAKEGI_API const char* bakegi_version_string(void);

/* The binary interface: raised whenever a struct below or a function's signature changes, so a
 * binding (the add-on's ctypes, addon/bakegi/native.py) can refuse a library it does not
 * match instead of passing misread memory. */
#define BAKEGI_ABI_VERSION 1
BAKEGI_API uint32_t bakegi_abi_version(void);
/* sizeof a public struct by its name ("bakegi_material_desc", "bakegi_mesh_desc",
 * "bakegi_light_desc", "bakegi_lightmap_info", "bakegi_grid_info"), 0 for another name: a binding
 * checks its own layouts against the library's. */
BAKEGI_API size_t bakegi_struct_size(const char* name);

/* ---- errors ----------------------------------------------------------------------------- */

typedef enum bakegi_status {
  BAKEGI_OK = 0,
  BAKEGI_ERROR_INVALID_ARGUMENT = 1, /* NULL pointer, bad enum, bad size, unknown option */
  BAKEGI_ERROR_INVALID_SCENE = 2,    /* NaN, degenerate or out-of-range geometry, no light */
  BAKEGI_ERROR_OUT_OF_MEMORY = 3,    /* allocation failed or the memory budget is exceeded */
  BAKEGI_ERROR_CANCELLED = 4,        /* the job was cancelled */
  BAKEGI_ERROR_IO = 5,               /* file could not be read or written */
  BAKEGI_ERROR_BAD_FILE = 6,         /* file is not a bakegi scene file or is corrupt */
  BAKEGI_ERROR_NOT_READY = 7,        /* the job has not finished yet */
  BAKEGI_ERROR_RAY_TRACER = 8,       /* Embree reported an error */
  BAKEGI_ERROR_INTERNAL = 9          /* a bug: please report with the scene file */
} bakegi_status;

/* Short constant name of a status, e.g. "BAKEGI_ERROR_INVALID_SCENE". Static storage. */
BAKEGI_API const char* bakegi_status_string(bakegi_status status);
/* Message of the last failed call on this thread ("" if none). Valid until the next
 * failing call on this thread. */
BAKEGI_API const char* bakegi_last_error(void);

/* ---- scene ------------------------------------------------------------------------------ */

typedef struct bakegi_scene bakegi_scene;

BAKEGI_API bakegi_status bakegi_scene_create(bakegi_scene** out_scene);
BAKEGI_API void bakegi_scene_destroy(bakegi_scene* scene);

/* Texture: linear (not sRGB) RGB float pixels in [0,1], row-major, row 0 at v = 0 (bottom,
 * as in Blender), sampled bilinearly with repeat wrapping (texel centres at (i + 0.5) / width)
 * at the UVs a mesh gives its triangles' corners. A texture multiplies a material's albedo
 * (albedo_texture) or its emission (bakegi_scene_set_material_emission_texture); the same
 * texture may do both. */
BAKEGI_API bakegi_status bakegi_scene_add_texture(bakegi_scene* scene, uint32_t width,
                                                  uint32_t height, const float* rgb_pixels,
                                                  uint32_t* out_texture);

#define BAKEGI_NO_TEXTURE 0xFFFFFFFFu

typedef struct bakegi_material_desc {
  float albedo[3];             /* diffuse reflectance in [0,1], linear RGB */
  uint32_t albedo_texture;     /* BAKEGI_NO_TEXTURE, or a texture that multiplies albedo */
  float emission[3];           /* emitted radiance W/(m^2 sr), linear RGB; 0 = not emissive;
                                  x an emission texture where one is set (below) */
  uint32_t emission_two_sided; /* 1: emits from both sides (Cycles 3.4 mesh emission) */
  /* Optional glossy lobe, added to the diffuse one: the normalized modified Phong BRDF
   * (Lafortune & Willems 1994) f_g = glossy * (n + 2) / (2 pi) * cos^n(alpha), alpha the
   * angle between the outgoing direction and the mirror direction of the incoming one
   * (about the shading normal), n = glossy_exponent. Energy conserving: its directional
   * albedo is at most `glossy` (equal at normal incidence). Zero-initialized = no glossy
   * lobe, so callers that set only the fields above keep a purely diffuse material. */
  float glossy[3];       /* glossy reflectance in [0,1] per channel, linear RGB; albedo +
                            glossy must not exceed 1 in any channel */
  float glossy_exponent; /* n >= 0, finite, at most 1e6 (0 = a second diffuse lobe;
                            ~1000+ is a near mirror) */
} bakegi_material_desc;

BAKEGI_API bakegi_status bakegi_scene_add_material(bakegi_scene* scene,
                                                   const bakegi_material_desc* material,
                                                   uint32_t* out_material);

/* Textured emission (an emissive screen, a printed lamp shade, a sign): material `material`
 * (its index as returned by bakegi_scene_add_material) then emits emission x texture(uv), in
 * W/(m^2 sr), at each point of its triangles, with the texture sampled as described above (a
 * mesh without UVs samples it at (0, 0), with a warning). Light sampling picks the brighter
 * parts of the texture more often (textured emitters are split into cells of a few texels,
 * their mean emission estimated once per bake), so a mostly black texture does not waste
 * samples. A texture whose values exceed 1 (an HDR image) is passed scaled into [0,1], its
 * scale moved into the material's emission. texture: an index returned by
 * bakegi_scene_add_texture, or BAKEGI_NO_TEXTURE to remove it (the default). Kept apart from
 * bakegi_material_desc so that its layout, which callers zero-initialize, stays as it was.
 * Errors (INVALID_ARGUMENT): NULL scene, a material or texture index not yet added. */
BAKEGI_API bakegi_status bakegi_scene_set_material_emission_texture(bakegi_scene* scene,
                                                                    uint32_t material,
                                                                    uint32_t texture);

/* See-through surfaces: window glass, cut-out leaves, a net curtain. Where a ray meets a
 * triangle of material `material`, the surface is present with probability opacity x the
 * opacity texture's red channel at the triangle's UVs (texture: BAKEGI_NO_TEXTURE for none),
 * and of a present surface a share `transmission` lets rays pass straight on (thin glass: no
 * refraction, no tint). A ray passes with probability 1 - present x (1 - transmission), in
 * every ray the core traces (lamp and sky shadow rays, paths, visibility); otherwise it stops
 * at the surface, which then reflects and emits as the material says: so albedo and glossy
 * are the reflectances of a surface a ray stopped at (a glass pane that reflects 8% of the
 * light it meets, passing 92%: glossy 1, transmission 0.92). transmission_ior > 0 (in
 * [1, 10]) makes the share passing depend on the angle of incidence theta as glass of that
 * index does, transmission x (1 - F(theta)) / (1 - F_avg), F the dielectric Fresnel
 * reflectance and F_avg its cosine-weighted average, so that `transmission` stays the
 * average; 0 = the same share at every angle. Defaults: opacity 1, no texture,
 * transmission 0 (opaque). Only the path tracer and the direct-light method are
 * measured with such surfaces; the other methods' transport treats them as opaque in parts
 * (a warning says so). Errors (INVALID_ARGUMENT): NULL scene, a material or texture index
 * not yet added, opacity or transmission outside [0,1] or not finite. */
BAKEGI_API bakegi_status bakegi_scene_set_material_passing(bakegi_scene* scene, uint32_t material,
                                                           float opacity, uint32_t opacity_texture,
                                                           float transmission,
                                                           float transmission_ior);

/* A triangle mesh in world space. Per-corner data has 3 entries per triangle, in the
 * order of indices. Optional arrays may be NULL. */
typedef struct bakegi_mesh_desc {
  const float* positions; /* 3 * vertex_count */
  uint32_t vertex_count;
  const uint32_t* indices; /* 3 * triangle_count, each < vertex_count */
  uint32_t triangle_count;
  const float* corner_normals;        /* optional, 9 * triangle_count; NULL = face normals */
  const float* corner_uvs;            /* optional, 6 * triangle_count; needed for textures */
  const uint32_t* triangle_materials; /* optional, triangle_count; NULL = all use `material` */
  uint32_t material;
  uint32_t object_id; /* the caller's id, reported back in messages */
} bakegi_mesh_desc;

BAKEGI_API bakegi_status bakegi_scene_add_mesh(bakegi_scene* scene, const bakegi_mesh_desc* mesh,
                                               uint32_t* out_mesh);

typedef enum bakegi_light_type {
  BAKEGI_LIGHT_POINT = 0, /* sphere light: position, radius, intensity */
  BAKEGI_LIGHT_SPOT = 1,  /* point light restricted to a cone: + direction, cone, blend */
  BAKEGI_LIGHT_SUN = 2,   /* distant light: direction, angular diameter, irradiance */
  BAKEGI_LIGHT_AREA = 3   /* one-sided planar emitter: position, axes, shape, size, radiance */
} bakegi_light_type;

typedef enum bakegi_area_shape {
  BAKEGI_AREA_SQUARE = 0,
  BAKEGI_AREA_RECTANGLE = 1,
  BAKEGI_AREA_DISK = 2,
  BAKEGI_AREA_ELLIPSE = 3
} bakegi_area_shape;

typedef struct bakegi_light_desc {
  bakegi_light_type type;
  float position[3];       /* point, spot, area: world position */
  float direction[3];      /* spot, area: the direction light is emitted towards (the light's -Z);
                              sun: the direction light travels (towards the scene) */
  float axis_u[3];         /* area: the light's local X axis (size_x along it) */
  float color[3];          /* point, spot: intensity W/sr; sun: irradiance W/m^2 on a surface
                              facing it; area: radiance W/(m^2 sr) */
  float radius;            /* point, spot: radius of the emitting sphere (0 = a true point) */
  float spot_size;         /* spot: full cone angle, radians in (0, pi]; area: Cycles' Spread, the
                              full angle of its soft-box cone in [0, pi] (0 or pi: Lambertian) */
  float spot_blend;        /* spot: softness of the cone edge, [0,1], Cycles' convention */
  float angle;             /* sun: angular diameter, radians in [0, pi) */
  bakegi_area_shape shape; /* area */
  float size_x;            /* area: side length or diameter along axis_u (metres) */
  float size_y;            /* area: along direction x axis_u; ignored for SQUARE and DISK */
  uint32_t flags;          /* bakegi_light_flags, or-ed; 0 = Cycles 3.x conventions */
} bakegi_light_desc;

/* Conventions that differ between the Cycles versions a light is matched to. */
typedef enum bakegi_light_flags {
  /* spot: inside the cone the intensity is I, softened at the edge by the blend's smoothstep
   * alone (Cycles 4.0 and later). Without it, it also falls as the cosine to the axis (3.x). */
  BAKEGI_LIGHT_SPOT_WITHOUT_COSINE = 1u,
  /* point, spot, sun, area: nothing blocks its light samples (Cycles' Cast Shadow off); rays
   * that bounce still find the light only where nothing is in front of it, as in Cycles. */
  BAKEGI_LIGHT_NO_SHADOW = 2u
} bakegi_light_flags;
#define BAKEGI_LIGHT_KNOWN_FLAGS 3u

BAKEGI_API bakegi_status bakegi_scene_add_light(bakegi_scene* scene, const bakegi_light_desc* light,
                                                uint32_t* out_light);
/* Copies light `index` (in the order added) into *out_light. */
BAKEGI_API bakegi_status bakegi_scene_get_light(const bakegi_scene* scene, uint32_t index,
                                                bakegi_light_desc* out_light);
/* Removes every light and portal, so that changed ones can be added for a relight. */
BAKEGI_API bakegi_status bakegi_scene_clear_lights(bakegi_scene* scene);

/* A window portal (Cycles' area light with Portal on): the shape of an area light (type
 * BAKEGI_LIGHT_AREA; position, direction into the room, axis_u, shape, sizes; color and
 * flags ignored) that emits nothing of its own. It only guides where the world's light is
 * sampled: from a point on its `direction` side the world's light samples aim through the
 * portals (half of them where the world is an image, all where it is a constant), so a
 * room lit by the sky through its windows finds the sky with its shadow rays instead of
 * only with bounced rays. The expected result is the same with or without portals (as in
 * Cycles); the noise is lower. Errors: INVALID_ARGUMENT (NULL, a type other than area, an
 * unknown shape), INVALID_SCENE (a shape an area light would be refused for). */
BAKEGI_API bakegi_status bakegi_scene_add_portal(bakegi_scene* scene,
                                                 const bakegi_light_desc* portal);
/* The number of portals added (since the last clear_lights). */
BAKEGI_API uint32_t bakegi_scene_portal_count(const bakegi_scene* scene);

/* Constant world (background) radiance W/(m^2 sr), seen by rays that leave the scene. */
BAKEGI_API bakegi_status bakegi_scene_set_world(bakegi_scene* scene, const float radiance[3]);

/* The world's radiance from an equirectangular image (an HDRI), as Cycles' Environment
 * Texture node maps it: a ray leaving the scene in the unit direction d reads the texture at
 * u = 0.5 - atan2(e.y, e.x) / (2 pi), v = 0.5 + asin(e.z) / pi with e = rotation * d
 * (rotation: 9 floats, column-major, orthonormal: world -> the image's frame; NULL for the
 * identity), bilinearly, and receives scale * that value, W/(m^2 sr) (an HDR image is passed
 * scaled into [0,1], its scale here). Replaces the constant world while set. Direct light
 * (every method's) and the path tracer sample the image by its light; where antiradiance,
 * meshless or a grid gather sky light themselves they take its mean over the sphere as a
 * constant world (the report warns). texture: an index returned by bakegi_scene_add_texture,
 * or BAKEGI_NO_TEXTURE to go back to the constant world.
 * Errors: INVALID_ARGUMENT (NULL scene or scale, a texture not yet added), INVALID_SCENE (a
 * negative or non-finite scale, a rotation that is not one). */
BAKEGI_API bakegi_status bakegi_scene_set_world_texture(bakegi_scene* scene, uint32_t texture,
                                                        const float scale[3],
                                                        const float* rotation);

/* Checks the whole scene (also done when a job starts). Errors name the mesh and
 * element. Warnings (e.g. triangles dropped as degenerate) go into job reports. */
BAKEGI_API bakegi_status bakegi_scene_validate(const bakegi_scene* scene);

/* Counts, for reports and tests. */
BAKEGI_API uint64_t bakegi_scene_triangle_count(const bakegi_scene* scene);
BAKEGI_API uint32_t bakegi_scene_light_count(const bakegi_scene* scene);
/* The axis-aligned box around every mesh vertex of the scene (what a grid bake covers by
 * default). BAKEGI_ERROR_INVALID_ARGUMENT for a scene without vertices. */
BAKEGI_API bakegi_status bakegi_scene_get_bounds(const bakegi_scene* scene, float out_min[3],
                                                 float out_max[3]);

/* ---- bake points ------------------------------------------------------------------------ */

/* Where the indirect field is evaluated: a position and the (shading) normal of the
 * surface there. object_ids is optional (NULL = 0 for all). */
typedef struct bakegi_points bakegi_points;

BAKEGI_API bakegi_status bakegi_points_create(const float* positions, const float* normals,
                                              const uint32_t* object_ids, uint64_t count,
                                              bakegi_points** out_points);
BAKEGI_API void bakegi_points_destroy(bakegi_points* points);
BAKEGI_API uint64_t bakegi_points_count(const bakegi_points* points);
/* Copies the points out (any output pointer may be NULL). */
BAKEGI_API bakegi_status bakegi_points_get(const bakegi_points* points, float* positions,
                                           float* normals, uint32_t* object_ids);
/* Optional: points that may share one value. candidates[i] is an earlier point (or i
 * itself) at the same place with the same normal, e.g. another corner of the same vertex; a
 * job bakes such a group once if a ray between the two points (each offset along its
 * normal) is unblocked and the normals agree, so a surface meeting the mesh at that place
 * keeps the points apart. count must equal the number of points; each candidate must be
 * <= its index and name a point that is its own candidate. Stored in scene files. */
BAKEGI_API bakegi_status bakegi_points_set_share_candidates(bakegi_points* points,
                                                            const uint32_t* candidates,
                                                            uint64_t count);
/* Optional "display probes": points inside the targets' faces where a job also estimates the
 * error of what a viewer shows between bake points (see "error_probes" below). The value
 * shown at probe k is sum_j weights[4k+j] * result[indices[4k+j]], j < 4 (the barycentric
 * weights of the corners of the face it lies in; unused entries weigh 0). object_ids may be
 * NULL (0 for all). Replaces the probes set before; count 0 removes them. Not stored in
 * scene files. */
BAKEGI_API bakegi_status bakegi_points_set_display_probes(
    bakegi_points* points, const float* positions, const float* normals, const uint32_t* object_ids,
    const uint32_t* indices, const float* weights, uint64_t count);

/* Which points lie inside or under geometry of `scene` (the test lightmaps' reject_inside
 * uses: from each point `rays` (1..4096; 0 = 32) fixed rays over the hemisphere of its normal;
 * flagged when at least backface_fraction (in (0,1]; 0 = 0.25) hit back faces closer than
 * max_distance metres (0 = any)). out_flags: one byte per point, 1 = inside. A grid's light
 * cannot know that a face lies buried (a floor under a box): Apply Grid darkens these. The
 * scene is validated and traced as by a bake. */
BAKEGI_API bakegi_status bakegi_points_flag_inside(const bakegi_points* points,
                                                   const bakegi_scene* scene, uint32_t rays,
                                                   float backface_fraction, float max_distance,
                                                   uint8_t* out_flags);

/* ---- meshes ----------------------------------------------------------------------------- */

/* A level of detail: the triangles of `indices` (three per triangle, into vertex_count xyz
 * positions) simplified by meshoptimizer's edge collapses towards target_ratio (0, 1] of
 * them, keeping the surface within max_error of the mesh's extent (1 = let the count decide;
 * the topology is kept, so it may stop above the target). out_indices has room for
 * index_count; *out_index_count gets the indices written, into the same vertices;
 * out_error (may be NULL) the deviation reached over the extent (NaN where the library
 * cannot say: meshoptimizer before 0.16). */
BAKEGI_API bakegi_status bakegi_mesh_simplify(const float* positions, uint64_t vertex_count,
                                              const uint32_t* indices, uint64_t index_count,
                                              float target_ratio, float max_error,
                                              uint32_t* out_indices, uint64_t* out_index_count,
                                              float* out_error);

/* ---- scene files ------------------------------------------------------------------------ */

/* A .bgs file holds exactly what the API received: the scene and, optionally, a set of
 * bake points. Little-endian binary, versioned, with a checksum. Files of older format
 * versions are still read (version 1: no glossy lobes; versions 1-2: no emission
 * textures; versions 1-3: no light flags, read as 0). */
BAKEGI_API bakegi_status bakegi_file_write(const char* path, const bakegi_scene* scene,
                                           const bakegi_points* points /* may be NULL */);
/* out_points may be NULL; *out_points is NULL if the file holds none. */
BAKEGI_API bakegi_status bakegi_file_read(const char* path, bakegi_scene** out_scene,
                                          bakegi_points** out_points);

/* ---- settings --------------------------------------------------------------------------- */

/* Key/value settings for a bake, validated when a job starts against the schema of its
 * method: a key the method does not read ("bins" in a path-traced bake), a wrong type, a value
 * out of range or not among its choices is an error (BAKEGI_ERROR_INVALID_ARGUMENT) naming the
 * key. Every method reads the common settings (method, samples, seed, sample_offset, threads,
 * memory_budget_mb, error_probes, error_probe_samples, fallback); antiradiance and meshless
 * also the path tracer's (max_bounces), which finishes their bake when they cannot model the
 * scene; then each its own. The schemas are the only list of keys: docs/settings.md is made
 * from them (`bakegi settings --markdown`), and bakegi_settings_describe gives one as JSON.
 * A setting's role says what a relight may change (bakegi_job_start_relight): "lighting" and
 * "execution" keys may change, "shapes" keys may not. */
typedef struct bakegi_settings bakegi_settings;

BAKEGI_API bakegi_status bakegi_settings_create(bakegi_settings** out_settings);
BAKEGI_API void bakegi_settings_destroy(bakegi_settings* settings);
BAKEGI_API bakegi_status bakegi_settings_set_int(bakegi_settings* settings, const char* key,
                                                 int64_t value);
BAKEGI_API bakegi_status bakegi_settings_set_float(bakegi_settings* settings, const char* key,
                                                   double value);
/* The settings schema of `method` (one the core registers: "pathtrace", "direct",
 * "antiradiance", "meshless"; NULL or "" lists them) as JSON: {"method", "summary",
 * "settings": [{"key", "type" ("integer" | "number" | "text"), "default", "min", "max" or
 * "choices", "role" ("shapes" | "lighting" | "execution"), "doc"}]}; without a method:
 * {"methods": [names in listing order], "default": the method a bake without the "method"
 * setting uses, the same for the C API, the CLI and the add-on}. Writes at most
 * capacity bytes including the NUL and stores the full length (without NUL) in *out_length;
 * call with capacity 0 to ask for the length. An unknown method is INVALID_ARGUMENT. */
BAKEGI_API bakegi_status bakegi_settings_describe(const char* method, char* buffer, size_t capacity,
                                                  size_t* out_length);
BAKEGI_API bakegi_status bakegi_settings_set_string(bakegi_settings* settings, const char* key,
                                                    const char* value);
/* Checks `settings` as bakegi_job_start will, without a scene: the method (the default
 * when none is named), every key, type, range and choice against its schema, and what the
 * method itself reads (e.g. meshless "viewpoint" must be "x,y,z"). BAKEGI_OK, or
 * INVALID_ARGUMENT with the message naming the first bad setting (bakegi_last_error), so a
 * caller can refuse a bake before exporting the scene. */
BAKEGI_API bakegi_status bakegi_settings_check(const bakegi_settings* settings);

/* ---- bake jobs -------------------------------------------------------------------------- */

/* A bake runs on the core's own threads. The job keeps its own copy of scene, points and
 * settings, so the caller may destroy them right after bakegi_job_start. */
typedef struct bakegi_job bakegi_job;

BAKEGI_API bakegi_status bakegi_job_start(const bakegi_scene* scene, const bakegi_points* points,
                                          const bakegi_settings* settings, bakegi_job** out_job);
/* Fraction done in [0,1]; never decreases. */
BAKEGI_API double bakegi_job_progress(const bakegi_job* job);
/* Short text of the current stage, e.g. "building BVH", "tracing 32/256 samples".
 * Copies at most capacity-1 bytes plus NUL. */
BAKEGI_API void bakegi_job_stage(const bakegi_job* job, char* buffer, size_t capacity);
/* Asks the job to stop; returns at once. A job that has not ended by then ends with
 * BAKEGI_ERROR_CANCELLED (also when its work was complete); one that has ended is left as it
 * ended. */
BAKEGI_API void bakegi_job_cancel(bakegi_job* job);
/* 1 if the job has ended (done, failed or cancelled), else 0. */
BAKEGI_API int bakegi_job_is_done(const bakegi_job* job);
/* Blocks until the job ends; returns its final status (and sets the thread's last error
 * to the job's message if it failed). */
BAKEGI_API bakegi_status bakegi_job_wait(bakegi_job* job);
/* After success: copies 3 * count floats (RGB per bake point, the output quantity above).
 * count must equal the number of bake points. */
BAKEGI_API bakegi_status bakegi_job_get_result(const bakegi_job* job, float* out_rgb,
                                               uint64_t count);
/* A JSON object describing the finished (or failed) job: seconds per stage, bake points,
 * method ("method_used": the path tracer when the method handed the bake to it), settings
 * (every value used, defaults included), rays traced, memory, warnings. With error probes
 * (setting "error_probes"): "estimated_error" (the NRMSE at bake points, a fraction; null if
 * no indirect light reached the probes), "estimated_error_interval" ([low, high], 90%),
 * "error_estimate" (both kinds of probes, per object: "object" is the bake points' object
 * id) and seconds "error_estimate"; meshless adds "meshless_cache" ("hit" | "miss" | "stale" |
 * "off"), "meshless_cache_path", "meshless_cache_bytes". Writes at most capacity bytes including
 * the NUL and stores the full length (without NUL) in *out_length; call with capacity 0
 * to ask for the length. */
BAKEGI_API bakegi_status bakegi_job_get_report(const bakegi_job* job, char* buffer, size_t capacity,
                                               size_t* out_length);
/* Cancels if still running, waits, and frees. */
BAKEGI_API void bakegi_job_destroy(bakegi_job* job);

/* ---- relighting ------------------------------------------------------------------------- */

/* 1 if `job` finished successfully and its method kept what a relight reuses (antiradiance:
 * bins, element hierarchy and links), else 0. */
BAKEGI_API int bakegi_job_can_relight(const bakegi_job* job);
/* Starts a bake of `scene` that reuses the finished `previous` job's precomputation, with
 * the previous job's settings: only direct light and the solve run again. `settings` (NULL =
 * none) may change the keys whose role in the method's schema is "lighting" or "execution"
 * (docs/settings.md; antiradiance: samples, iterations, tolerance, scheme, direct_samples,
 * seed, threads); another changed key fails with BAKEGI_ERROR_INVALID_ARGUMENT. `scene` must have
 * the same meshes, materials and textures as the previous bake's scene (lights and world may
 * differ); a difference fails the new job with BAKEGI_ERROR_INVALID_ARGUMENT. points: NULL =
 * the previous job's points. The previous job may be destroyed while the new one runs. */
BAKEGI_API bakegi_status bakegi_job_start_relight(const bakegi_job* previous,
                                                  const bakegi_scene* scene,
                                                  const bakegi_points* points,
                                                  const bakegi_settings* settings,
                                                  bakegi_job** out_job);

/* ---- lightmaps -------------------------------------------------------------------------- */

/* Lightmap textures: texels of meshes' lightmap UV maps become bake points, and the baked
 * values become padded OpenEXR files. All lightmaps of a bake share one set of bake points,
 * so that every object is baked in ONE job:
 *   1. bakegi_lightmaps_create; bakegi_lightmaps_add for each mesh (its lightmap UVs and
 *      resolution), or bakegi_lightmaps_add_to for more meshes in one atlas; optionally
 *      bakegi_lightmaps_reject_inside once all are added;
 *   2. bakegi_lightmaps_get_points -> bakegi_job_start -> bakegi_job_get_result (3 floats per
 *      point, all lightmaps' points concatenated in the order added);
 *   3. bakegi_lightmaps_write_exr for each lightmap, passing the whole result each time
 *      (or bakegi_lightmaps_resolve to have the image in memory).
 * To bake elsewhere (the CLI), write the points with bakegi_file_write and the lightmaps
 * with bakegi_lightmaps_write_file after step 1, and bake the pair with
 * `bakegi bake scene.bgs --lightmaps layout.bgl --exr-dir DIR`.
 * Texel (x, y) of a W x H lightmap covers UVs [x/W, (x+1)/W] x [y/H, (y+1)/H]; row 0 is at
 * v = 0 as in Blender (the files are written top-down, as EXR readers expect). Triangles are
 * rasterized conservatively: a texel that a triangle covers even partly gets a sample (on
 * the triangle, at the texel centre's barycentrics clamped onto it), and a texel covered by
 * several triangles gets one sample from each, averaged by covered area when written. */
typedef struct bakegi_lightmaps bakegi_lightmaps;

BAKEGI_API bakegi_status bakegi_lightmaps_create(bakegi_lightmaps** out_lightmaps);
/* What the texel samples of all the lightmaps may take, in MB (1..2^30; default 4096, the
 * job's default memory_budget_mb): bakegi_lightmaps_add refuses, before it allocates, a mesh
 * whose samples could exceed it (BAKEGI_ERROR_OUT_OF_MEMORY naming the budget). Pass the
 * bake's memory_budget_mb. */
BAKEGI_API bakegi_status bakegi_lightmaps_set_memory_budget(bakegi_lightmaps* lightmaps,
                                                            uint64_t megabytes);
/* Callable from any thread while another runs bakegi_lightmaps_add, _add_to or
 * _reject_inside on the same handle (not while it is destroyed): that call stops within a
 * texel row or 64 samples with BAKEGI_ERROR_CANCELLED, adding no partial samples, and so does
 * every later one. For a bake's Esc during its texel work. */
BAKEGI_API bakegi_status bakegi_lightmaps_cancel(bakegi_lightmaps* lightmaps);
BAKEGI_API void bakegi_lightmaps_destroy(bakegi_lightmaps* lightmaps);

/* Adds a width x height lightmap (each 1..8192) for mesh `mesh` of `scene` (its index as
 * returned by bakegi_scene_add_mesh): lightmap_uvs holds 6 * triangle_count floats (u, v per
 * corner, in the order of the mesh's indices), normally in [0,1] (parts outside are
 * clipped). Positions and shading normals come from the mesh; the points carry its
 * object_id. Triangles with zero UV or world area are skipped (counted in the info). The
 * mesh's UV seams are kept for bakegi_lightmaps_write_exr: edges shared by exactly two
 * triangles (the same two vertex indices) whose lightmap UVs differ at either end, and
 * whose shading normals agree there within 10 degrees (a hard edge is a real edge in the
 * light, not a seam to hide).
 * *out_lightmap (may be NULL) gets the lightmap's index, 0, 1, ... in the order added. */
BAKEGI_API bakegi_status bakegi_lightmaps_add(bakegi_lightmaps* lightmaps,
                                              const bakegi_scene* scene, uint32_t mesh,
                                              const float* lightmap_uvs, uint32_t width,
                                              uint32_t height, uint32_t* out_lightmap);

/* Rasterizes mesh `mesh` of `scene` into the EXISTING lightmap `lightmap` (its width and
 * height), appending samples: several objects share one atlas when the caller passes each
 * one's UVs already placed in its own region of the atlas. The samples carry the mesh's
 * object_id. Same UV rules as bakegi_lightmaps_add; the lightmap's samples (and the
 * first_point of the lightmaps after it) change, so call before bakegi_lightmaps_get_points.
 * Texels covered by several meshes (overlapping UVs) average their samples by coverage.
 * The mesh's UV seams (as for bakegi_lightmaps_add, in the atlas UVs given) join the
 * lightmap's.
 * Refused (INVALID_ARGUMENT) after bakegi_lightmaps_reject_inside has run, whose rejection
 * the new samples would miss; then nothing is added. */
BAKEGI_API bakegi_status bakegi_lightmaps_add_to(bakegi_lightmaps* lightmaps, uint32_t lightmap,
                                                 const bakegi_scene* scene, uint32_t mesh,
                                                 const float* lightmap_uvs);

/* Drops the samples of every lightmap that lie inside or under other geometry of `scene`
 * (the whole scene, lights included: it is validated and traced like a bake): from each
 * sample, `rays` (1..4096; 0 = 32) fixed rays over its hemisphere; a sample is dropped when
 * at least backface_fraction (in (0,1]; 0 = 0.25) of them hit back faces closer than
 * max_distance metres (0 = any distance). Their texels are filled from neighbours when
 * written. Call after the last bakegi_lightmaps_add and before bakegi_lightmaps_get_points.
 * *out_rejected (may be NULL) gets the number of samples dropped. */
BAKEGI_API bakegi_status bakegi_lightmaps_reject_inside(bakegi_lightmaps* lightmaps,
                                                        const bakegi_scene* scene, uint32_t rays,
                                                        float backface_fraction, float max_distance,
                                                        uint64_t* out_rejected);

typedef struct bakegi_lightmap_info {
  uint32_t width, height;
  uint64_t first_point;       /* its samples are points [first_point, first_point + */
  uint64_t point_count;       /*   point_count) of bakegi_lightmaps_get_points */
  uint64_t covered_texels;    /* texels with at least one sample */
  uint64_t rejected_samples;  /* dropped by bakegi_lightmaps_reject_inside */
  uint64_t skipped_triangles; /* zero UV area or zero world area */
} bakegi_lightmap_info;

BAKEGI_API uint32_t bakegi_lightmaps_count(const bakegi_lightmaps* lightmaps);
BAKEGI_API bakegi_status bakegi_lightmaps_get_info(const bakegi_lightmaps* lightmaps,
                                                   uint32_t lightmap,
                                                   bakegi_lightmap_info* out_info);
/* All lightmaps' samples as bake points (count = the sum of their point_count), for
 * bakegi_job_start. Fails if there are none. */
BAKEGI_API bakegi_status bakegi_lightmaps_get_points(const bakegi_lightmaps* lightmaps,
                                                     bakegi_points** out_points);

typedef enum bakegi_exr_compression {
  BAKEGI_EXR_ZIP = 0, /* lossless, the default */
  BAKEGI_EXR_PIZ = 1, /* lossless, better on noisy images */
  BAKEGI_EXR_NONE = 2
} bakegi_exr_compression;

/* Writes lightmap `lightmap` as an RGB OpenEXR file at path (UTF-8; written to a temporary
 * file beside it and renamed, so an existing file is replaced only by a complete one).
 * rgb: 3 * count floats, the bake result for ALL points of bakegi_lightmaps_get_points
 * (count must equal their number); each texel is the coverage-weighted mean of its samples,
 * then `padding` (0..1024) rounds of dilation fill the texels around covered ones (gutters,
 * rejected texels) from their neighbours: use at least the UV margin in texels. Texels
 * farther from any chart stay 0. Then the UV seams are stitched: the texels on both sides
 * of each seam are adjusted (least squares, a few dozen Gauss-Seidel sweeps over points
 * 1/2 texel apart) so that bilinear lookups at the same surface point read the same value
 * from either side, as GPU filtering reads them (texel centres at (i + 0.5) / W). Only
 * texels within a texel of a seam change (and only filled ones: texels still 0 stay 0);
 * a lightmap without seams is written as before. full_float: 0 = half floats (enough for
 * light, half the size), 1 = 32-bit floats. compression: a bakegi_exr_compression value
 * (passed as an integer, so that a value outside the enum is refused rather than stored in
 * one). */
BAKEGI_API bakegi_status bakegi_lightmaps_write_exr(const bakegi_lightmaps* lightmaps,
                                                    uint32_t lightmap, const float* rgb,
                                                    uint64_t count, const char* path,
                                                    uint32_t padding, int full_float,
                                                    uint32_t compression);

/* Lightmap `lightmap` resolved into memory the caller owns: the image that
 * bakegi_lightmaps_write_exr writes (same rgb, count and padding rules; texel means,
 * dilation, seam stitching), before any half-float rounding. width * height pixels of
 * `channels` floats (3: RGB; 4: RGBA with alpha 1), rows bottom-up (row 0 at v = 0) as
 * Blender's Image.pixels holds them; width and height from bakegi_lightmaps_get_info.
 * capacity: the floats out_pixels holds (at least width * height * channels). */
BAKEGI_API bakegi_status bakegi_lightmaps_resolve(const bakegi_lightmaps* lightmaps,
                                                  uint32_t lightmap, const float* rgb,
                                                  uint64_t count, uint32_t padding,
                                                  uint32_t channels, float* out_pixels,
                                                  uint64_t capacity);

/* A .bgl lightmap layout file (path in UTF-8): every lightmap's size, samples (positions,
 * normals, object ids, face normals, texel, weight), coverage, UV seams and counters, and
 * whether bakegi_lightmaps_reject_inside has run, so that the CLI can write the EXRs of a
 * .bgs file whose bake points came from bakegi_lightmaps_get_points
 * (bakegi.export_scene_file(target='LIGHTMAP') writes both). Files of format version 1
 * (before seams were stored) are still read, as lightmaps without seams. Little-endian,
 * versioned, checksummed, and read with every count checked against the bytes left before
 * anything is allocated (format in native/src/lightmap/lightmap_layout_file.h). A
 * lightmaps object read back gives the same points, info and EXRs as the one written.
 * Write: atomic (a temporary file beside path, then a rename); BAKEGI_ERROR_IO if it cannot
 * be written. Read: BAKEGI_ERROR_IO if the file cannot be read, BAKEGI_ERROR_BAD_FILE
 * naming what is wrong if it is not a layout file, is truncated or corrupt; *out_lightmaps
 * is NULL on failure, else owned by the caller (bakegi_lightmaps_destroy). */
BAKEGI_API bakegi_status bakegi_lightmaps_write_file(const bakegi_lightmaps* lightmaps,
                                                     const char* path);
BAKEGI_API bakegi_status bakegi_lightmaps_read_file(const char* path,
                                                    bakegi_lightmaps** out_lightmaps);

/* ---- irradiance vector grids -------------------------------------------------------------- */

/* An Irradiance Vector Grid (Pacanowski et al. 2008; docs/ivg.md): a box of grid vertices,
 * each holding six irradiance vectors (one per axis hemisphere, RGB), gathered from a bake's
 * full lighting so that ANY surface inside the box (moved, added, decimated or subdivided
 * meshes) gets its indirect light from the grid without a new bake:
 *   1. bakegi_grid_create (the layout: bounds and resolution);
 *   2. bakegi_job_start_grid -> bakegi_job_wait -> bakegi_job_get_grid (the baked grid);
 *   3. bakegi_grid_evaluate at any positions and normals (values in the output convention,
 *      like a bake's), and/or bakegi_grid_write_file (.bgivg), bakegi_grid_read_file.
 * Grid vertices sit at the centres of the box's cells. */
typedef struct bakegi_grid bakegi_grid;

typedef struct bakegi_grid_info {
  float bounds_min[3], bounds_max[3];
  uint32_t resolution[3]; /* vertices along x, y, z */
  uint64_t vertex_count;
  uint64_t invalid_vertices; /* inside geometry: filled from their neighbours */
} bakegi_grid_info;

/* A grid layout (not yet baked: all zero) over [bounds_min, bounds_max] (a flat axis is widened
 * to one cell) with cells of about cell_size metres (0 = 32 cells on the longest axis), made
 * coarser until it has at most max_vertices vertices (0 = 262144, i.e. 64^3; each vertex takes
 * 217 bytes while baking, 433 when the scene has a world or emissive surfaces). At least 2 and at
 * most 1024 vertices per axis. */
BAKEGI_API bakegi_status bakegi_grid_create(const float bounds_min[3], const float bounds_max[3],
                                            float cell_size, uint64_t max_vertices,
                                            bakegi_grid** out_grid);
BAKEGI_API void bakegi_grid_destroy(bakegi_grid* grid);
BAKEGI_API bakegi_status bakegi_grid_get_info(const bakegi_grid* grid, bakegi_grid_info* out_info);

/* Bakes `scene` into a grid with `layout`'s bounds and resolution: the method of `settings`
 * solves as for bakegi_job_start, then from every grid vertex rays_per_hemisphere rays
 * (1..65536; 0 = 64) per hemisphere gather the light the surfaces reflect (the path tracer
 * continues a path from each hit; other methods give direct light plus their indirect field
 * there). Vertices whose rays hit back faces a quarter of the time or more are inside
 * geometry and filled by push-pull from the others. Progress, stage, cancel, wait and the
 * report work as for any job (report: grid_vertices, grid_invalid_vertices, grid_resolution,
 * seconds.grid_gather); bakegi_job_get_result has no points to give. */
BAKEGI_API bakegi_status bakegi_job_start_grid(const bakegi_scene* scene, const bakegi_grid* layout,
                                               uint32_t rays_per_hemisphere,
                                               const bakegi_settings* settings,
                                               bakegi_job** out_job);
/* After a grid job succeeded: its grid, as a new handle owned by the caller. */
BAKEGI_API bakegi_status bakegi_job_get_grid(const bakegi_job* job, bakegi_grid** out_grid);

typedef enum bakegi_grid_interpolation {
  BAKEGI_GRID_TRILINEAR = 0, /* the default: 8 vertices */
  BAKEGI_GRID_TRICUBIC = 1   /* cubic B-spline over 64 vertices: smoother, about 8x slower */
} bakegi_grid_interpolation;

typedef enum bakegi_grid_directional {
  BAKEGI_GRID_SQUARED = 0, /* the paper's n_a^2 weights: exact along the axes, dark between
                            * them (uniform light at 45 degrees reads 71%) */
  BAKEGI_GRID_ABSOLUTE = 1 /* |n_a| weights: exact along the axes and under uniform light */
} bakegi_grid_directional;

/* The grid's indirect light at `count` points: positions and normals 3 floats each (normals
 * need not be unit; a zero normal gives 0), out_rgb 3 floats each, in the output convention
 * (the value a bake writes: outgoing diffuse radiance = albedo x value). Points outside the
 * box take the nearest vertices' values. interpolation: a bakegi_grid_interpolation value;
 * directional: a bakegi_grid_directional value (docs/ivg.md measures both). */
BAKEGI_API bakegi_status bakegi_grid_evaluate(const bakegi_grid* grid, const float* positions,
                                              const float* normals, uint64_t count,
                                              int interpolation, int directional, float* out_rgb);

typedef enum bakegi_grid_encoding {
  BAKEGI_GRID_FLOAT = 0,     /* the 3x3 float matrices: exact, 216 bytes a vertex */
  BAKEGI_GRID_QUANTIZED = 1, /* the paper's compression (a direction and a colour per
                              * hemisphere) quantized to 24 bits + R9G9B9E5: 42 bytes a vertex */
  BAKEGI_GRID_FACTORED = 2   /* the same direction and colour in floats: 144 bytes a vertex */
} bakegi_grid_encoding;

/* bakegi_grid_evaluate where the scene is known (native/src/grid/grid_visibility.h): with
 * BAKEGI_GRID_VISIBILITY each point reads only the grid vertices it sees (a shadow ray to
 * each vertex of its interpolation), so light does not leak through walls thinner than a
 * cell (a point that sees none of its 8 vertices reads those of the 4^3 around it that it
 * sees); with BAKEGI_GRID_DARKEN_BURIED points inside or under geometry (as
 * bakegi_points_flag_inside finds them, 32 rays) read 0, as a bake sees them. out_codes (may
 * be NULL): per point 0 = read, 1 = unsure (it saw no grid vertex near it: 0 written; a face
 * outside the grid's rooms, or a grid too coarse for the place), 2 = buried. The scene is validated
 * and its BVH built (the cost of a bake's first step).
 * BAKEGI_GRID_PAGE_VISIBILITY (alone, trilinear) reads as the web page does, without rays
 * from the points: from the visibility volume bakegi_web_export writes beside the grid
 * (native/src/grid/grid_visibility_volume.h), built here over the scene, times the factor the
 * export stores per glTF vertex (native/src/web/corner_grid_reach.h: 0 where the rays above
 * read nothing); code 1 where it reads 0 for a point that sees no vertex, else the rays'
 * code where they read nothing. */
typedef enum bakegi_grid_scene_flags {
  BAKEGI_GRID_VISIBILITY = 1,
  BAKEGI_GRID_DARKEN_BURIED = 2,
  BAKEGI_GRID_PAGE_VISIBILITY = 4
} bakegi_grid_scene_flags;
BAKEGI_API bakegi_status bakegi_grid_evaluate_in_scene(const bakegi_grid* grid,
                                                       const bakegi_scene* scene,
                                                       const float* positions, const float* normals,
                                                       uint64_t count, int interpolation,
                                                       int directional, uint32_t flags,
                                                       float* out_rgb, uint8_t* out_codes);

/* The .bgivg file (format in native/src/grid/grid_file.h). encoding: a bakegi_grid_encoding
 * value. info_json (may be NULL: the grid's own, "{}" unless read from a file): a JSON object
 * stored with the grid (what made it). Written atomically; BAKEGI_ERROR_IO if it cannot be. */
BAKEGI_API bakegi_status bakegi_grid_write_file(const bakegi_grid* grid, const char* path,
                                                int encoding, const char* info_json);
/* Reads a .bgivg file (a quantized or factored one comes back expanded to matrices).
 * BAKEGI_ERROR_IO if unreadable, BAKEGI_ERROR_BAD_FILE naming what is wrong. */
BAKEGI_API bakegi_status bakegi_grid_read_file(const char* path, bakegi_grid** out_grid);
/* The JSON stored with a grid read from a file ("{}" otherwise), like bakegi_job_get_report:
 * writes at most capacity bytes (NUL included) and the full length to *out_length (may be
 * NULL). */
BAKEGI_API bakegi_status bakegi_grid_get_info_json(const bakegi_grid* grid, char* buffer,
                                                   size_t capacity, size_t* out_length);
/* The grid the web page streams, as a new grid: `grid`'s vectors plus its emitted light (the
 * world's and emissive surfaces' direct light, gathered with the grid when the scene has
 * either, and kept in its file), so that bakegi_grid_evaluate reads what the page draws
 * besides its lamps. *out_has_emitted (may be NULL): 1 if `grid` holds emitted light, else 0
 * (and the new grid equals it). out_grid NULL: only the question is answered (no copy). */
BAKEGI_API bakegi_status bakegi_grid_with_emitted_light(const bakegi_grid* grid,
                                                        bakegi_grid** out_grid,
                                                        int* out_has_emitted);

/* ---- the web page (issue 16, section 4 of the grid's paper; native/src/web/) --------- */

/* Writes a scene for the web page into `folder` (made if missing): scene.gltf + scene.bin
 * (glTF 2.0; every mesh a progressive mesh: see native/src/web/gltf_export.h) and, when
 * `grid` is given, grid.bgivg (quantized) and grid_visibility.bin (which grid vertices each
 * place sees, so that the page does not read light through thin walls: built with rays over
 * the scene, native/src/grid/grid_visibility_volume.h), and with it every glTF vertex's
 * _BAKEGI_READS_GRID (0 where the corner reads nothing of the grid: pressed against or
 * buried under geometry, native/src/web/corner_grid_reach.h). camera (may be NULL): 9 floats,
 * position xyz, the rotation quaternion xyzw (looking down -Z), vertical field of view
 * (radians), aspect ratio. Files are written atomically; BAKEGI_ERROR_IO names what could not be
 * written. */
BAKEGI_API bakegi_status bakegi_web_export(const bakegi_scene* scene, const bakegi_grid* grid,
                                           const char* folder, const float* camera);
/* The order a server streams the grid's vertices in: the eight corners, then coarse to fine,
 * stratified over slices of the longest axis (random within a slice, fixed by seed).
 * out_order: room for every vertex (bakegi_grid_info's vertex count). */
BAKEGI_API bakegi_status bakegi_grid_stream_order(const bakegi_grid* grid, uint64_t seed,
                                                  uint32_t* out_order);
/* The vertices' hemispheres as sent: encoding BAKEGI_GRID_QUANTIZED (per hemisphere u8
 * direction[3] + u32 R9G9B9E5 colour: 42 bytes a vertex) or BAKEGI_GRID_FACTORED (f32
 * direction[3] + f32 colour[3]: 144 bytes), hemispheres +x -x +y -y +z -z, vertex by vertex
 * in the order given: the .bgivg file's bytes for them. */
BAKEGI_API bakegi_status bakegi_grid_encode_vertices(const bakegi_grid* grid,
                                                     const uint32_t* vertices, uint64_t count,
                                                     int encoding, uint8_t* out_bytes);

/* ---- the splatting preview (issue 17; native/src/solvers/splatting/) ----------------- */

/* Direct light plus one bounce splatted from reflective-shadow-map VPLs through the
 * adaptive multiresolution buffer (Nichols & Wyman 2009), seen from a camera: the render
 * engine "BakeGI Preview". The preview copies the scene's geometry and materials and builds
 * its BVH once; lights change with bakegi_preview_set_lights without rebuilding it. */
typedef struct bakegi_preview bakegi_preview;

BAKEGI_API bakegi_status bakegi_preview_create(const bakegi_scene* scene,
                                               bakegi_preview** out_preview);
BAKEGI_API void bakegi_preview_destroy(bakegi_preview* preview);
/* Takes the lights and the world's radiance of `lights` (its meshes are ignored). */
BAKEGI_API bakegi_status bakegi_preview_set_lights(bakegi_preview* preview,
                                                   const bakegi_scene* lights);
/* Renders width x height pixels, the top row first. camera: 12 floats, position xyz, the
 * rotation quaternion xyzw (looking down -Z, up +Y, as a Blender camera), vertical field of
 * view (radians), lens shift x and y (in units of the larger image side), orthographic
 * scale (0: perspective). settings: the splatting method's (may be NULL: defaults). Any
 * output may be NULL: out_rgba (w*h*4) the radiance (alpha 1 where a surface is seen, 0
 * where the world shows), out_direct and out_indirect (w*h*3) E_direct/pi and E_indirect/pi,
 * out_levels (w*h) the subsplat level covering each pixel (texels of 2^level pixels; 255
 * where none, and everywhere for refinement "illumination").
 * The frame's report (timings per step, VPLs, subsplats per level) is kept for
 * bakegi_preview_get_report. */
BAKEGI_API bakegi_status bakegi_preview_render(bakegi_preview* preview, const float* camera,
                                               uint32_t width, uint32_t height,
                                               const bakegi_settings* settings, float* out_rgba,
                                               float* out_direct, float* out_indirect,
                                               uint8_t* out_levels);
/* The last frame's report as JSON (the text contract of bakegi_job_get_report). */
BAKEGI_API bakegi_status bakegi_preview_get_report(const bakegi_preview* preview, char* buffer,
                                                   size_t capacity, size_t* out_length);

#ifdef __cplusplus
}
#endif

#endif /* BAKEGI_H */
