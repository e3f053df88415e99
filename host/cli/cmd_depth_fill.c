/* relief depth-fill: repair of depth and range images, and of meshes
 * through six depth images (paper 003; relief/depth.h): the options, the
 * files, one call of relief_depth_fill or relief_depth_fill_mesh, the
 * outputs (all or none) and the summary. */
#include "cli/commands.h"

#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "relief/relief.h"
#include "base/error.h"
#include "base/memlimit.h"
#include "cli/batch.h"
#include "cli/camera_files.h"
#include "cli/options.h"
#include "depth/depth_io.h"
#include "mesh/mesh.h"
#include "depth/frame.h"

/* A PGM (NYU's raw frames) is read as a PNG depth is, and written as a
 * 16-bit PNG: IN_PNG, its name's only difference. */
typedef enum in_kind { IN_PNG, IN_PFM, IN_PCD, IN_MESH } in_kind;

static int kind_of_name(const char *path, in_kind *k)
{
    const char *ext = cli_ext_of(path);
    if (strcasecmp(ext, ".png") == 0 || strcasecmp(ext, ".pgm") == 0)
        *k = IN_PNG;
    else if (strcasecmp(ext, ".pfm") == 0)
        *k = IN_PFM;
    else if (strcasecmp(ext, ".pcd") == 0)
        *k = IN_PCD;
    else if (cli_known_mesh_ext(path))
        *k = IN_MESH;
    else
        return 0;
    return 1;
}

static const char *kind_name(in_kind k)
{
    return k == IN_PNG ? "PNG" : k == IN_PFM ? "PFM" : k == IN_PCD ? "PCD" : "a mesh";
}

/* What the command line asked. */
typedef struct depth_args {
    cli_common cm;
    relief_depth_fill_params p;
    const char *in, *truth, *points, *colour;
    const char *camera_file; /* --intrinsics CAMERA.json */
    int has_camera;          /* --intrinsics given */
    cli_camera camera;       /* its numbers (a file's once read) */
    double scale; /* --scale; 0: the default */
    relief_depth_encoding encoding; /* --depth-format (auto) */
    in_kind kind;
    cli_output outs[3]; /* -o, --points, --report */
} depth_args;

enum { DF_SCALE = OPT_COMMAND, DF_TRUTH, DF_POINTS, DF_HOLE_MASK, DF_COLOUR, DF_FORMAT,
       DF_INTRINSICS };

static const cli_own own[] = {
    {"scale", DF_SCALE, "S", "16-bit PNG: values per metre (default 5000, TUM and Kinect)"},
    {"truth", DF_TRUTH, "T", "measure against T (IN's format): RMS over the filled pixels "
     "and the slope jump at the rim; for a mesh, the complete mesh: surface distances and "
     "voxel IoU"},
    {"depth-format", DF_FORMAT, "F", "(PNG, PGM) how the samples are depths: auto (default: "
     "a PNG or big-endian PGM at --scale), png, pgm, nyu (NYU Depth v2's raw Kinect "
     "disparities) or sun (SUN RGB-D's rotated bits, millimetres); OUT is a 16-bit PNG "
     "at --scale"},
    {"colour", DF_COLOUR, "C", "(PNG, PFM) the frame's registered colour image, of its "
     "size: where a hole lies across a depth step (edges layers), its colour edges part "
     "the surfaces, as a PCD's own colour does"},
    {"intrinsics", DF_INTRINSICS, "FX,FY,CX,CY|CAMERA.json", "(PNG, PGM) the depth "
     "image's pinhole camera, pixels, or Open3D's camera JSON of its size: --points then "
     "back-projects every pixel through it"},
    {"points", DF_POINTS, "OUT.ply", "(PCD; PNG or PGM with --intrinsics) the repaired points, coloured where IN (or --colour) has "
     "colour, with a 'label' property: 1 for the filled ones"},
    {"hole-mask", DF_HOLE_MASK, "WHAT", "(mesh) fill exactly the holes whose rims touch WHAT, "
     "whatever their size (a border, or a rim wider than max_hole, only where WHAT touches "
     "it: the notch, closed by its chord): ball:X,Y,Z,R or label (the vertices with a "
     "non-zero PLY label)"},
    {NULL, 0, NULL, NULL}};

static cli_spec spec(void)
{
    cli_spec s = {"depth-fill", "IN -o OUT [--variant plain|haar|decompose] [options]\n"
                  "       relief depth-fill MESH -o OUT_MESH [--resolution N] [options]",
                  "Repair the missing pixels of a depth or range image by constrained "
                  "texture synthesis (paper 003). IN is an organised PCD (x y z [rgb]; "
                  "ascii, binary or binary_compressed), a PFM (Middlebury disparities) or a "
                  "16-bit PNG depth image (--scale units per metre). Missing: 0, NaN or inf, "
                  "or MASK's non-zero pixels. OUT is written in IN's format; known pixels "
                  "keep their depths (a PCD keeps x y z as floats and rgb; its other fields "
                  "and viewpoint are not kept). Missing pixels outside the capture (no known "
                  "pixel on both sides along their row or column: a camera's invalid "
                  "margin) are left missing.\n\n"
                  "A mesh (PLY, OBJ, OFF, STL; triangles counter-clockwise from outside) is "
                  "repaired through the six orthographic depth images of its bounding box: "
                  "the pixels whose ray meets the mesh's inside through a hole are repaired, "
                  "the voxels between the front and back depths of every axis kept, and "
                  "their surface (marching tetrahedra) written as OUT_MESH, closed.",
                  CLI_OUTPUT | CLI_REPORT | CLI_QUIET | CLI_MASK | CLI_LIMIT,
                  "the repaired image, IN's format; required, never IN",
                  "PNG of IN's size: non-zero = missing too", NULL, 0, NULL, own, NULL};
    s.params = relief_depth_fill_param_table(&s.n_params);
    return s;
}

/* The command's own options: 1 taken, 0 a bad value (said). */
static int take(void *ctx, int c, const char *arg)
{
    depth_args *a = ctx;
    switch (c) {
    case DF_SCALE: return cli_parse_real("depth-fill", "--scale", arg, &a->scale);
    case DF_TRUTH: a->truth = arg; return 1;
    case DF_POINTS: a->points = arg; return 1;
    case DF_COLOUR: a->colour = arg; return 1;
    case DF_INTRINSICS:
        a->has_camera = 1;
        a->camera_file = cli_camera_numbers(arg, &a->camera) ? NULL : arg;
        return 1;
    case DF_FORMAT: {
        static const char *const encodings[] = CLI_NAMES(RELIEF_DEPTH_ENCODING_LIST);
        int v;
        if (!CLI_PARSE_ENUM("depth-fill", "--depth-format", arg, encodings, &v))
            return 0;
        a->encoding = (relief_depth_encoding)v;
        /* NYU's and SUN's depths are millimetres: written back at that */
        if (a->scale == 0.0 && (v == RELIEF_DEPTH_ENCODING_NYU || v == RELIEF_DEPTH_ENCODING_SUN))
            a->scale = 1000.0;
        return 1;
    }
    case DF_HOLE_MASK:
        return cli_parse_hole_mask("depth-fill", arg, &a->p.hole_labels, &a->p.has_hole_ball,
                                   a->p.hole_ball);
    }
    return 0;
}

/* The files' names of one run (a->in to a->cm.out): 0 when they fit
 * together, else the exit status (said). */
static int check_files(depth_args *a)
{
    const char *out = a->cm.out, *ins[5];
    in_kind kout, kt;
    if (!kind_of_name(a->in, &a->kind))
        return cli_usage_error("depth-fill", "IN: '%s' does not end in .pcd, .pfm, .png or "
                                "a mesh's .ply, .obj, .off, .stl", a->in);
    if (a->encoding != RELIEF_DEPTH_ENCODING_AUTO && a->kind != IN_PNG)
        return cli_usage_error("depth-fill", "--depth-format: '%s' is no PNG or PGM depth "
                                "image", a->in);
    if (a->kind == IN_PNG && strcasecmp(cli_ext_of(out), ".png") != 0)
        return cli_usage_error("depth-fill", "-o: '%s': a PNG's or PGM's repair is written as "
                                "a 16-bit PNG: give OUT the .png extension", out);
    if (!kind_of_name(out, &kout) || kout != a->kind)
        return cli_usage_error("depth-fill", "-o: '%s': OUT is written in IN's format: give "
                                "it IN's extension (a mesh: .ply, .obj, .off or .stl)", out);
    if (a->kind == IN_MESH && (a->cm.mask || a->points))
        return cli_usage_error("depth-fill", "%s--mask and --points are for depth images, "
                                "not meshes", "");
    if (a->colour && (a->kind == IN_PCD || a->kind == IN_MESH))
        return cli_usage_error("depth-fill", "--colour '%s': a PCD carries its own colour "
                                "and a mesh none: --colour is for a PNG or PFM", a->colour);
    if (a->has_camera && a->kind != IN_PNG)
        return cli_usage_error("depth-fill", "--intrinsics: '%s' is no PNG or PGM depth image "
                                "(a PCD carries its points)", a->in);
    if (a->points && a->kind != IN_PCD && !a->has_camera)
        return cli_usage_error("depth-fill", "--points: '%s': points need an organised PCD, or "
                                "a depth image's camera (--intrinsics)", a->points);
    if (a->truth && a->kind == IN_MESH && !cli_known_mesh_ext(a->truth))
        return cli_usage_error("depth-fill", "--truth '%s': a mesh's truth is the complete "
                                "mesh (.ply, .obj, .off or .stl)", a->truth);
    if (a->truth && a->kind != IN_MESH && (!kind_of_name(a->truth, &kt) || kt != a->kind)) {
        fprintf(stderr, "relief depth-fill: error: --truth %s: expected IN's format (%s)\n",
                a->truth, kind_name(a->kind));
        return EXIT_USAGE;
    }
    ins[0] = a->in, ins[1] = a->cm.mask, ins[2] = a->truth, ins[3] = a->colour;
    ins[4] = a->camera_file;
    a->outs[0] = (cli_output){"-o", out, CLI_OUT_FILE};
    a->outs[1] = (cli_output){"--points", a->points, CLI_OUT_FILE};
    a->outs[2] = (cli_output){"--report", a->cm.report, CLI_OUT_FILE};
    return cli_check_outputs("depth-fill", ins, 5, a->outs, 3);
}

/* The options into *a: -1 to go on, else the exit status. */
static int parse_args(int argc, char **argv, depth_args *a)
{
    cli_spec s = spec();
    int rc;
    memset(a, 0, sizeof *a);
    a->cm = cli_common_init("depth-fill");
    a->p = relief_depth_fill_params_default();
    rc = cli_parse(&s, &a->cm, &a->p, take, a, argc, argv);
    return rc ? (rc < 0 ? 0 : rc) : -1;
}

/* The files and the parameters of one run: -1 to go on, else the exit
 * status (said). */
static int check_run(depth_args *a)
{
    relief_error err = {0};
    int rc = check_files(a);
    if (rc)
        return rc;
    a->p.run.input_name = a->in;
    a->p.run.output_name = a->cm.out;
    if (relief_depth_fill_params_validate(&a->p, &err) != RELIEF_OK)
        return cli_fail("depth-fill", &err);
    return -1;
}

/* The host memory limit the readers take: --max-memory, or the default. */
static uint64_t read_limit(const depth_args *a)
{
    return a->p.run.max_memory ? a->p.run.max_memory : relief_default_memory_limit();
}

/* A depth frame whose format is its name's. */
static relief_status read_frame(const depth_args *a, const char *path, relief_depth_image *f,
                                relief_error *err)
{
    relief_status st = relief_depth_read_as(path, a->encoding, a->scale, read_limit(a) / 64, f,
                                            err);
    relief_depth_format want = a->kind == IN_PFM ? RELIEF_DEPTH_PFM : RELIEF_DEPTH_PNG16;
    if (st != RELIEF_OK)
        return st;
    if (a->kind == IN_PCD ? f->format == RELIEF_DEPTH_PFM || f->format == RELIEF_DEPTH_PNG16
                          : f->format != want)
        st = relief_fail(err, RELIEF_E_FORMAT, "%s is a %s file named %s", path,
                         relief_depth_format_name(f->format), cli_ext_of(path));
    if (st != RELIEF_OK)
        relief_depth_image_free(f);
    return st;
}

/* --colour: the frame's colour as 8-bit RGB into f->rgb (owned by f: the
 * PNG and PFM writers ignore it). Grey is repeated, alpha dropped, 16 bits
 * taken to their high byte. */
static relief_status read_colour(const depth_args *a, relief_depth_image *f, relief_error *err)
{
    relief_image c = {0, 0, 0, 0, 0, NULL};
    relief_status st = relief_image_read(a->colour, read_limit(a), &c, err);
    size_t n = (size_t)f->width * f->height;
    if (st == RELIEF_OK && (c.width != f->width || c.height != f->height))
        st = relief_fail(err, RELIEF_E_USAGE, "--colour %s is %d x %d pixels, %s is %d x %d: "
                         "they must be the same size", a->colour, c.width, c.height, a->in,
                         f->width, f->height);
    if (st == RELIEF_OK && !(f->rgb = malloc(3 * n)))
        st = relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the colour of %s", a->colour);
    if (st == RELIEF_OK)
        cli_image_rgb8(&c, f->rgb);
    relief_image_free(&c);
    return st;
}

/* --intrinsics CAMERA.json: its numbers, its size IN's. */
static relief_status read_camera(depth_args *a, const relief_depth_image *f, relief_error *err)
{
    relief_status st = cli_read_camera_json("--intrinsics", a->camera_file, &a->camera, err);
    if (st == RELIEF_OK && a->camera.width &&
        (a->camera.width != f->width || a->camera.height != f->height))
        st = relief_fail(err, RELIEF_E_USAGE, "--intrinsics %s is a camera of %d x %d pixels, "
                         "%s is %d x %d", a->camera_file, a->camera.width, a->camera.height,
                         a->in, f->width, f->height);
    return st;
}

/* The repaired depth image's points for --points: each pixel back-projected
 * through --intrinsics (NaN where still missing), as a PCD carries them. */
static relief_status camera_points(const depth_args *a, relief_depth_image *f,
                                   relief_error *err)
{
    const double *k = a->camera.k;
    if (!(f->xyz = malloc((size_t)f->width * f->height * 3 * sizeof *f->xyz)))
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the frame's points");
    for (int v = 0; v < f->height; ++v)
        for (int u = 0; u < f->width; ++u) {
            size_t i = (size_t)v * f->width + u;
            float z = isfinite(f->z[i]) && f->z[i] > 0.0f ? f->z[i] : NAN;
            f->xyz[3 * i] = (float)((u - k[2]) / k[0] * z);
            f->xyz[3 * i + 1] = (float)((v - k[3]) / k[1] * z);
            f->xyz[3 * i + 2] = z;
        }
    return RELIEF_OK;
}

/* What write_one writes: OUT (a frame, or a mesh), --points, --report
 * with the names of the files the engine did not read. */
typedef struct depth_out {
    const depth_args *a;
    const relief_depth_image *f;
    const relief_mesh *mesh;
    const uint8_t *label;
    const char *json;
    const char *repair; /* a mesh's "input_repair" member (cli_repair_json) */
} depth_out;

static relief_status write_one(void *ctx, size_t i, relief_sink *s, relief_error *err)
{
    static const char *const keys[] = {"mask", "truth"};
    const depth_out *o = ctx;
    const char *values[] = {o->a->cm.mask, o->a->truth};
    if (i == 0)
        return o->mesh ? relief_mesh_write_to(o->mesh, s, NULL, err)
                       : relief_depth_write_to(s, o->f, o->f->format, o->a->scale, err);
    if (i == 1)
        return relief_depth_points_write_to(s, o->f, o->label, err);
    /* A mesh's report names its truth only. */
    return o->mesh ? cli_json_with_to(s, o->json, 1, keys + 1, values + 1, o->repair, err)
                   : cli_json_to(s, o->json, 2, keys, values, err);
}

static void say_image(const depth_args *a, const relief_depth_image *f,
                      const relief_depth_fill_report *r)
{
    size_t n = (size_t)f->width * f->height;
    if (r->backend_note[0])
        fprintf(stderr, "relief depth-fill: %s\n", r->backend_note);
    if (f->xyz && !r->camera_fitted)
        fprintf(stderr, "relief depth-fill: warning: %s: no camera could be fitted to its "
                "points: the filled pixels' points are NaN\n", a->in);
    if (r->membrane_capped)
        fprintf(stderr, "relief depth-fill: warning: the membrane stopped at its %d-iteration "
                "cap before converging\n", r->membrane_iterations);
    if (r->unreached)
        fprintf(stderr, "relief depth-fill: warning: %zu coefficients joined to no known one "
                "kept zero detail\n", r->unreached);
    if (!r->missing) {
        fprintf(stderr, "relief depth-fill: %s: no missing pixels: written unchanged\n", a->in);
        return;
    }
    fprintf(stderr, "relief depth-fill: %s: %zu of %zu pixels missing (%.1f %%): %zu filled, "
            "%zu outside the capture left missing; variant %s: %zu synthesised (%s order), %zu "
            "by the membrane, %zu fallbacks; %.2f s on %s\n", a->in, r->missing, n,
            100.0 * r->missing / n, r->filled, r->outside, relief_depth_variant_name(a->p.variant),
            r->by_synthesis, relief_depth_order_name(r->order_kept), r->by_membrane,
            r->by_fallback, r->seconds_total, r->device);
    if (a->p.edges != RELIEF_DEPTH_EDGES_ACROSS && r->stepped_holes)
        fprintf(stderr, "relief depth-fill: edges layers: %zu holes across a depth step (over "
                "%g x the noise measured, %.3g%s), filled surface by surface, %zu pixels by a "
                "nearer surface than the farthest%s\n", r->stepped_holes, a->p.edge_step,
                r->noise, f->format == RELIEF_DEPTH_PFM ? "" : " z^2", r->front_pixels,
                f->rgb ? " (parted by colour)" : "");
    if (r->measured)
        fprintf(stderr, "relief depth-fill: against %s: RMS %.6g over %zu pixels; slope jump "
                "at the rim %.3g (fill %.4g, the truth's own %.4g, the capture's second "
                "difference %.4g)\n", a->truth, r->rms, r->compared, r->slope_jump,
                r->rim_jump, r->truth_rim_jump, r->capture_jump);
}

/* A depth image: read, repaired, written. */
static int image_mode(depth_args *a)
{
    relief_error err = {0};
    relief_depth_image f, truth;
    relief_image mask = {0, 0, 0, 0, 0, NULL};
    relief_depth_fill_report rep;
    uint8_t *label = NULL;
    cli_progress pr;
    relief_status st;
    memset(&f, 0, sizeof f);
    memset(&truth, 0, sizeof truth);
    memset(&rep, 0, sizeof rep);
    if (a->p.has_hole_ball || a->p.hole_labels || a->p.solid || a->p.max_hole > 0.0)
        return cli_usage_error("depth-fill", "%s: --hole-mask, --max-hole and --solid choose a "
                               "mesh's holes; a depth image's are its missing pixels (--mask "
                               "adds more)", a->in);
    st = read_frame(a, a->in, &f, &err);
    if (st == RELIEF_OK && a->cm.mask) {
        st = relief_image_read(a->cm.mask, read_limit(a), &mask, &err);
        if (st == RELIEF_OK && (mask.width != f.width || mask.height != f.height))
            st = relief_fail(&err, RELIEF_E_USAGE, "--mask %s is %d x %d pixels, %s is %d x "
                             "%d: they must be the same size", a->cm.mask, mask.width,
                             mask.height, a->in, f.width, f.height);
    }
    if (st == RELIEF_OK && a->colour)
        st = read_colour(a, &f, &err);
    if (st == RELIEF_OK && a->camera_file)
        st = read_camera(a, &f, &err);
    if (st == RELIEF_OK && a->truth) {
        st = read_frame(a, a->truth, &truth, &err);
        if (st == RELIEF_OK && (truth.width != f.width || truth.height != f.height))
            st = relief_fail(&err, RELIEF_E_USAGE, "--truth %s is %d x %d pixels, %s is %d x "
                             "%d: they must be the same size", a->truth, truth.width,
                             truth.height, a->in, f.width, f.height);
        a->p.truth = &truth;
    }
    /* The points' labels: the pixels missing before the repair. */
    if (st == RELIEF_OK && a->points && !(label = malloc((size_t)f.width * f.height)))
        st = relief_fail(&err, RELIEF_E_NOMEM, "cannot allocate the points' labels");
    if (st == RELIEF_OK && label) {
        size_t in_input, by_mask;
        relief_depth_missing(&f, a->cm.mask ? &mask : NULL, label, &in_input, &by_mask);
    }
    if (st == RELIEF_OK) {
        cli_progress_start(&pr, &a->cm, &a->p.run);
        st = relief_depth_fill(&f, a->cm.mask ? &mask : NULL, &a->p, &rep, &err);
        cli_progress_end(&pr);
        cli_progress_explain(&pr, st, &err);
    }
    if (st == RELIEF_OK && a->points && !f.xyz)
        st = camera_points(a, &f, &err);
    if (st == RELIEF_OK) {
        depth_out o = {a, &f, NULL, label, rep.json, NULL};
        st = cli_write_outputs(a->outs, 3, write_one, &o, NULL, &err);
    }
    if (st == RELIEF_OK && !a->cm.quiet)
        say_image(a, &f, &rep);
    relief_depth_fill_report_free(&rep);
    relief_depth_image_free(&f);
    relief_depth_image_free(&truth);
    relief_image_free(&mask);
    free(label);
    return st == RELIEF_OK ? 0 : cli_fail("depth-fill", &err);
}

/* A mesh through its six depth images. */
static int mesh_mode(depth_args *a)
{
    relief_error err = {0};
    relief_mesh *m = NULL, *t = NULL, *o = NULL;
    relief_depth_fill_report r;
    cli_progress pr;
    relief_read_info info;
    char repair[1024] = "";
    relief_status st = cli_read_mesh("depth-fill", a->in, a->cm.quiet, &m, &info, &err);
    memset(&r, 0, sizeof r);
    if (st == RELIEF_OK && a->truth)
        st = cli_read_mesh("depth-fill", a->truth, a->cm.quiet, &t, NULL, &err);
    if (st == RELIEF_OK)
        cli_repair_json(&info, repair, sizeof repair);
    if (st == RELIEF_OK) {
        cli_progress_start(&pr, &a->cm, &a->p.run);
        st = relief_depth_fill_mesh(m, &a->p, t, &o, &r, &err);
        cli_progress_end(&pr);
        cli_progress_explain(&pr, st, &err);
    }
    if (st == RELIEF_OK) {
        depth_out w = {a, NULL, o, NULL, r.json, repair};
        st = cli_write_outputs(a->outs, 3, write_one, &w, NULL, &err);
    }
    if (st == RELIEF_OK && !a->cm.quiet) {
        if (r.backend_note[0])
            fprintf(stderr, "relief depth-fill: %s\n", r.backend_note);
        if (r.holes_left[0])
            fprintf(stderr, "relief depth-fill: %s\n", r.holes_left);
        fprintf(stderr, "relief depth-fill: %s: %d x %d x %d voxels of %.4g; six depth images, "
                "%zu pixels seen through holes, %zu repaired (variant %s); %zu inside voxels; "
                "%zu vertices, %zu triangles; %.2f s\n", a->in, r.grid[0], r.grid[1], r.grid[2],
                r.voxel, r.missing, r.filled, relief_depth_variant_name(a->p.variant),
                r.inside_voxels, r.vertices, r.triangles, r.seconds_total);
        if (t)
            fprintf(stderr, "relief depth-fill: against %s: mean distance %.4g, Hausdorff %.4g "
                    "(%.2f voxels), voxel IoU %.4f\n", a->truth, r.rms, r.hausdorff,
                    r.hausdorff / r.voxel, r.iou);
    }
    relief_depth_fill_report_free(&r);
    relief_mesh_destroy(m);
    relief_mesh_destroy(t);
    relief_mesh_destroy(o);
    return st == RELIEF_OK ? 0 : cli_fail("depth-fill", &err);
}

/* One input (a->in to a->cm.out): the checks, then, unless parse_only,
 * the run. Returns the exit status. */
static int one(depth_args *a, int parse_only)
{
    int rc = check_run(a);
    if (rc >= 0 || parse_only)
        return rc >= 0 ? rc : 0;
    return a->kind == IN_MESH ? mesh_mode(a) : image_mode(a);
}

/* A batch's run on one input (batch.h): a copy of the job, quiet. */
static int batch_one(const void *job, const char *in, const char *out)
{
    depth_args a = *(const depth_args *)job;
    a.in = in, a.cm.out = out, a.cm.quiet = 1;
    return one(&a, 0);
}

int cli_cmd_depth_fill(int argc, char **argv, int parse_only)
{
    depth_args a;
    int rc = parse_args(argc, argv, &a);
    if (rc >= 0)
        return rc;
    if (cli_batch_asked(&a.cm, argc)) {
        const cli_batch b = {NULL, batch_one, &a,
                             {{"--report", a.cm.report}, {"--points", a.points},
                              {"--truth", a.truth}}};
        return cli_batch_run(&a.cm, &b, argv + optind, argc - optind, parse_only);
    }
    if (!cli_one_input(&a.cm, argc, argv, "input IN", &a.in))
        return EXIT_USAGE;
    return one(&a, parse_only);
}
