/*
 * radiosity.h - the public interface of the radiosity library.
 *
 * Radiosity solves the rendering equation for diffuse surfaces as an exchange of energy between
 * patches:  B_k = E_k + rho_k * sum_j B_j A_j F_jk / A_k.
 *
 * The data flows one way:  scene -> mesh -> form factors -> solver -> outputs.
 *   rad_scene   what was loaded: a patch system with given form factors (.ffm) or geometry.
 *   rad_system  the scene cut into patches (which shoot) and elements (which receive), with a
 *               form-factor provider; it holds the radiosity solution.
 *   rad_solve   runs one of the classic solvers on a system.
 *
 * Conventions (after Embree and SQLite):
 *   - Every fallible call returns a rad_status; the message is kept on the context
 *     (rad_context_error) until the next failing call.
 *   - Each create has one destroy; destroying NULL is fine.
 *   - Option structs are valid when zeroed: zero means "the default".
 *   - The library never exits and never prints; warnings go to the log callback.
 *   - Threads: the library runs its own worker threads (rad_context_options.threads). A context
 *     and everything made on it (scenes, systems, images) are used by one caller thread at a
 *     time; objects of different contexts may be used on different threads at once. A scene is
 *     not read-only even through a const pointer: the first call that traces rays on it builds
 *     and keeps its ray structure.
 *   - Units: see docs/units.md. Emission in scene files is radiance L; the solver works in
 *     radiosity (exitance) B = pi L. Patch systems (.ffm) give emission directly as radiosity.
 */
#ifndef RADIOSITY_H
#define RADIOSITY_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* ---------------------------------------------------------------------------------------------
 * Status codes
 * ------------------------------------------------------------------------------------------- */

typedef enum rad_status {
    RAD_OK = 0,
    RAD_ERROR_INVALID_ARGUMENT, /* a bad value handed to the library */
    RAD_ERROR_PARSE,            /* an input file is malformed; the message names file:line */
    RAD_ERROR_IO,               /* a file could not be opened, read or written */
    RAD_ERROR_NO_MEMORY,        /* an allocation failed */
    RAD_ERROR_MEMORY_BUDGET,    /* the work would not fit rad_context_options.max_memory */
    RAD_ERROR_UNSUPPORTED,      /* a format or feature this build does not handle */
    RAD_ERROR_CANCELLED,        /* the progress callback asked to stop */
    RAD_ERROR_INTERNAL          /* a failure inside a dependency (Embree, assimp) */
} rad_status;

/* A short name for a status ("parse error"); static storage. */
const char *rad_status_name(rad_status status);

/* The version of this header; rad_version() gives the library's, the same when they match. */
#define RAD_VERSION_MAJOR 0
#define RAD_VERSION_MINOR 1
#define RAD_VERSION_PATCH 0
/* One number to compare: MAJOR * 10000 + MINOR * 100 + PATCH. */
#define RAD_VERSION_NUMBER (RAD_VERSION_MAJOR * 10000 + RAD_VERSION_MINOR * 100 + RAD_VERSION_PATCH)

/* The library version, "MAJOR.MINOR.PATCH"; static storage. */
const char *rad_version(void);

/* ---------------------------------------------------------------------------------------------
 * Context: allocator, log, progress, threads, limits, and the last error
 * ------------------------------------------------------------------------------------------- */

typedef struct rad_context rad_context;

typedef enum rad_log_level { RAD_LOG_INFO = 0, RAD_LOG_WARNING = 1 } rad_log_level;

typedef void (*rad_log_fn)(void *user, rad_log_level level, const char *message);

/* Called with every error the library records on the context, as it records it (the same
 * message rad_context_error then gives): for callers that log or count errors where they
 * happen. The failing call still returns its status. */
typedef void (*rad_error_fn)(void *user, rad_status status, const char *message);

/* Called now and then during long work. `phase` names the step ("form factors", "shooting");
 * done/total measure it in the phase's own unit. Return nonzero to cancel: the running call
 * then returns RAD_ERROR_CANCELLED and leaves its results as far as they got. */
typedef int (*rad_progress_fn)(void *user, const char *phase, double done, double total);

/* One allocator for everything the library allocates itself. All three functions or none.
 * With more than one thread the functions are called from worker threads at once: they must be
 * thread-safe (malloc is). */
typedef struct rad_allocator {
    void *(*allocate)(void *user, size_t size);
    void *(*reallocate)(void *user, void *pointer, size_t size);
    void (*release)(void *user, void *pointer);
    void *user;
} rad_allocator;

typedef struct rad_context_options {
    rad_allocator allocator; /* zero: malloc, realloc, free */
    rad_log_fn log;          /* zero: warnings are dropped */
    void *log_user;
    rad_progress_fn progress; /* zero: no progress reports */
    void *progress_user;
    int threads;          /* worker threads, 0..RAD_MAX_THREADS; zero: all cores */
    uint64_t seed;        /* seed for every random choice; the same seed gives the same result */
    uint64_t max_memory;  /* bytes a form-factor matrix or dense solve may take; zero: 2 GiB */
    rad_error_fn on_error; /* zero: none */
    void *error_user;
} rad_context_options;

/* The most worker threads a context takes: OpenMP's per-thread state for more crashes. */
#define RAD_MAX_THREADS 4096

/* RAD_ERROR_INVALID_ARGUMENT when threads is outside 0..RAD_MAX_THREADS or the allocator is
 * given in part; no context is made then, so the message goes to options->on_error only. */
rad_status rad_context_create(const rad_context_options *options, rad_context **out);
void rad_context_destroy(rad_context *context);

/* The message of the last failing call ("file:line: what is wrong" for parse errors), or "".
 * Lives until the next failing call on this context. */
const char *rad_context_error(const rad_context *context);

/* RAD_OK when `bytes` fit the context's memory budget (max_memory); otherwise
 * RAD_ERROR_MEMORY_BUDGET with a message naming `what` and both sizes. For callers that allocate
 * large tables for the library (e.g. for rad_system_surface_form_factors). */
rad_status rad_context_check_memory(rad_context *context, double bytes, const char *what);

/* Bytes (1 to 4) of the well-formed UTF-8 character that `text` starts with; 0 at the end of
 * the string or when the bytes there are not UTF-8. Names and paths come from files and may be
 * in any encoding: JSON writers replace each byte this refuses with U+FFFD. */
int rad_utf8_char_length(const char *text);

/* ---------------------------------------------------------------------------------------------
 * Scenes
 * ------------------------------------------------------------------------------------------- */

typedef struct rad_scene rad_scene;

/* Loads a scene file: ".ffm" is a patch system (docs/formats.md); anything else goes through
 * assimp (OBJ/MTL, glTF, GLB, PLY, ...). */
rad_status rad_scene_load(rad_context *context, const char *path, rad_scene **out);

/* Parses a patch system from text. `source_name` is used in error messages. */
rad_status rad_scene_parse_ffm(rad_context *context, const char *text, size_t length,
                               const char *source_name, rad_scene **out);

/* Built-in scenes by name ("four-walls", "cornell", ...). */
rad_status rad_scene_builtin(rad_context *context, const char *name, rad_scene **out);
size_t rad_builtin_scene_count(void);
const char *rad_builtin_scene_name(size_t index);        /* static storage */
const char *rad_builtin_scene_description(size_t index); /* static storage */

void rad_scene_destroy(rad_scene *scene);

/* Nonzero when the scene is geometry (form factors computed), zero for a patch system. */
int rad_scene_is_geometric(const rad_scene *scene);

/* The files the scene was read from: the scene file, its .mtl, .bin and textures (whatever the
 * importer opened), MGF includes, IES profiles; each once, as opened (relative paths are
 * relative to the working directory). None for built-in scenes. The string lives as long as the
 * scene; NULL past the end. An output must never be one of these files (the CLI refuses). */
size_t rad_scene_file_count(const rad_scene *scene);
const char *rad_scene_file(const rad_scene *scene, size_t index);

/* ---------------------------------------------------------------------------------------------
 * Systems: patches, elements, form factors and the solution
 * ------------------------------------------------------------------------------------------- */

typedef struct rad_system rad_system;

typedef enum rad_ff_method {
    RAD_FF_DEFAULT = 0,
    RAD_FF_ANALYTIC,   /* point-to-polygon contour integral, ray-tested visibility */
    RAD_FF_HEMICUBE,   /* Cohen & Greenberg 1985 */
    RAD_FF_RAYCAST,    /* Wallace, Elmquist & Haines 1989 */
    RAD_FF_MONTECARLO  /* area to area, random point pairs with visibility */
} rad_ff_method;

/* Meshing, after Cohen et al. 1986: surfaces are cut into patches, patches into elements.
 * Sizes are the longest edge in scene units. Zero: defaults (docs/meshing.md). */
typedef struct rad_mesh_options {
    double patch_size;
    double element_size;
    size_t elements; /* approximate total element count; used when element_size is zero */
    /* Nonzero: one element per input polygon (larger polygons fanned into triangles), no
     * contact cuts, no form-factor provider: for a solver that refines and draws its own leaves
     * (RAD_SOLVER_OWN_LEAVES); the sizes above are then not used. */
    int polygons_only;
    /* Nonzero: besides the contacts (always cut), cut the surfaces along the shadow boundaries
     * of the brightest area emitters before meshing (discontinuity meshing D1/D2,
     * docs/meshing.md, "Shadow boundaries"). Off by default: it pays for sharp shadows. */
    int shadow_boundaries;
} rad_mesh_options;

/* Per-method options: a bag of name = value pairs, as Mitsuba's plugins read their properties
 * and pbrt's Create() its ParameterDictionary. Each solver and form-factor method reads its own
 * registered options (rad_solver_info.options, rad_ff_method_info.options: "overshoot",
 * "ambient", "link-error", "ff-samples", "hemicube-res", ...) from the bag it is given; a name
 * the chosen method has not registered is an error that lists the ones it has. Values are text
 * (numbers as "%.17g"; flags "1" or "0"). Valid when zeroed; no allocation, nothing to free. */
#define RAD_OPTIONS_MAX 16
typedef struct rad_option_entry {
    char name[32];
    char value[48];
} rad_option_entry;
typedef struct rad_options {
    size_t count;
    rad_option_entry entries[RAD_OPTIONS_MAX];
} rad_options;

/* Sets (or replaces) name = value; RAD_ERROR_INVALID_ARGUMENT when the name or value is too
 * long or the bag is full. */
rad_status rad_options_set(rad_options *options, const char *name, const char *value);
rad_status rad_options_set_number(rad_options *options, const char *name, double value);
/* The value of `name`, or NULL when it is not set. Lives as long as the bag is not changed. */
const char *rad_options_get(const rad_options *options, const char *name);

typedef struct rad_ff_options {
    rad_ff_method method;
    int samples;             /* rays or point pairs per form factor; zero: the method's default */
    int hemicube_resolution; /* pixels along the top face; zero: default */
    /* The method's own options ("ff-samples", "hemicube-res"; see rad_ff_method_info.options);
     * NULL: none. Read while the system is built, not kept. `samples` and
     * `hemicube_resolution` above are the older way to say the same and are read when the bag
     * does not set them. */
    const rad_options *method_options;
} rad_ff_options;

/* Builds the system of a scene: meshing and form-factor set-up for geometry (the options are
 * ignored for patch systems). The scene may be destroyed afterwards. */
rad_status rad_system_create(rad_context *context, const rad_scene *scene,
                             const rad_mesh_options *mesh, const rad_ff_options *ff,
                             rad_system **out);

/* A patch, for building systems from arrays. */
typedef struct rad_patch_desc {
    const char *name;
    double area;
    double reflectance[3];
    double emission[3]; /* radiosity emitted, B units */
} rad_patch_desc;

/* A system of `count` patches with a dense form-factor matrix given row by row:
 * form_factors[i * count + j] is the fraction of the energy leaving patch i that arrives at j.
 * Everything is copied. */
rad_status rad_system_create_dense(rad_context *context, const rad_patch_desc *patches,
                                   size_t count, const float *form_factors, rad_system **out);

void rad_system_destroy(rad_system *system);

/* The name of the form-factor method the system uses ("analytic", ..., "given" for a patch
 * system's own matrix). Lives as long as the system. */
const char *rad_system_ff_method(const rad_system *system);

size_t rad_system_surface_count(const rad_system *system);
size_t rad_system_patch_count(const rad_system *system);
size_t rad_system_element_count(const rad_system *system);
/* What render and bake draw: the solution's leaves (the elements; after --solver hierarchical
 * or a loaded hierarchy, its quadtree leaves) and, in *polygons when not NULL, the polygons they
 * are drawn as (a leaf beside finer ones is drawn as a fan). 0 for a patch system (.ffm). */
size_t rad_system_leaf_count(const rad_system *system, size_t *polygons);

/* A named input surface (a patch of a .ffm file, an object of a geometric scene) and its share
 * of the solution: radiosity is the area-weighted mean over its elements, power = radiosity *
 * area (W when radiosity is W/m^2). */
typedef struct rad_surface_info {
    const char *name; /* lives as long as the system */
    double area;
    double reflectance[3];
    double emission[3];
    double radiosity[3];
    double unshot[3];
    double power[3];
} rad_surface_info;

rad_status rad_system_surface(const rad_system *system, size_t index, rad_surface_info *out);

/* Where the emitted power went (src/system/energy_balance.c), per channel, in power units
 * (radiosity times area): emitted = absorbed + unshot + escaped. Absorbed is what each element
 * takes of the light arriving at it, (1 - rho) H A with H = (B - E) / rho; unshot is the power
 * a shooting solver has yet to send; escaped is the rest: light that left the scene, or, in a
 * closed scene, light lost through leaks. Where rho is 0 the arriving light is not known and
 * its absorption is counted as escaped; `black_area` is the area of such elements (any channel). */
typedef struct rad_energy_balance {
    double emitted[3], absorbed[3], unshot[3], escaped[3];
    double escaped_fraction; /* escaped / emitted, summed over channels */
    double black_area;
} rad_energy_balance;

void rad_system_energy_balance(const rad_system *system, rad_energy_balance *out);

/* The form factor between two surfaces, each surface's elements combined by area: the fraction
 * of the energy leaving surface `from` that arrives at surface `to`. Fills a row-major
 * surface_count x surface_count matrix. */
rad_status rad_system_surface_form_factors(rad_system *system, double *matrix);

/* Per-element solution, in element order. `radiosity` may be NULL. */
rad_status rad_system_element_radiosity(const rad_system *system, size_t element,
                                        double radiosity[3]);

/* Resets the solution to B = E, unshot = E (what every solver starts from). */
void rad_system_reset(rad_system *system);

/* ---------------------------------------------------------------------------------------------
 * Solvers
 * ------------------------------------------------------------------------------------------- */

/* The registered solvers, in registry order (src/solve/registry.c): a solver's kind is its
 * position in the registry plus one, so solvers registered later have kinds past these names
 * and are reached by rad_solver_kind_parse. Zero (a zeroed rad_solve_options) is the default. */
typedef enum rad_solver_kind {
    RAD_SOLVER_DEFAULT = 0, /* the default solver: shooting */
    RAD_SOLVER_DIRECT,      /* Gaussian elimination with partial pivoting (LAPACK dgesv) */
    RAD_SOLVER_JACOBI,      /* gathering from the previous round */
    RAD_SOLVER_GAUSS_SEIDEL, /* gathering in place */
    RAD_SOLVER_SHOOTING,    /* progressive refinement, Cohen et al. 1988 */
    RAD_SOLVER_IMPORTANCE,  /* shooting ordered by what the camera sees, Smits et al. 1992 */
    RAD_SOLVER_HIERARCHICAL /* quadtrees and links, Hanrahan et al. 1991 (docs/hierarchical.md) */
} rad_solver_kind;

/* What a solver does (rad_solver_info.capabilities). */
#define RAD_SOLVER_SHOOTS 1u        /* one shot a step; without it, gathering rounds */
#define RAD_SOLVER_ITERATIVE 2u     /* steps until converged; without it one step solves */
#define RAD_SOLVER_NEEDS_MATRIX 4u  /* asks for the whole form-factor matrix at once */
#define RAD_SOLVER_NEEDS_CAMERA 8u  /* needs rad_solve_options.camera */
#define RAD_SOLVER_KEEPS_UNSHOT 16u /* its solutions carry a true unshot radiosity */
#define RAD_SOLVER_NEEDS_UNSHOT 32u /* resumes only from solutions that carry one */
#define RAD_SOLVER_OWN_LEAVES 64u   /* refines its own leaves from the input polygons and draws
                                       them: build its system with rad_mesh_options.polygons_only */

/* One of a method's own options: its name (as the CLI spells it after "--") and what it does. */
typedef struct rad_method_option {
    const char *name;
    const char *help;
} rad_method_option;

/* A setting of a solver worth running in a comparison (radiosity solve --compare-solvers). */
typedef struct rad_solver_variant {
    const char *label; /* with one %g for omega when `relaxed` */
    int relaxed;       /* over-relaxed: the caller's omega, or the solver's best_omega */
    int overshoot;
} rad_solver_variant;

/* A registered solver. Lives as long as the program. */
typedef struct rad_solver_info {
    const char *name;        /* "shooting" */
    const char *description; /* one line */
    unsigned capabilities;   /* RAD_SOLVER_SHOOTS | ... */
    const rad_method_option *options; /* its own options, option_count of them */
    size_t option_count;
    const rad_solver_variant *variants; /* for comparisons; none: not compared */
    size_t variant_count;
    double best_omega;       /* the over-relaxation measured best, for relaxed variants */
} rad_solver_info;

/* The registry: rad_solver_count() solvers; rad_solver_at(i) is the solver of kind i + 1. */
size_t rad_solver_count(void);
const rad_solver_info *rad_solver_at(size_t index);
/* The solver of a kind (RAD_SOLVER_DEFAULT gives the default's); NULL when unknown. */
const rad_solver_info *rad_solver_get(rad_solver_kind kind);
/* Nonzero when `solver` can go on from a solution saved by `saved_by`. */
int rad_solver_can_resume(rad_solver_kind solver, rad_solver_kind saved_by);

/* Parses a registered name ("direct", "jacobi", "gauss-seidel", "shooting", "importance",
 * ...); -1 when unknown. */
int rad_solver_kind_parse(const char *name);
const char *rad_solver_kind_name(rad_solver_kind kind);

/* The solver the commands use for a scene when none is named: hierarchical radiosity for a
 * geometric scene of RAD_HIERARCHY_DEFAULT_POLYGONS input polygons or more, where shooting's
 * cost (shots times elements, both growing with the polygons) runs to minutes and Gauss-Seidel's
 * matrix does not fit (generated office of 9,708 polygons: the shooting render 258 processor-s,
 * the hierarchy's 5.7 s, and at equal error 29 times faster; Sponza, 41k polygons: shooting -39%
 * after a minute); shooting otherwise (docs/hierarchical.md, "Default solver"). */
#define RAD_HIERARCHY_DEFAULT_POLYGONS 8000
rad_solver_kind rad_scene_default_solver(const rad_scene *scene);

/* What one round (gathering) or one shot (shooting) did, per surface (area-weighted means over
 * the surface's elements). Arrays have surface_count entries and live during the callback. */
typedef struct rad_trace_event {
    int iteration;          /* 1 for the first round or shot */
    long shooter;           /* surface that shot, or -1 for gathering */
    size_t surface_count;
    const double (*received)[3];  /* light arriving: sum_j B_j A_j F_jk / A_k (this round/shot) */
    const double (*reflected)[3]; /* shooting: rho * received, added to radiosity and unshot */
    const double (*radiosity)[3]; /* after the round or shot */
    const double (*unshot)[3];    /* shooting only; NULL for gathering */
} rad_trace_event;

typedef void (*rad_trace_fn)(void *user, const rad_trace_event *event);

/* What the solver has done so far, after every round or shot (docs/solvers.md, "Progressive
 * refinement"): for logs, convergence plots, snapshots and progress lines. */
typedef struct rad_iteration_event {
    int iteration;          /* rounds or shots in this call, 1 for the first */
    double seconds;         /* since rad_solve began, not counting time spent in the callback */
    long shots;             /* shooting, importance: shots so far in this call; gathering: 0 */
    long rounds;            /* gathering: rounds so far in this call; shooting: 0 */
    double unshot_fraction; /* shooting, importance: unshot power / emitted power; else NaN */
    double residual;        /* the solver's stopping measure after the step */
    long shooter;           /* the patch that shot, or -1 for gathering */
    /* hierarchical: links and leaves after the step, and the oracle's largest remaining error
     * relative to its threshold; 0, 0 and NaN for the other solvers */
    size_t links, leaves;
    double largest_error;
} rad_iteration_event;

/* Return nonzero to stop: rad_solve then returns RAD_OK with report->stop RAD_STOP_CALLBACK
 * and the solution as far as it got. */
typedef int (*rad_iteration_fn)(void *user, const rad_iteration_event *event);

/* A pinhole camera: eye, the point looked at, up, vertical field of view in degrees. */
typedef struct rad_camera_desc {
    double eye[3], look[3], up[3];
    double fov_degrees;
} rad_camera_desc;

typedef struct rad_solve_options {
    rad_solver_kind solver;
    int max_iterations;   /* rounds or shots; zero: until converged (with a safety cap) */
    double tolerance;     /* zero: 1e-6. Gathering: largest change between rounds relative to
                             the largest radiosity; shooting: unshot power over emitted power */
    double omega;         /* over-relaxation, zero: 1 (Gauss-Seidel: SOR; shooting: overshoot) */
    int ambient;          /* shooting: add the ambient term to displayed results */
    rad_trace_fn trace;   /* zero: no trace */
    void *trace_user;
    /* Progressive refinement and importance (docs/solvers.md). */
    int overshoot;        /* shooting, importance: overshooting (Feda & Purgathofer 1992) */
    double time_budget;   /* seconds, zero: none; stops after the step that uses it up */
    int resume;           /* nonzero: go on from the system's radiosity and unshot radiosity
                             (rad_system_load_solution) instead of starting from B = E */
    rad_iteration_fn on_iteration; /* zero: none; called after every round or shot, in place
                                      of the context's progress reports for the steps */
    void *iteration_user;
    const rad_camera_desc *camera; /* importance: the camera whose image matters (required) */
    int view_width, view_height;   /* importance: the image's size; zero: 256 x 256 */
    double link_error;    /* hierarchical: the oracle's threshold on rho B dF relative to the
                             brightest emitter; zero: the tolerance when given, else 1e-3 */
    /* The solver's own options ("overshoot", "ambient", "link-error", ...; see
     * rad_solver_info.options); NULL: none. The per-solver fields above (ambient, overshoot,
     * link_error) are the older way to say the same and are read when the bag does not set
     * them. */
    const rad_options *method_options;
} rad_solve_options;

typedef enum rad_solve_stop {
    RAD_STOP_CONVERGED = 0, /* the stopping measure reached the tolerance */
    RAD_STOP_ITERATIONS,    /* max_iterations, or the safety cap */
    RAD_STOP_TIME_BUDGET,   /* time_budget used up: the best solution so far */
    RAD_STOP_CALLBACK,      /* on_iteration asked to stop */
    RAD_STOP_ERROR,         /* an error or a cancel; the status says which */
    RAD_STOP_MEMORY_BUDGET, /* the solver could not go on within max_memory: the best solution
                               so far, not converged (the hierarchical solver's refinement) */
    RAD_STOP_TAIL           /* converged by the solver's tail rule: the hierarchical solver
                               after a step that refined at most 0.2% of its links, solved;
                               every link passed the oracle at the radiosities it was refined
                               with (docs/hierarchical.md, "The tail rule"); converged is 1 */
} rad_solve_stop;

typedef struct rad_solve_report {
    int iterations;
    int converged;
    double residual;       /* the stopping measure at the end (hierarchical: the oracle's
                              largest error, a fraction of the emitted power like the link
                              error); infinite when the last step was cut short */
    double seconds;        /* solver time, not counting time spent in on_iteration */
    rad_solve_stop stop;   /* why it stopped */
    double unshot_fraction; /* shooting, importance: unshot power / emitted power; else NaN */
    int importance_shots;  /* importance: shots of the importance pass, before any light */
    size_t links, leaves;  /* hierarchical: at the end (0 for the other solvers) */
    double largest_error;  /* hierarchical: the oracle's largest remaining error over its
                              threshold at the end; NaN for the other solvers */
} rad_solve_report;

/* Solves the system from B = E (or from where it is, with options->resume), until converged,
 * max_iterations or time_budget. The solution stays on the system. A stop by max_iterations,
 * time_budget or the iteration callback is not an error (report->converged is 0). */
rad_status rad_solve(rad_system *system, const rad_solve_options *options,
                     rad_solve_report *report);

/* ---------------------------------------------------------------------------------------------
 * Output files (docs/errors.md, "Outputs"): every file the library writes goes this way
 *
 * Symbolic links are followed and their target written. A regular file (or a new name) is
 * written whole or not at all: a temporary file beside it, renamed over it. A device, FIFO or
 * socket is written through and never replaced; a FIFO with no reader is an error, not a wait.
 * A directory is refused.
 * ------------------------------------------------------------------------------------------- */

/* Checks, before long work, that `path` can be written (RAD_ERROR_IO with the reason): a
 * temporary file is made and removed beside a regular target; special files are not opened. */
rad_status rad_output_check(rad_context *context, const char *path);

/* Writes `size` bytes to `path` by the rules above. */
rad_status rad_output_write(rad_context *context, const char *path, const void *data,
                            size_t size);

/* ---------------------------------------------------------------------------------------------
 * Baking: the solution as vertex colours that other tools open (docs/bake.md)
 * ------------------------------------------------------------------------------------------- */

typedef enum rad_bake_format {
    RAD_BAKE_AUTO = 0, /* from the extension of the path */
    RAD_BAKE_GLB,      /* binary glTF 2.0 */
    RAD_BAKE_GLTF,     /* glTF 2.0 JSON and its buffer beside it: FILE.gltf + FILE.bin */
    RAD_BAKE_PLY,      /* binary little-endian PLY */
    RAD_BAKE_OBJ       /* Wavefront OBJ with the "v x y z r g b" vertex-colour extension */
} rad_bake_format;

typedef struct rad_bake_options {
    rad_bake_format format;  /* zero: from the path's extension */
    const rad_scene *scene;  /* the scene the system was built from, for its camera; may be NULL */
    double scale;            /* positions are multiplied by this (0.001: mm to m); zero: 1 */
    double exposure;         /* stops, for the display colours (glTF COLOR_0, PLY, OBJ) */
    const char *tonemap;     /* "clamp" (NULL), "none", "reinhard", "aces": display colours */
    double aspect;           /* glTF camera aspect ratio, width / height; zero: 1 */
    int ambient;             /* add the ambient term of progressive refinement */
    int final_gather;        /* > 0: each vertex's radiance gathered again at the vertex with
                                this many rays into the solution, and direct light sampled
                                (needs `scene`); zero: the mean of the elements around it */
} rad_bake_options;

/* The format a path's extension names (.glb, .gltf, .ply, .obj in any case), or RAD_BAKE_AUTO
 * when it names none. */
rad_bake_format rad_bake_format_of(const char *path);

/* Checks before any work is done: a known format and tone curve (RAD_ERROR_INVALID_ARGUMENT),
 * and a directory that takes a new file (RAD_ERROR_IO; a temporary file is made and removed). */
rad_status rad_bake_check(rad_context *context, const char *path,
                          const rad_bake_options *options);

/* Writes the solution of a geometric system as a mesh with vertex colours: one mesh per surface,
 * each vertex carrying the linear radiance B / pi averaged over the elements around it on its
 * own surface and side of a crease (never across a corner), or with final_gather the radiance
 * gathered at it, and its display colour (exposure and tone curve). The file, and the .bin of
 * a .gltf, appear whole or not at all. A patch system (.ffm) has no geometry:
 * RAD_ERROR_INVALID_ARGUMENT. */
rad_status rad_bake(const rad_system *system, const char *path, const rad_bake_options *options);

/* ---------------------------------------------------------------------------------------------
 * Scene files: export (import is rad_scene_load; both in docs/formats.md, "Scene files")
 * ------------------------------------------------------------------------------------------- */

/* Writes a geometric scene as Wavefront OBJ (`path`) with its material library next to it (the
 * same name ending in .mtl): one object (`o`) per surface, named as the surface (white space
 * becomes '_'); materials keep reflectance (Kd), emitted radiance (Ke) and the mirror/glass
 * hints (illum, Ks, Ns, Ni, Tf). Both files appear whole or not at all. A patch system (.ffm)
 * has no geometry: RAD_ERROR_INVALID_ARGUMENT. */
rad_status rad_scene_export_obj(rad_context *context, const rad_scene *scene, const char *path);

/* A generated open-plan office of about `triangles` triangles (quads count two): 3 m cells, each
 * with a desk, a chair and an emitting ceiling lamp, rooms of 4 x 4 cells with doorways, outer
 * walls; deterministic (src/scene/generate_office.c). At least 123 triangles. */
rad_status rad_scene_generate_office(rad_context *context, size_t triangles, rad_scene **out);

/* A generated closed two-room house (metres) built as building models are: a floor slab running
 * under the walls and out of the building, exterior walls passing through it and the roof slab,
 * a partition with a doorway, one ceiling lamp; nothing leaves it, so power escaping from a
 * solution is a leak (src/scene/generate_house.c). */
rad_status rad_scene_generate_house(rad_context *context, rad_scene **out);

/* ---------------------------------------------------------------------------------------------
 * Rendering: pictures of the solution and the ray-traced second pass (docs/rendering.md)
 *
 * Images here are shared with the path tracer; cameras are rad_camera_desc (pixels square, the
 * field of view vertical). A pixel is the radiance seen:
 * B / pi on diffuse surfaces (on an emitter that includes its emitted radiance L = E / pi).
 * ------------------------------------------------------------------------------------------- */

/* A float RGB image of linear radiance, row 0 at the top. */
typedef struct rad_image rad_image;

int rad_image_width(const rad_image *image);
int rad_image_height(const rad_image *image);
/* width * height * 3 floats, row by row from the top; lives as long as the image. */
const float *rad_image_pixels(const rad_image *image);
void rad_image_destroy(rad_image *image);

typedef struct rad_image_save_options {
    double exposure;     /* stops; PNG only */
    const char *tonemap; /* "clamp" (NULL), "none", "reinhard", "aces"; PNG only */
    int exr_half;        /* EXR only: nonzero writes 16-bit half floats (default 32-bit float) */
} rad_image_save_options;

/* Checks before any work is done: an extension rad_image_save knows and a known tone curve
 * (RAD_ERROR_INVALID_ARGUMENT), a directory that takes a new file (RAD_ERROR_IO). */
rad_status rad_image_check_path(rad_context *context, const char *path,
                                const rad_image_save_options *options);

/* Writes by extension: .png tone mapped sRGB 8 bit; .hdr (Radiance RGBE), .pfm (32-bit float)
 * and .exr (OpenEXR, 32-bit float or half, ZIP) linear, never tone mapped. The file appears whole or not at all. */
rad_status rad_image_save(const rad_image *image, const char *path,
                          const rad_image_save_options *options);

typedef enum rad_shading {
    RAD_SHADING_SMOOTH = 0, /* radiosity averaged to element vertices, interpolated across */
    RAD_SHADING_FLAT        /* constant per element */
} rad_shading;

/* Parses "smooth", "flat"; -1 when unknown. */
int rad_shading_parse(const char *name);

typedef struct rad_render_options {
    int width, height;             /* pixels; zero: 512 */
    const rad_camera_desc *camera; /* NULL: the scene's own, or one framing it */
    int samples_per_pixel;         /* jittered samples, box filter; zero: 4 */
    rad_shading shading;
    int final_gather;   /* direct light sampled and this many rays per sample gathered into
                           the solution at the first diffuse hit; zero: off (the solution,
                           interpolated, alone) */
    int light_samples;  /* final gather: emitter samples per sample; zero: final_gather / 2
                           (final_gather / 4 with no_gather_filter), at least 1, twice that
                           in scenes of more than 256 emitting surfaces */
    int max_depth;      /* specular bounces (mirrors, glass) per path; zero: 16 */
    int ambient;        /* add the ambient term of progressive refinement */
    int no_gather_filter; /* final gather: keep each pixel's own gathered light instead of
                             filtering it over its neighbours (docs/rendering.md) */
} rad_render_options;

typedef struct rad_render_stats {
    double seconds; /* the last rad_renderer_render */
    uint64_t camera_rays, gather_rays, shadow_rays, specular_rays;
} rad_render_stats;

typedef struct rad_renderer rad_renderer;

/* Checks the options and the camera (it must see the front of some surface) and builds the ray
 * tracing structures. The scene must be the one the system was built from; it may be destroyed
 * afterwards; the system must outlive the renderer. Patch systems (.ffm) have no geometry:
 * RAD_ERROR_INVALID_ARGUMENT. Random choices follow the context's seed: the same seed gives the
 * same image whatever the thread count. */
rad_status rad_renderer_create(const rad_scene *scene, const rad_system *system,
                               const rad_render_options *options, rad_renderer **out);

/* Renders the system's current solution. Reports progress as "rendering" (rows done). */
rad_status rad_renderer_render(rad_renderer *renderer, rad_image **out, rad_render_stats *stats);

void rad_renderer_destroy(rad_renderer *renderer);

/* Create, render, destroy in one call. */
rad_status rad_render(const rad_scene *scene, const rad_system *system,
                      const rad_render_options *options, rad_image **out);

/* ---------------------------------------------------------------------------------------------
 * Progressive refinement and importance: solution files, what a camera sees (docs/solvers.md,
 * docs/formats.md "Solution files")
 * ------------------------------------------------------------------------------------------- */

/* What a solution file says about how it was made. */
typedef struct rad_solution_info {
    rad_solver_kind solver; /* the solver that made it */
    long steps;             /* rounds or shots done so far, over every resumed run */
} rad_solution_info;

/* Writes the system's solution (radiosity and unshot radiosity per element, the ambient term)
 * with fingerprints of the scene, the mesh and the form factors; after a hierarchical solve, the
 * hierarchy itself (docs/formats.md, version 2), from which a resumed solve goes on exactly as
 * if it had never stopped. The file appears whole or not at all. `info` may be NULL. */
rad_status rad_system_save_solution(rad_system *system, const char *path,
                                    const rad_solution_info *info);

/* Reads a solution saved for this same system (same scene, meshing and form-factor options) into
 * it; rad_solve with options.resume then goes on from it, and renderers show it as it is. A file
 * that is damaged (RAD_ERROR_PARSE) or was saved for another scene, mesh or form factors
 * (RAD_ERROR_INVALID_ARGUMENT) is refused with a one-line message and the system is untouched.
 * `info` may be NULL. */
rad_status rad_system_load_solution(rad_system *system, const char *path,
                                    rad_solution_info *info);

/* What a solution file's header says (solver and steps), before any system is built for it: a
 * command can then build the system the file needs (one element per polygon for a hierarchy's).
 * Nothing else is checked; rad_system_load_solution checks everything. RAD_ERROR_IO when it
 * cannot be read, RAD_ERROR_PARSE when it is not a solution file. `ctx` may be NULL (no message
 * kept). */
rad_status rad_solution_file_info(rad_context *ctx, const char *path, rad_solution_info *info);

/* Area of an element (scene units squared); 0 for an index out of range. */
double rad_system_element_area(const rad_system *system, size_t element);

/* The scene's camera, or one that frames the whole scene when it has none. */
void rad_scene_get_camera(const rad_scene *scene, rad_camera_desc *out);

/* The share of a width x height image (one ray per pixel centre; zero sizes: 256 x 256) that
 * each element covers, seen from the camera (front sides only): element_count entries summing to
 * the fraction of pixels that see a surface. Geometric systems only. */
rad_status rad_system_screen_share(rad_system *system, const rad_camera_desc *camera, int width,
                                   int height, double *share);

/* A converged solution to measure others against (docs/solvers.md, "Comparing the solvers"):
 * Gauss-Seidel to 1e-10, or shooting to 1e-10 when the matrix does not fit the memory budget.
 * Solves the system from B = E and copies the radiosity into reference[3 * element_count];
 * `used` (may be NULL) gets the solver, `tolerance` (may be NULL) the tolerance. */
rad_status rad_system_solve_reference(rad_system *system, double *reference,
                                      rad_solver_kind *used, double *tolerance);

/* How far the system's solution is from a reference: sum_e w_e |B_e - B*_e| / sum_e w_e |B*_e|
 * over elements, each summed over channels, with weights w_e the element areas (weights NULL:
 * the fraction of the power that is wrong) or given (a screen share: the view error). Zero
 * when the reference is zero with area weights; NaN with given weights that see nothing. */
double rad_system_solution_error(const rad_system *system, const double *reference,
                                 const double *weights);

/* ---------------------------------------------------------------------------------------------
 * Images and path tracing: reference images and their comparison (docs/pathtracing.md,
 * docs/images.md). Cameras and image files are those of "Rendering" above.
 * ------------------------------------------------------------------------------------------- */

/* Reads a linear image: .pfm (Portable Float Map), .hdr (Radiance RGBE) or .exr (OpenEXR). */
rad_status rad_image_read(rad_context *context, const char *path, rad_image **out);

typedef struct rad_pathtrace_options {
    int width, height;             /* pixels; zero: 512 */
    const rad_camera_desc *camera; /* NULL: rad_scene_get_camera of the scene */
    int samples_per_pixel;         /* paths per pixel, uniformly jittered, box filter; zero: 64 */
    int max_bounces;               /* scattering events per path (1: direct light only); zero:
                                      no limit, Russian roulette ends the paths */
    double clamp_indirect;         /* zero: unbiased (the default). Else light that scattered
                                      twice or more counts at most this much (R + G + B) per
                                      contribution, as Cycles' "Clamp Indirect": biased */
    double time_budget;            /* seconds; zero: none. Past it the render stops with the
                                      image so far (after at least one path per pixel) */
} rad_pathtrace_options;

typedef enum rad_pathtrace_stop {
    RAD_PATHTRACE_DONE = 0,     /* every path asked for was traced */
    RAD_PATHTRACE_TIME_BUDGET,  /* options->time_budget ran out: the image so far */
    RAD_PATHTRACE_CANCELLED     /* the progress callback stopped it after the first pass: the
                                   image so far */
} rad_pathtrace_stop;

typedef struct rad_pathtrace_stats {
    double seconds;
    uint64_t paths; /* camera samples traced to the end */
    uint64_t rays;  /* closest-hit and shadow rays */
    /* Paths per pixel in the image: samples_per_pixel unless stopped early; a stop inside a
     * pass leaves the rows that pass finished with more (samples_max) than the others
     * (samples_min). */
    int samples_min, samples_max;
    rad_pathtrace_stop stopped;
} rad_pathtrace_stats;

/* Path-traces a geometric scene: unbiased for diffuse, mirror, glossy and glass materials, with
 * next-event estimation and multiple importance sampling. Pixels are radiance. Random choices
 * follow the context's seed (each pixel has its own stream): the same seed gives the same image
 * whatever the thread count. Fails with RAD_ERROR_INVALID_ARGUMENT when the camera sees nothing
 * or only the backs of surfaces (it is inside an object). Renders in passes over the whole
 * image (one path per pixel, then longer ones; the same image however they fall) and reports
 * progress as "path tracing" in paths per pixel; a forecast longer than a minute is logged
 * after the first pass. Cancelled through the progress callback during the first pass it fails
 * with RAD_ERROR_CANCELLED; after it, it returns RAD_OK with the image so far and says so in
 * `stats` (stopped, samples_min, samples_max), as the time budget does. `stats` may be NULL. */
rad_status rad_pathtrace(rad_context *context, const rad_scene *scene,
                         const rad_pathtrace_options *options, rad_image **out,
                         rad_pathtrace_stats *stats);

/* How far a test image is from a reference, over every channel of every pixel. */
typedef struct rad_image_comparison {
    double rmse;         /* sqrt(mean (t - r)^2) */
    double relative_mse; /* mean (t - r)^2 / (r^2 + 0.01), as pbrt's imgtool computes it */
    double psnr;         /* dB, 10 log10(peak^2 / MSE), peak = 1 (white of a display-referred
                            image; linear values above 1 count as they are); infinite for
                            identical images */
    double mean_test, mean_reference;
    double mean_ratio;   /* mean_test / mean_reference */
} rad_image_comparison;

/* Compares two images of the same size (else RAD_ERROR_INVALID_ARGUMENT). Non-finite pixels of
 * the test image count as errors (RAD_ERROR_INVALID_ARGUMENT names the first). */
rad_status rad_image_compare(rad_context *context, const rad_image *test,
                             const rad_image *reference, rad_image_comparison *out);

/* A false-colour picture of the per-pixel relative error sqrt(mean_c (t - r)^2 / (r^2 + 0.01)):
 * black (none) through blue, magenta and orange to pale yellow at `scale` and above; zero scale:
 * the 99th percentile of the error (stored back into *scale). Linear values, for rad_image_save. */
rad_status rad_image_error_map(rad_context *context, const rad_image *test,
                               const rad_image *reference, double *scale, rad_image **out);

/* ---------------------------------------------------------------------------------------------
 * Form-factor methods (docs/formfactors.md)
 * ------------------------------------------------------------------------------------------- */

/* The name of a method ("analytic", "hemicube", "raycast", "montecarlo"); RAD_FF_DEFAULT gives
 * the name of the method it stands for. NULL for an unknown value. Static storage. */
const char *rad_ff_method_name(rad_ff_method method);

/* A registered form-factor method (src/formfactor/factory.c). Lives as long as the program. */
typedef struct rad_ff_method_info {
    const char *name;        /* "analytic" */
    const char *description; /* one line */
    int default_samples;     /* rays or point pairs per form factor; zero: not sampled */
    const rad_method_option *options; /* its own options, option_count of them */
    size_t option_count;
} rad_ff_method_info;

/* The registry: rad_ff_method_count() methods; rad_ff_method_at(i) is method i + 1. */
size_t rad_ff_method_count(void);
const rad_ff_method_info *rad_ff_method_at(size_t index);
/* Parses a registered name, or "default" (RAD_FF_DEFAULT); -1 when unknown. */
int rad_ff_method_parse(const char *name);

/* ---------------------------------------------------------------------------------------------
 * What a scene holds (`radiosity scenes --info`; src/scene/scene_info.c). Strings live as long
 * as the scene.
 * ------------------------------------------------------------------------------------------- */
typedef struct rad_scene_info {
    int geometric;        /* 0: a patch system (.ffm): only patch_count is set */
    size_t patch_count;
    size_t surface_count, material_count, texture_count;
    size_t vertex_count, polygon_count, triangle_count; /* triangles: sum of (corners - 2) */
    size_t emitting_surface_count;
    int has_camera;       /* the file's own camera (rad_scene_get_camera gives it) */
    double bounds_min[3], bounds_max[3];
    int camera_automatic; /* no camera in the file: one was placed inside its open space */
} rad_scene_info;
void rad_scene_get_info(const rad_scene *scene, rad_scene_info *out);

typedef struct rad_material_info {
    const char *name;
    const char *kind;     /* "diffuse", "mirror", "glass" */
    double reflectance[3], emission[3];
    const char *texture;  /* the texture's file (or "FILE: embedded image N"); NULL: none */
    unsigned texture_width, texture_height;
    size_t surface_count; /* surfaces that use it */
} rad_material_info;
/* Material `index` < material_count; RAD_ERROR_INVALID_ARGUMENT past the end. */
rad_status rad_scene_get_material(const rad_scene *scene, size_t index, rad_material_info *out);

typedef struct rad_surface_listing {
    const char *name;
    size_t material;      /* index for rad_scene_get_material */
    size_t polygon_count, triangle_count;
    double area;
    int textured;         /* its material has a texture and its polygons texture coordinates */
} rad_surface_listing;
rad_status rad_scene_get_surface(const rad_scene *scene, size_t index, rad_surface_listing *out);

/* ---------------------------------------------------------------------------------------------
 * Photon mapping (docs/photonmapping.md)
 * ------------------------------------------------------------------------------------------- */

typedef struct rad_photonmap_options {
    int width, height;             /* pixels; zero: 512 */
    const rad_camera_desc *camera; /* NULL: rad_scene_get_camera of the scene */
    int samples_per_pixel;         /* camera samples per pixel (box filter); zero: 4 */
    int gather_rays;               /* final-gather rays per camera sample at its first diffuse or
                                      glossy point; zero: 16 */
    uint64_t photons;              /* photons emitted for the global map (and caustics); zero:
                                      200,000 */
    uint64_t caustic_photons;      /* photons emitted more for the caustic map alone (none when
                                      no material is a mirror or glass); zero: as many as
                                      `photons` */
    double radius;                 /* largest density-estimation radius, scene units; zero: the
                                      radius a disc holding `nearest` photons has on average */
    int nearest;                   /* k of the k-nearest estimate; zero: 20 */
    int iterations;                /* progressive photon mapping: passes, each with fresh
                                      photons and smaller radii; zero or 1: one pass */
    double alpha;                  /* progressive: radius^2 shrinks by (i + alpha) / (i + 1)
                                      after pass i; zero: 2/3 */
} rad_photonmap_options;

typedef struct rad_photonmap_stats {
    double seconds, trace_seconds, build_seconds, render_seconds;
    double trace_cpu_seconds;       /* processor time of the photon tracing (all threads) */
    uint64_t photons_emitted;       /* over every pass */
    uint64_t global_stored, caustic_stored; /* of the last pass */
    double radius, caustic_radius;  /* of the last pass */
    uint64_t rays;                  /* camera, shadow and gather rays */
} rad_photonmap_stats;

/* Renders a geometric scene by photon mapping (Jensen 1996): photons traced from the emitters
 * into a global and a caustic map, then per pixel the emitted light, direct light by emitter
 * sampling, caustics from the caustic map and indirect light by final gather into the global
 * map's precomputed irradiance (Christensen 1999); mirrors and glass are followed from the
 * camera. The same seed gives the same image whatever the thread count. Fails with
 * RAD_ERROR_INVALID_ARGUMENT for bad options and RAD_ERROR_MEMORY_BUDGET when the photons would
 * not fit the context's budget (checked before allocating). Reports progress as "photon
 * tracing" and "photon mapping"; `stats` may be NULL. */
rad_status rad_photonmap(rad_context *context, const rad_scene *scene,
                         const rad_photonmap_options *options, rad_image **out,
                         rad_photonmap_stats *stats);

/* ---------------------------------------------------------------------------------------------
 * Lights that are not surfaces, and the sky (docs/lights.md, units in docs/units.md)
 * ------------------------------------------------------------------------------------------- */

typedef enum rad_light_type {
    RAD_LIGHT_TYPE_POINT = 0,
    RAD_LIGHT_TYPE_SPOT,       /* a point with a cone: full inside inner, none outside outer */
    RAD_LIGHT_TYPE_DIRECTIONAL /* parallel light (the sun): `direction` is where it travels */
} rad_light_type;

/* What `strength` is measured in. Photometric units turn into radiometric ones at 179 lm/W. */
typedef enum rad_light_units {
    RAD_LIGHT_WATTS = 0, /* point, spot: radiant intensity W/sr; directional: irradiance W/m^2 */
    RAD_LIGHT_CANDELA,   /* point, spot: cd (on the axis); directional: lux */
    RAD_LIGHT_LUMENS     /* point, spot: total luminous flux; directional: lux */
} rad_light_units;

typedef struct rad_light_desc {
    const char *name;     /* for --ies and messages; may be NULL */
    rad_light_type type;
    double position[3];   /* point, spot */
    double direction[3];  /* spot axis, or where a directional light travels; any length > 0 */
    double color[3];      /* relative colour, >= 0 (zero: white) */
    double strength;      /* in `units`, times color */
    rad_light_units units;
    double inner_degrees, outer_degrees; /* spot half angles; 0 < outer <= 90, inner <= outer */
} rad_light_desc;

/* Adds a light to a geometric scene. Bad values: RAD_ERROR_INVALID_ARGUMENT naming the field. */
rad_status rad_scene_add_light(rad_scene *scene, const rad_light_desc *light);
/* Point and spot lights in the scene (from its file or added). */
size_t rad_scene_light_count(const rad_scene *scene);
/* Gives the point or spot light named `light_name` (NULL or "*": every point and spot light) the
 * intensity profile of the IES LM-63 file at `path`; errors name file:line. */
rad_status rad_scene_set_light_ies(rad_scene *scene, const char *light_name, const char *path);

typedef enum rad_sky_model {
    RAD_SKY_NONE = 0,
    RAD_SKY_MODEL_UNIFORM,     /* radiance L everywhere above the horizon */
    RAD_SKY_MODEL_CIE_OVERCAST /* L(theta) = L_zenith (1 + 2 cos theta) / 3 (CIE overcast sky) */
} rad_sky_model;

typedef struct rad_sky_desc {
    rad_sky_model model;
    double radiance[3]; /* uniform: L; overcast: at the zenith (W m^-2 sr^-1) */
    double up[3];       /* the zenith; zero: +Y */
    int samples;        /* rays per element of the solver's sky pass; 0: 64 */
} rad_sky_desc;

/* Sets (or with RAD_SKY_NONE removes) the sky of a geometric scene: light that enters through
 * its openings, in the solve, render, bake and path tracer. */
rad_status rad_scene_set_sky(rad_scene *scene, const rad_sky_desc *sky);

/* What the scene's lights are (`radiosity scenes --info`; src/scene/scene_info.c): a point, spot
 * or directional light (from its file, rad_scene_add_light or the sun) in the solver's units;
 * 179 times the intensity is candela, 179 times the irradiance lux (docs/units.md). Strings
 * live as long as the scene. */
typedef struct rad_light_info {
    const char *name;
    rad_light_type type;
    double position[3];      /* point, spot */
    double direction[3];     /* unit: spot axis, or where a directional light travels */
    double intensity[3];     /* point, spot: W/sr (on the axis); directional: irradiance W/m^2 */
    double inner_degrees, outer_degrees; /* spot half angles */
    const char *ies;         /* the IES LM-63 file it was given, or NULL */
} rad_light_info;
/* Light `index` < rad_scene_light_count; RAD_ERROR_INVALID_ARGUMENT past the end. */
rad_status rad_scene_get_light(const rad_scene *scene, size_t index, rad_light_info *out);
/* The scene's sky: its model (RAD_SKY_NONE without one) and radiance (rad_sky_desc). */
void rad_scene_get_sky(const rad_scene *scene, rad_sky_desc *out);

/* The specular-first pass (docs/specular-first.md): before the solve, photons from the emitting
 * surfaces are followed through mirrors and glass, and what they bring to a diffuse element
 * becomes light it emits in the solution (solve, render, bake). `on`: 1 always, 0 never, -1 when
 * the scene has a mirror or glass material (the default). `photons`: 1 .. 10^9, or 0 for the
 * default (RAD_SPECULAR_PHOTONS). */
#define RAD_SPECULAR_PHOTONS 1000000
rad_status rad_scene_set_specular_first(rad_scene *scene, int on, uint64_t photons);

/* Makes every surface of a geometric scene two-sided (`--two-sided`; glTF doubleSided does it
 * per material): both faces receive and reflect, as two one-sided surfaces back to back
 * (surfaces "NAME (back)"). Emitting surfaces stay one-sided (a panel would emit twice its
 * power), and glass has both sides already. A patch system: RAD_ERROR_INVALID_ARGUMENT. */
rad_status rad_scene_set_two_sided(rad_scene *scene);

#ifdef __cplusplus
}
#endif
#endif /* RADIOSITY_H */
