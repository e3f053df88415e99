/* relief/core.h: what every engine shares: statuses and errors, the
 * backends and a call's run options and progress, meshes and their files,
 * synthetic surfaces, devices. Include <relief/relief.h> (everything) or an
 * engine's header (which brings this one). */
#ifndef RELIEF_CORE_H
#define RELIEF_CORE_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* What the shared library exports: only the functions declared in the
 * public headers (the build hides the rest). */
#if defined(RELIEF_STATIC_DEFINE) || !defined(__GNUC__)
#define RELIEF_API
#else
#define RELIEF_API __attribute__((visibility("default")))
#endif

#define RELIEF_VERSION_MAJOR 0
#define RELIEF_VERSION_MINOR 1
#define RELIEF_VERSION_PATCH 0
#define RELIEF_VERSION_STRING "0.1.0"

/* The version of the library linked at run time ("0.1.0"), which may
 * differ from RELIEF_VERSION_STRING, the one compiled against. */
RELIEF_API const char *relief_version(void);

/* ------------------------------------------------------------------ status */

/* One list generates the enum, the names and the messages.
 * X(code, value, name, message, exit code of the CLI) */
#define RELIEF_STATUS_LIST(X)                                                  \
    X(RELIEF_OK, 0, "ok", "success", 0)                                        \
    X(RELIEF_E_USAGE, 1, "usage", "invalid usage or option", 1)                \
    X(RELIEF_E_RANGE, 2, "range", "parameter out of range", 1)                 \
    X(RELIEF_E_IO, 3, "io", "cannot open, read or write a file", 1)            \
    X(RELIEF_E_FORMAT, 4, "format", "unknown or unsupported file format", 1)   \
    X(RELIEF_E_PARSE, 5, "parse", "malformed or truncated file", 1)            \
    X(RELIEF_E_MESH, 6, "mesh", "invalid mesh", 1)                             \
    X(RELIEF_E_NOMEM, 7, "nomem", "out of memory", 2)                          \
    X(RELIEF_E_DEVICE, 8, "device", "compute device failure", 2)               \
    X(RELIEF_E_NOT_BUILT, 9, "not-built", "feature not built in", 2)           \
    X(RELIEF_E_NOT_IMPLEMENTED, 10, "not-implemented",                         \
      "not implemented yet", 2)                                                \
    X(RELIEF_E_INTERNAL, 11, "internal", "internal error", 2)                  \
    X(RELIEF_E_CANCELLED, 12, "cancelled",                                  \
      "cancelled (by the progress callback or SIGINT)", 130)                   \
    X(RELIEF_E_SYSTEM, 13, "system",                                           \
      "the system failed a read or write (disk full, I/O error, read-only "    \
      "file system)", 2)

typedef enum relief_status {
#define RELIEF_X_ENUM(code, value, name, msg, exit_code) code = value,
    RELIEF_STATUS_LIST(RELIEF_X_ENUM)
#undef RELIEF_X_ENUM
} relief_status;

/* Static, human-readable description of a status ("malformed or truncated
 * file"). Never NULL; unknown values give "unknown status". */
RELIEF_API const char *relief_strerror(relief_status status);

/* Short stable name of a status ("parse"), for JSON reports and logs. */
RELIEF_API const char *relief_status_name(relief_status status);

/* Process exit code the CLI uses for a status: 0 success, 1 bad input or
 * usage, 2 a resource (memory, disk, the system's I/O), device or internal
 * failure, 130 interrupted (128 + SIGINT, as a shell reports a process
 * killed by Ctrl-C). */
RELIEF_API int relief_status_exit_code(relief_status status);

/* Why a call failed, where a caller may act on it without reading the
 * message: a finer kind than the status. One list generates the enum, the
 * names and the descriptions. X(code, value, name, description) */
#define RELIEF_REASON_LIST(X)                                                  \
    X(RELIEF_REASON_NONE, 0, "none", "no finer reason")                        \
    X(RELIEF_REASON_NOTHING_TO_FILL, 1, "nothing-to-fill",                     \
      "the selection holds no hole to fill")                                   \
    X(RELIEF_REASON_HOLES_LEFT_OPEN, 2, "holes-left-open",                     \
      "the hole model leaves every missing region open")                       \
    X(RELIEF_REASON_FOLD_REFUSED, 3, "fold-refused",                           \
      "the capture overlaps itself over its primitive")                        \
    X(RELIEF_REASON_DEVICE_FELL_BACK, 4, "device-fell-back",                   \
      "OpenCL was unavailable and the host ran the call")                      \
    X(RELIEF_REASON_NO_SPACE, 5, "no-space",                                   \
      "no space left (disk full, quota or file size limit)")                   \
    X(RELIEF_REASON_READ_ONLY, 6, "read-only", "a read-only file system")      \
    X(RELIEF_REASON_NO_PERMISSION, 7, "no-permission",                         \
      "the system refused access to a path")                                   \
    X(RELIEF_REASON_NOT_RELIEFS, 8, "not-reliefs",                             \
      "a file or folder relief did not write was named as its output")         \
    X(RELIEF_REASON_PARAMETER, 9, "parameter",                                 \
      "a parameter's value (the error's `param` names it)")                    \
    X(RELIEF_REASON_TIME_LIMIT, 10, "time-limit",                              \
      "the call ran past its time limit")

typedef enum relief_reason {
#define RELIEF_X_ENUM(code, value, name, desc) code = value,
    RELIEF_REASON_LIST(RELIEF_X_ENUM)
#undef RELIEF_X_ENUM
} relief_reason;

/* Short stable name of a reason ("no-space"); "unknown" out of range. */
RELIEF_API const char *relief_reason_name(relief_reason reason);

#define RELIEF_ERROR_MESSAGE_MAX 1024
#define RELIEF_ERROR_PARAM_MAX 64

/* Where a failed call explains itself. Owned by the caller; zero-initialise
 * it (`relief_error err = {0}`) or pass NULL when the detail is not wanted:
 * every entry point accepts NULL. Decide on `status`, `reason`, `param`
 * and `sys_errno`, never on the message's text, which is for people and
 * may change. */
typedef struct relief_error {
    relief_status status;
    char message[RELIEF_ERROR_MESSAGE_MAX]; /* one line: what, where, why */
    relief_reason reason;       /* RELIEF_REASON_NONE when no finer kind */
    int sys_errno;              /* the system's errno behind an I/O or system
                                   failure (ENOSPC, EROFS, ...), else 0 */
    char param[RELIEF_ERROR_PARAM_MAX]; /* the parameter the failure concerns
                                   ("min_window", "threads"), or "";
                                   relief_param_set's message then starts
                                   with "PARAM:", which a client may show
                                   under its own name for it (--min-window) */
} relief_error;

/* ------------------------------------------------------- parameter tables */

/* What a parameter holds. */
typedef enum relief_param_kind {
    RELIEF_PARAM_FLAG,  /* int, 0 or 1 */
    RELIEF_PARAM_INT,   /* int */
    RELIEF_PARAM_SEED,  /* uint32_t */
    RELIEF_PARAM_REAL,  /* double */
    RELIEF_PARAM_ENUM,  /* an enumeration (int-sized), written by its names */
    RELIEF_PARAM_BYTES, /* uint64_t, a size: "1048576", "512K", "64M", "4G" */
    RELIEF_PARAM_PATH,  /* const char *, borrowed from the caller */
    RELIEF_PARAM_REALS  /* double[]: "X,Y,Z,R"; how many go to another field */
} relief_param_kind;

/* One parameter of an engine, described once for every client that sets
 * parameters by name (the command line's --min-window is the field
 * min_window; Python's keyword arguments) and for the documentation. The
 * engine's _validate checks the range given here (tests/api holds the two
 * together): a value is accepted when it is in [min, max] or one of the
 * special values, whose meaning `help` says. */
typedef struct relief_param {
    const char *name;          /* the field ("min_window"; run's "backend") */
    relief_param_kind kind;
    size_t offset;             /* of the field in the engine's params struct */
    const char *value;         /* how a value is written ("W", "X,Y,Z,R") */
    const char *const *names;  /* ENUM: the enumeration's names in order, NULL last */
    double min, max;           /* INT, SEED, REAL, BYTES: the range (+-HUGE_VAL:
                                  none); REALS: how many values */
    int n_special;             /* 0 to 2 values outside [min, max] that mean */
    double special[2];         /* something (a default chosen for you) */
    size_t count_offset;       /* REALS: the int field that receives how many */
    int count_is_flag;         /* REALS: 1 when that field is a flag (set to 1) */
    const char *help;          /* what it does, its default, its special values */
} relief_param;

/* The parameter of `table` (`count` entries) named `name`, or NULL. */
RELIEF_API const relief_param *relief_param_find(const relief_param *table, size_t count,
                                                 const char *name);

/* Set the parameter `p` of the params struct `params` from its text form
 * ("17", "auto", "yes", "512M", "1,2,3,0.5"). The text is checked for its
 * kind only (RELIEF_E_USAGE naming the parameter: not a number, not one of
 * the names, too many values); its range is the engine's _validate's. A
 * PATH keeps the pointer `text`. */
RELIEF_API relief_status relief_param_set(void *params, const relief_param *p,
                                          const char *text, relief_error *err);

/* Write the value of `p` in `params` as text into buf (at most size bytes,
 * terminated): the form relief_param_set takes. Returns the length the
 * whole text needs. */
RELIEF_API size_t relief_param_format(const void *params, const relief_param *p, char *buf,
                                      size_t size);

/* ------------------------------------------------------------------- mesh */

/* A triangle mesh or point cloud: positions, triangles and optional
 * per-vertex colour, normal and label arrays. The mesh owns all arrays;
 * pointers returned by the accessors stay valid until the mesh is destroyed.
 */
typedef struct relief_mesh relief_mesh;

/* Which optional per-vertex attributes a mesh carries. */
enum {
    RELIEF_MESH_COLOURS = 1u << 0, /* n x 3 float, linear RGB in [0, 1] */
    RELIEF_MESH_NORMALS = 1u << 1, /* n x 3 double, unit length */
    RELIEF_MESH_LABELS = 1u << 2   /* n uint8: relief_label values */
};

/* Per-vertex label written to and read from the PLY `label` property. */
typedef enum relief_label {
    RELIEF_LABEL_CAPTURED = 0,  /* original sample vertex */
    RELIEF_LABEL_COMPLETED = 1  /* vertex added by the completion */
} relief_label;

/* Create a mesh with n_vertices vertices and n_triangles triangles, all
 * arrays zero-filled, carrying the attributes in `attributes`
 * (RELIEF_MESH_* flags). */
RELIEF_API relief_status relief_mesh_create(size_t n_vertices, size_t n_triangles,
                                 unsigned attributes, relief_mesh **out,
                                 relief_error *err);

/* Free a mesh and all its arrays. NULL is accepted. */
RELIEF_API void relief_mesh_destroy(relief_mesh *mesh);

RELIEF_API size_t relief_mesh_vertex_count(const relief_mesh *mesh);
RELIEF_API size_t relief_mesh_triangle_count(const relief_mesh *mesh);
RELIEF_API unsigned relief_mesh_attributes(const relief_mesh *mesh);

/* n_vertices x 3 positions (double, input units). */
RELIEF_API double *relief_mesh_positions(relief_mesh *mesh);
/* n_triangles x 3 vertex indices, counter-clockwise seen from outside. */
RELIEF_API uint32_t *relief_mesh_triangles(relief_mesh *mesh);
/* n_vertices x 3 colours in [0, 1], or NULL when the mesh has none. */
RELIEF_API float *relief_mesh_colours(relief_mesh *mesh);
/* n_vertices x 3 unit normals, or NULL when the mesh has none. */
RELIEF_API double *relief_mesh_normals(relief_mesh *mesh);
/* n_vertices labels (relief_label), or NULL when the mesh has none. */
RELIEF_API uint8_t *relief_mesh_labels(relief_mesh *mesh);

/* Check a mesh is usable: at least one vertex, finite coordinates, triangle
 * indices in range and distinct, and, when it has triangles, at least one of
 * non-zero area. Names the first offending vertex or triangle. */
RELIEF_API relief_status relief_mesh_validate(const relief_mesh *mesh, relief_error *err);

/* -------------------------------------------------------------------- I/O */

/* What relief_mesh_repair changed, each step in the order it runs. A real
 * capture (photogrammetry, a scanner's export) comes as a triangle soup:
 * vertices listed twice, faces twice, slivers, fins on an edge, two fans
 * touching at a vertex, patches facing the other way, stray crumbs. The
 * later stages build a half-edge mesh (OpenMesh), which holds none of that,
 * so the reader mends it and says what it did. A clean mesh comes back
 * unchanged: same vertices, same triangles, same order. */
typedef struct relief_repair_info {
    size_t vertices_welded;        /* dropped: same coordinates as an earlier
                                      vertex; their triangles use that one */
    size_t degenerate_triangles;   /* dropped: a vertex twice after welding,
                                      or zero area */
    size_t duplicate_triangles;    /* dropped: the same three vertices as an
                                      earlier triangle, in any order */
    size_t nonmanifold_edges;      /* edges that had more than two triangles */
    size_t nonmanifold_edge_triangles; /* dropped from them: each such edge
                                      keeps two triangles, the pair that
                                      agrees in orientation first, then the
                                      most nearly coplanar pair, then the
                                      earliest; the others go */
    size_t triangles_flipped;      /* turned over so that each connected part
                                      is consistently oriented; a part keeps
                                      the orientation most of its triangles
                                      have */
    size_t orientation_triangles;  /* dropped: no orientation agreed with all
                                      their neighbours (a Moebius-like loop);
                                      the later of the two on such an edge */
    size_t nonmanifold_vertices;   /* vertices where several fans of
                                      triangles met (a bow-tie) */
    size_t vertices_added;         /* by splitting them: each fan but the one
                                      with the earliest triangle gets a copy
                                      of the vertex, appended */
    size_t small_components;       /* connected parts dropped: fewer than
                                      RELIEF_REPAIR_SMALL_TRIANGLES triangles
                                      and under 1 % of the mesh's triangles;
                                      the largest part is never dropped */
    size_t small_component_triangles; /* their triangles */
    size_t unstorable_triangles;   /* dropped: OpenMesh's add_face still
                                      refused them, in order */
    size_t vertices_unused;        /* dropped: used by triangles before the
                                      repair, by none after it (a vertex the
                                      file lists in no triangle is kept) */
} relief_repair_info;

/* Stray parts below this many triangles (and under 1 % of the mesh) are
 * dropped by the repair. */
#define RELIEF_REPAIR_SMALL_TRIANGLES 16

/* What a read found besides the mesh itself. */
typedef struct relief_read_info {
    char format[8];               /* "ply", "obj", "off" or "stl" */
    int binary;                   /* 1 for binary PLY or STL */
    size_t nonmanifold_triangles; /* faces OpenMesh could not add as they
                                     stand in the file (before the repair) */
    int repaired;                 /* 1 when the repair changed the mesh */
    relief_repair_info repair;    /* what it changed (all 0 when raw) */
} relief_read_info;

/* How to read. */
typedef struct relief_read_options {
    int raw; /* 1: no repair, the file's triangle soup as it is (non-manifold
                edges, bow-ties, duplicates, zero-area triangles kept);
                default 0 */
} relief_read_options;

/* Read PLY (ascii and binary), OBJ, OFF or STL, chosen by the file's
 * extension (case-insensitive), and repair it (relief_mesh_repair). Reads
 * per-vertex colour, normals and the PLY `label` property when present. A
 * file with vertices and no faces is read as a point cloud (not repaired).
 * Malformed, truncated or invalid content (NaN or Inf coordinates, a
 * coordinate over 1e30 in magnitude or a vertex over 1e15 times farther
 * from the median point than the other vertices, face indices out of range,
 * an empty or degenerate-only mesh, nothing left after the repair) is
 * rejected. `info` may be NULL. */
RELIEF_API relief_status relief_mesh_read(const char *path, relief_mesh **out,
                               relief_read_info *info, relief_error *err);

/* relief_mesh_read with options; `opts` NULL reads as relief_mesh_read. */
RELIEF_API relief_status relief_mesh_read_with(const char *path,
                                               const relief_read_options *opts,
                                               relief_mesh **out, relief_read_info *info,
                                               relief_error *err);

/* Mend a triangle soup in place into an edge- and vertex-manifold,
 * consistently oriented mesh that OpenMesh stores (the steps and their
 * rules: relief_repair_info). Vertices keep their order (welded and unused
 * ones go, split copies are appended), triangles keep theirs (dropped ones
 * go). A mesh with no triangle is left as it is. `info` may be NULL.
 * RELIEF_E_MESH when no triangle is left, or when the mesh is invalid
 * (relief_mesh_validate) or out of range (as relief_mesh_read says); the
 * mesh is then unchanged. */
RELIEF_API relief_status relief_mesh_repair(relief_mesh *mesh, relief_repair_info *info,
                                            relief_error *err);

/* The repair in words, for one line: "3 duplicate vertices welded, 2
 * triangles on non-manifold edges dropped". Writes "" and returns 0 when
 * nothing changed, else the count of items written. */
RELIEF_API int relief_repair_info_describe(const relief_repair_info *info, char *text,
                                           size_t size);

typedef struct relief_write_options {
    int ascii; /* PLY only: 1 writes ascii, 0 (default) little-endian binary */
} relief_write_options;

/* Write a mesh as PLY, OBJ, OFF or STL by the path's extension. PLY keeps
 * colour and the `label` property; OFF keeps colour; OBJ and STL keep
 * geometry only. The file is written under a temporary name in the same
 * folder, every write, the flush and fsync checked, and renamed into
 * place, so `path` is either the complete new file or untouched. A full
 * disk, a file size limit, an I/O error or a read-only file system is
 * RELIEF_E_SYSTEM with the system's reason and `path` (err->sys_errno,
 * err->reason); a folder that is not there or not writable, RELIEF_E_IO.
 * `opts` may be NULL (defaults). */
RELIEF_API relief_status relief_mesh_write(const relief_mesh *mesh, const char *path,
                                const relief_write_options *opts,
                                relief_error *err);

/* ------------------------------------------------------ synthetic surfaces */

/* Surfaces with known relief, for tests, demos and benchmarks. */
#define RELIEF_SYNTH_KIND_LIST(X)                                             \
    X(RELIEF_SYNTH_PLANE_WAVES, "plane-waves",                                \
      "plane with sinusoidal relief; a disc is missing")                      \
    X(RELIEF_SYNTH_PLANE_NOISE, "plane-noise",                                \
      "plane with stochastic pebbles; a disc is missing")                     \
    X(RELIEF_SYNTH_CYLINDER_BANDS, "cylinder-bands",                          \
      "cylinder with raised rings, seen from one side")                       \
    X(RELIEF_SYNTH_CYLINDER_BARK, "cylinder-bark",                            \
      "cylinder with stochastic ridges along the axis, seen from one side")   \
    X(RELIEF_SYNTH_SPHERE_DIMPLES, "sphere-dimples",                          \
      "golf ball: sphere with dimples, seen from one side")

typedef enum relief_synth_kind {
#define RELIEF_X_ENUM(code, name, desc) code,
    RELIEF_SYNTH_KIND_LIST(RELIEF_X_ENUM)
#undef RELIEF_X_ENUM
    RELIEF_SYNTH_KIND_COUNT
} relief_synth_kind;

/* Name ("plane-waves") and one-line description of a kind; NULL if out of
 * range. */
RELIEF_API const char *relief_synth_kind_name(relief_synth_kind kind);
RELIEF_API const char *relief_synth_kind_description(relief_synth_kind kind);
/* Kind by name; RELIEF_E_USAGE (listing the valid names) if unknown. */
RELIEF_API relief_status relief_synth_kind_parse(const char *name,
                                      relief_synth_kind *out,
                                      relief_error *err);

typedef struct relief_synth_params {
    relief_synth_kind kind;
    uint32_t seed;       /* MT19937 seed; default 1 */
    size_t vertices;     /* approximate vertex count of the whole truth
                            surface; default 2000, range [100, 4000000] */
    int colour;          /* 1: per-vertex colour; default 0 */
    double noise;        /* std. dev. of Gaussian scanner noise added along
                            the normal of the captured part, in units of
                            the primitive's size (radius or plane side);
                            default 0, range [0, 0.1] */
} relief_synth_params;

/* Defaults as documented in relief_synth_params. */
RELIEF_API relief_synth_params relief_synth_params_default(void);

/* Check every field; RELIEF_E_RANGE naming the field and its range. */
RELIEF_API relief_status relief_synth_params_validate(const relief_synth_params *params,
                                                      relief_error *err);

/* Make a synthetic surface. `*truth` receives the whole textured surface,
 * `*captured` the part a scanner sees (a cylinder or sphere seen from +x,
 * a plane with a disc removed), labelled RELIEF_LABEL_CAPTURED. Either
 * output pointer may be NULL when not wanted. Deterministic for a given
 * parameter set on every platform. Units: plane side 1, cylinder and sphere
 * radius 1. */
RELIEF_API relief_status relief_synth(const relief_synth_params *params,
                           relief_mesh **captured, relief_mesh **truth,
                           relief_error *err);

/* ------------------------------------------------------ backends and runs */

/* Who scores the candidate matches. Every backend gives the same bytes.
 *   scalar  the reference: plain C on one thread;
 *   opencl  the OpenCL kernel on a device (`device`; the first GPU or
 *           accelerator by default, else the first device);
 *   host    the reference's scoring on every core of the host, the same bits
 *           (relief_complete, relief_image_fill, relief_depth_fill;
 *           relief_complete_points takes it as scalar);
 *   auto    OpenCL on a GPU or accelerator when there is one (or on the
 *           device named), else the host's cores: on a CPU an OpenCL device
 *           runs on the same cores, and measured slower.
 * X(code, name) */
#define RELIEF_BACKEND_LIST(X)                                                  \
    X(RELIEF_BACKEND_AUTO, "auto")                                              \
    X(RELIEF_BACKEND_SCALAR, "scalar")                                          \
    X(RELIEF_BACKEND_OPENCL, "opencl")                                          \
    X(RELIEF_BACKEND_HOST, "host")

typedef enum relief_backend {
#define RELIEF_X_ENUM(code, name) code,
    RELIEF_BACKEND_LIST(RELIEF_X_ENUM)
#undef RELIEF_X_ENUM
} relief_backend;

/* "auto", "scalar", "opencl" or "host"; "unknown" out of range. */
RELIEF_API const char *relief_backend_name(relief_backend backend);

/* Progress of a long call: `fraction` of the work done, 0 to 1, never
 * decreasing within a call. Called on the calling thread, between two
 * steps of the engine (a target, a pixel, an iteration). Return 0 to go
 * on; any other value cancels the call, which then returns
 * RELIEF_E_CANCELLED and leaves every output of the caller untouched. */
typedef int (*relief_progress_fn)(void *ctx, double fraction);

/* What every engine call shares: where it runs, how much memory it may
 * take, its progress, and how its report names the files. */
typedef struct relief_run_options {
    relief_backend backend;      /* default auto */
    int device;                  /* OpenCL device index (relief_devices), or -1
                                    (default): the first GPU or accelerator, else
                                    the first device; [-1, 255] */
    uint64_t max_memory;         /* bytes of host memory a call may plan for: one
                                    whose estimate exceeds it is refused
                                    (RELIEF_E_NOMEM) before it allocates. 0
                                    (default): 80 % of physical memory */
    relief_progress_fn progress; /* NULL (default): none */
    void *progress_ctx;          /* passed to progress */
    const char *input_name;      /* what the report's JSON calls the input and */
    const char *output_name;     /* the output (a path, or any label); NULL
                                    (default): not named */
    int threads;                 /* host threads the call may run on at once,
                                    its own included: 1..RELIEF_THREADS_MAX, or 0
                                    (default): the CPUs the calling thread may
                                    run on (its affinity: taskset, a cpuset),
                                    at most RELIEF_THREADS_MAX. A stage may use
                                    fewer (the mesh growth's host scoring 16 at
                                    most); backend scalar runs on the calling
                                    thread alone whatever this says. The output
                                    is the same bytes for any count */
} relief_run_options;

/* The most host threads a call takes (relief_run_options.threads). */
#define RELIEF_THREADS_MAX 64

/* The defaults above. */
RELIEF_API relief_run_options relief_run_options_default(void);

/* Check the fields' ranges; RELIEF_E_RANGE naming the field and its range. */
RELIEF_API relief_status relief_run_options_validate(const relief_run_options *run,
                                                     relief_error *err);

/* ---------------------------------------------------------------- devices */

/* One OpenCL device as `relief devices` lists it and `--device` picks it. */
typedef struct relief_device_info {
    int index;                 /* the number --device takes */
    char platform[128];        /* platform name */
    char name[128];            /* device name */
    char type[16];             /* "cpu", "gpu", "accelerator" or "other" */
    char version[64];          /* the device's OpenCL version string */
    char driver[64];           /* driver version */
    unsigned compute_units;
    uint64_t global_mem_bytes;
    uint64_t max_alloc_bytes;  /* largest single buffer */
} relief_device_info;

/* Enumerate the OpenCL devices of every platform, numbered in platform then
 * device order. Fills at most `cap` entries of `out` (may be NULL with cap 0)
 * and sets `*count` to the number found; no platform is not an error (count
 * 0). RELIEF_E_USAGE for count NULL, or out NULL with cap > 0;
 * RELIEF_E_NOT_BUILT when relief was built without OpenCL;
 * RELIEF_E_DEVICE, naming the OpenCL error, when a query fails. */
RELIEF_API relief_status relief_devices(relief_device_info *out, size_t cap, size_t *count,
                             relief_error *err);

#ifdef __cplusplus
}
#endif

#endif /* RELIEF_CORE_H */
