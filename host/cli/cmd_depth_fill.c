/* relief depth-fill: repair of depth and range images (paper 003;
 * depth/depth_fill.h). */
#include "cli/commands.h"

#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <unistd.h>

#include "relief/relief.h"
#include "base/params.h"
#include "base/atomic.h"
#include "base/clock.h"
#include "base/error.h"
#include "base/json.h"
#include "base/memlimit.h"
#include "cli/options.h"
#include "depth/depth_fill.h"
#include "depth/depth_io.h"
#include "depth/mesh_fill.h"
#include "image/image_io.h"
#include "image/patch.h"

static const char depth_fill_help[] =
    "usage: relief depth-fill IN -o OUT [--variant plain|haar|decompose] [options]\n"
    "       relief depth-fill MESH -o OUT_MESH [--resolution N] [options]\n"
    "\n"
    "Repair the missing pixels of a depth or range image by constrained texture\n"
    "synthesis (paper 003). IN is an organised PCD (x y z [rgb]; ascii, binary or\n"
    "binary_compressed), a PFM (Middlebury disparities) or a 16-bit PNG depth\n"
    "image (--scale units per metre). Missing: 0, NaN or inf, or MASK's non-zero\n"
    "pixels. OUT is written in IN's format; known pixels keep their depths (a PCD\n"
    "keeps x y z as floats and rgb; its other fields and viewpoint are not kept).\n"
    "Missing pixels outside the capture (no known pixel on both sides along their\n"
    "row or column: a camera's invalid margin) are left missing.\n"
    "\n"
    "A mesh (PLY, OBJ, OFF, STL; triangles counter-clockwise from outside) is\n"
    "repaired through the six orthographic depth images of its bounding box: the\n"
    "pixels whose ray meets the mesh's inside through a hole are repaired, the\n"
    "voxels between the front and back depths of every axis kept, and their\n"
    "surface (marching tetrahedra) written as OUT_MESH, closed.\n"
    "\n"
    "  -o, --output OUT      the repaired image, IN's format; required, never IN\n"
    "  --variant V           plain: synthesis on the depths; haar: LL interpolated,\n"
    "                        the Haar detail bands synthesised; decompose (default):\n"
    "                        ROF structure u interpolated, texture v synthesised\n"
    "  --mask MASK           PNG of IN's size: non-zero = missing too\n"
    "  --scale S             16-bit PNG: values per metre (default 5000, TUM/Kinect)\n"
    "  --window W            synthesis window, odd pixels (default 9)\n"
    "  --sigma S             the window's Gaussian weights, pixels (default W / 6.4)\n"
    "  --search-radius R     symmetric search distance, pixels (default 32; 0: all)\n"
    "  --exhaustive          every window at full resolution (no pyramid)\n"
    "  --order O             both (default: keep the better), horizontal, vertical\n"
    "  --tileable            the image is a torus (paper 003's tileable constraint):\n"
    "                        windows see across the borders, the result repeats\n"
    "                        without seams, and holes at a border are filled\n"
    "  --levels L            haar: transform steps (default 2)\n"
    "  --membrane M          the smooth fill of haar's LL and decompose's u:\n"
    "                        harmonic (default for images) or thin-plate (default\n"
    "                        for meshes: carries the rim's slope and curvature\n"
    "                        in; can overshoot at depth edges)\n"
    "  --no-seam             leave the rims as synthesised (by\n"
    "                        default each hole's rim is blended in the gradient\n"
    "                        domain, so the fill continues the capture's slope)\n"
    "  --resolution N        mesh: voxels along the box's longest side (default 256)\n"
    "  --lambda L            decompose: ROF's lambda, depth units x pixels (default:\n"
    "                        8 x the capture's robust step between neighbours)\n"
    "  --truth T             measure against T (IN's format): RMS over the filled\n"
    "                        pixels and the slope jump at the rim; for a mesh, the\n"
    "                        complete mesh: surface distances and voxel IoU\n"
    "  --points OUT.ply      (PCD) the repaired points, coloured where IN has colour,\n"
    "                        with a 'label' property: 1 for the filled ones\n"
    "  --seed N              the near-minimum draw (default 1)\n"
    "  --backend B           auto, scalar or opencl (outputs are identical)\n"
    "  --device N            OpenCL device (see 'relief devices')\n"
    "  --max-memory SIZE     refuse images needing more host memory\n"
    "  --report R.json       pixels per stage, times, measures, backend\n"
    "  --quiet               no progress or notes on stderr\n";

typedef enum in_kind { IN_PNG, IN_PFM, IN_PCD, IN_MESH } in_kind;

/* The synthesis's progress on stderr; it never stops it. */
static int count_progress(void *ctx, size_t done, size_t total)
{
    cli_on_progress(ctx, done, total);
    return 0;
}

static int kind_of_name(const char *path, in_kind *k)
{
    const char *dot = strrchr(path, '.');
    if (!dot)
        return 0;
    if (strcasecmp(dot, ".png") == 0)
        *k = IN_PNG;
    else if (strcasecmp(dot, ".pfm") == 0)
        *k = IN_PFM;
    else if (strcasecmp(dot, ".pcd") == 0)
        *k = IN_PCD;
    else if (strcasecmp(dot, ".ply") == 0 || strcasecmp(dot, ".obj") == 0 ||
             strcasecmp(dot, ".off") == 0 || strcasecmp(dot, ".stl") == 0)
        *k = IN_MESH;
    else
        return 0;
    return 1;
}

static const char *kind_name(in_kind k)
{
    return k == IN_PNG ? "PNG" : k == IN_PFM ? "PFM" : k == IN_PCD ? "PCD" : "a mesh";
}

/* Read a depth image of any kind into *f (z NaN where missing). PNG: one
 * 16-bit grey channel, 0 missing, value / scale. */
static relief_status read_depth(const char *path, in_kind k, double scale, uint64_t limit,
                                relief_depth_frame *f, relief_error *err)
{
    memset(f, 0, sizeof *f);
    if (k != IN_PNG) {
        relief_status st = relief_depth_frame_read(path, limit ? limit / 64 : 0, f, err);
        if (st == RELIEF_OK && k == IN_PCD && f->format == RELIEF_DEPTH_PFM)
            st = relief_fail(err, RELIEF_E_FORMAT, "%s is a PFM named .pcd", path);
        if (st == RELIEF_OK && k == IN_PFM && f->format != RELIEF_DEPTH_PFM)
            st = relief_fail(err, RELIEF_E_FORMAT, "%s is a PCD named .pfm", path);
        if (st != RELIEF_OK)
            relief_depth_frame_free(f);
        return st;
    } else {
        relief_image_limit lim = {limit, 16.0, "repairing it"};
        relief_raster r = {0, 0, 0, 0, NULL};
        relief_status st = relief_raster_read(path, &lim, &r, err);
        size_t n;
        if (st != RELIEF_OK)
            return st;
        if (r.channels != 1 || r.bit_depth != 16) {
            relief_raster_free(&r);
            return relief_fail(err, RELIEF_E_FORMAT, "%s: a PNG depth image has one 16-bit "
                               "grey channel; this one has %d channel(s) of %d bits", path,
                               r.channels, r.bit_depth);
        }
        n = (size_t)r.width * r.height;
        f->width = r.width;
        f->height = r.height;
        f->format = RELIEF_DEPTH_PFM;
        f->z = malloc(n * sizeof *f->z);
        if (!f->z) {
            relief_raster_free(&r);
            return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the depths");
        }
        for (size_t i = 0; i < n; ++i)
            f->z[i] = r.v[i] > 0.0f ? (float)(r.v[i] / scale) : NAN;
        relief_raster_free(&r);
        return RELIEF_OK;
    }
}

static relief_status write_png_depth(const char *path, const relief_depth_frame *f,
                                     double scale, relief_error *err)
{
    relief_raster r = {0, 0, 0, 0, NULL};
    size_t n = (size_t)f->width * f->height;
    relief_status st = relief_raster_create(f->width, f->height, 1, 16, &r, err);
    if (st != RELIEF_OK)
        return st;
    for (size_t i = 0; i < n; ++i) {
        double v = isfinite(f->z[i]) ? floor(f->z[i] * scale + 0.5) : 0.0;
        /* A filled depth rounds to at least 1: 0 would read as missing. */
        r.v[i] = (float)(v < 1.0 && isfinite(f->z[i]) ? 1.0 : v > 65535.0 ? 65535.0 : v);
    }
    st = relief_raster_write(path, &r, err);
    relief_raster_free(&r);
    return st;
}

/* The camera of an organised cloud, x / z = a u + b and y / z = c v + d
 * (a pinhole; u, v pixels), fitted to the known points by least squares;
 * 0 when there are too few distinct columns or rows. */
static int fit_camera(const relief_depth_frame *f, double cam[4])
{
    double su = 0, suu = 0, sx = 0, sux = 0, sv = 0, svv = 0, sy = 0, svy = 0;
    size_t m = 0;
    for (int v = 0; v < f->height; ++v)
        for (int u = 0; u < f->width; ++u) {
            const float *q = f->xyz + 3 * ((size_t)v * f->width + u);
            double x, y;
            if (!isfinite(q[2]) || q[2] == 0.0f)
                continue;
            x = q[0] / q[2];
            y = q[1] / q[2];
            su += u, suu += (double)u * u, sx += x, sux += u * x;
            sv += v, svv += (double)v * v, sy += y, svy += v * y;
            ++m;
        }
    if (m < 3)
        return 0;
    {
        double du = m * suu - su * su, dv = m * svv - sv * sv;
        if (!(du > 0) || !(dv > 0))
            return 0;
        cam[0] = (m * sux - su * sx) / du;
        cam[1] = (sx - cam[0] * su) / m;
        cam[2] = (m * svy - sv * sy) / dv;
        cam[3] = (sy - cam[2] * sv) / m;
    }
    return 1;
}

typedef struct points_ctx {
    const relief_depth_frame *f;
    const uint8_t *filled;
} points_ctx;

static int write_points(FILE *fp, void *ctx)
{
    const points_ctx *c = ctx;
    const relief_depth_frame *f = c->f;
    size_t n = (size_t)f->width * f->height, m = 0;
    for (size_t i = 0; i < n; ++i)
        m += isfinite(f->xyz[3 * i + 2]);
    fprintf(fp, "ply\nformat binary_little_endian 1.0\ncomment relief depth-fill\n"
            "element vertex %zu\nproperty float x\nproperty float y\nproperty float z\n%s"
            "property uchar label\nend_header\n", m,
            f->rgb ? "property uchar red\nproperty uchar green\nproperty uchar blue\n" : "");
    for (size_t i = 0; i < n; ++i) {
        uint8_t rec[16];
        size_t k = 12;
        if (!isfinite(f->xyz[3 * i + 2]))
            continue;
        memcpy(rec, f->xyz + 3 * i, 12); /* little-endian hosts only (as the PLY writer) */
        if (f->rgb) {
            memcpy(rec + 12, f->rgb + 3 * i, 3);
            k = 15;
        }
        rec[k++] = c->filled[i];
        if (fwrite(rec, 1, k, fp) != k)
            return 1;
    }
    return ferror(fp);
}

typedef struct report_ctx {
    const char *in, *out, *mask, *truth, *variant;
    const relief_depth_frame *f;
    const relief_depth_repair_params *p;
    const relief_depth_repair_report *r;
    const relief_depth_measures *m;
    const relief_patch_scorer *scorer;
    const char *note;
    size_t missing_in, missing_mask;
    double seconds_total;
} report_ctx;

static const char *order_name(relief_pixsyn_order o)
{
    return o == RELIEF_ORDER_VERTICAL ? "vertical" : o == RELIEF_ORDER_HORIZONTAL ? "horizontal"
                                                                                  : "both";
}

static int write_report(FILE *fp, void *ctx)
{
    const report_ctx *c = ctx;
    const relief_depth_repair_report *r = c->r;
    relief_json j;
    rj_init(&j, fp);
    rj_begin_object(&j, NULL);
    rj_string(&j, "command", "depth-fill");
    rj_string(&j, "input", c->in);
    rj_string(&j, "output", c->out);
    if (c->mask)
        rj_string(&j, "mask", c->mask);
    else
        rj_null(&j, "mask");
    rj_begin_object(&j, "image");
    rj_int(&j, "width", c->f->width);
    rj_int(&j, "height", c->f->height);
    rj_end_object(&j);
    rj_begin_object(&j, "parameters");
    rj_string(&j, "variant", c->variant);
    rj_int(&j, "window", c->p->synth.window);
    rj_number(&j, "sigma", c->p->synth.sigma > 0 ? c->p->synth.sigma
                                                 : c->p->synth.window / 6.4);
    rj_number(&j, "epsilon", c->p->synth.epsilon);
    rj_int(&j, "search_radius", c->p->synth.search_radius);
    rj_bool(&j, "exhaustive", c->p->synth.exhaustive);
    rj_string(&j, "order", order_name(c->p->synth.order));
    rj_bool(&j, "tileable", c->p->synth.tileable);
    rj_int(&j, "levels", c->p->levels);
    rj_number(&j, "lambda", r->lambda);
    rj_string(&j, "membrane", c->p->thin_plate ? "thin-plate" : "harmonic");
    rj_bool(&j, "seam", c->p->seam);
    rj_int(&j, "seed", c->p->synth.seed);
    rj_end_object(&j);
    rj_begin_object(&j, "pixels");
    rj_int(&j, "missing", (long long)r->missing);
    rj_int(&j, "filled", (long long)r->filled);
    rj_int(&j, "outside_left_missing", (long long)r->outside);
    rj_int(&j, "missing_in_input", (long long)c->missing_in);
    rj_int(&j, "missing_by_mask", (long long)c->missing_mask);
    rj_int(&j, "by_synthesis", (long long)r->by_synthesis);
    rj_int(&j, "by_fallback", (long long)r->by_fallback);
    rj_int(&j, "by_membrane", (long long)r->by_membrane);
    rj_int(&j, "unreached", (long long)r->unreached);
    rj_end_object(&j);
    rj_begin_object(&j, "synthesis");
    rj_string(&j, "order_kept", order_name(r->kept));
    rj_number(&j, "energy_horizontal", r->energy[0]);
    rj_number(&j, "energy_vertical", r->energy[1]);
    rj_int(&j, "candidates_scored", (long long)r->candidates);
    rj_int(&j, "membrane_iterations", r->membrane_iterations);
    rj_int(&j, "seam_edges", (long long)r->seam_edges);
    rj_end_object(&j);
    if (c->m) {
        rj_begin_object(&j, "measures");
        if (c->truth)
            rj_string(&j, "truth", c->truth);
        rj_int(&j, "compared", (long long)c->m->compared);
        rj_number(&j, "rms", c->m->rms);
        rj_int(&j, "rim_triples", (long long)c->m->rim_pairs);
        rj_number(&j, "rim_jump", c->m->rim_jump);
        rj_number(&j, "capture_jump", c->m->capture_jump);
        rj_number(&j, "slope_jump", c->m->rim_jump / c->m->capture_jump);
        rj_number(&j, "truth_rim_jump", c->m->truth_jump);
        rj_end_object(&j);
    }
    rj_begin_object(&j, "seconds");
    rj_number(&j, "transform", r->seconds_transform);
    rj_number(&j, "synthesis", r->seconds_synthesis);
    rj_number(&j, "scoring", r->seconds_score);
    rj_number(&j, "total", c->seconds_total);
    rj_end_object(&j);
    rj_string(&j, "backend", relief_backend_name(c->scorer->backend));
    rj_string(&j, "device", c->scorer->device);
    rj_string(&j, "backend_note", c->note);
    rj_end_object(&j);
    fputc('\n', fp);
    return ferror(fp);
}

typedef struct mesh_report_ctx {
    const char *in, *out, *truth, *variant;
    const relief_mesh_fill_params *p;
    const relief_mesh_fill_report *r;
    const relief_mesh_measures *m;
    size_t vertices, triangles;
    const relief_patch_scorer *scorer;
    const char *note;
    double seconds_total;
} mesh_report_ctx;

static int write_mesh_report(FILE *fp, void *ctx)
{
    const mesh_report_ctx *c = ctx;
    const relief_mesh_fill_report *r = c->r;
    static const char *names[6] = {"x_front", "x_back", "y_front", "y_back", "z_front", "z_back"};
    relief_json j;
    rj_init(&j, fp);
    rj_begin_object(&j, NULL);
    rj_string(&j, "command", "depth-fill");
    rj_string(&j, "input", c->in);
    rj_string(&j, "output", c->out);
    rj_begin_object(&j, "parameters");
    rj_string(&j, "variant", c->variant);
    rj_int(&j, "resolution", c->p->resolution);
    rj_int(&j, "window", c->p->depth.synth.window);
    rj_int(&j, "search_radius", c->p->depth.synth.search_radius);
    rj_int(&j, "seed", c->p->depth.synth.seed);
    rj_end_object(&j);
    rj_begin_object(&j, "grid");
    rj_number(&j, "voxel", r->grid.h);
    rj_int(&j, "nx", r->grid.n[0]);
    rj_int(&j, "ny", r->grid.n[1]);
    rj_int(&j, "nz", r->grid.n[2]);
    rj_int(&j, "inside_voxels", (long long)r->inside_voxels);
    rj_end_object(&j);
    rj_begin_object(&j, "images");
    for (int k = 0; k < 6; ++k) {
        rj_begin_object(&j, names[k]);
        rj_int(&j, "hole_pixels", (long long)r->hole_pixels[k]);
        rj_int(&j, "filled", (long long)r->filled[k]);
        rj_end_object(&j);
    }
    rj_end_object(&j);
    rj_begin_object(&j, "pixels");
    rj_int(&j, "surface", (long long)r->surface_pixels);
    rj_int(&j, "by_synthesis", (long long)r->by_synthesis);
    rj_int(&j, "by_fallback", (long long)r->by_fallback);
    rj_int(&j, "by_membrane", (long long)r->by_membrane);
    rj_int(&j, "unreached", (long long)r->unreached);
    rj_end_object(&j);
    rj_begin_object(&j, "output_mesh");
    rj_int(&j, "vertices", (long long)c->vertices);
    rj_int(&j, "triangles", (long long)c->triangles);
    rj_end_object(&j);
    if (c->m) {
        rj_begin_object(&j, "measures");
        rj_string(&j, "truth", c->truth);
        rj_number(&j, "mean_distance", c->m->mean);
        rj_number(&j, "hausdorff", c->m->hausdorff);
        rj_number(&j, "hausdorff_voxels", c->m->hausdorff / r->grid.h);
        rj_number(&j, "voxel_iou", c->m->iou);
        rj_end_object(&j);
    }
    rj_begin_object(&j, "seconds");
    rj_number(&j, "zbuffers", r->seconds_zbuffers);
    rj_number(&j, "repair", r->seconds_repair);
    rj_number(&j, "surface", r->seconds_surface);
    rj_number(&j, "total", c->seconds_total);
    rj_end_object(&j);
    rj_string(&j, "backend", relief_backend_name(c->scorer->backend));
    rj_string(&j, "device", c->scorer->device);
    rj_string(&j, "backend_note", c->note);
    rj_end_object(&j);
    fputc('\n', fp);
    return ferror(fp);
}

/* A mesh through its six depth images. */
static int mesh_mode(const char *in, const char *out, const char *truth_path,
                     const char *report, const char *variant,
                     const relief_mesh_fill_params *p, relief_backend backend, int device,
                     uint64_t limit, int quiet, double t_start)
{
    relief_error err = {RELIEF_OK, ""};
    relief_mesh *m = NULL, *t = NULL, *o = NULL;
    relief_patch_scorer *scorer = NULL;
    relief_mesh_fill_report rep;
    relief_mesh_measures meas;
    relief_grid g;
    char note[1024] = "";
    relief_status st = relief_mesh_read(in, &m, NULL, &err);
    sigset_t held;
    int rc = 0;

    if (st == RELIEF_OK && truth_path)
        st = relief_mesh_read(truth_path, &t, NULL, &err);
    if (st == RELIEF_OK && relief_mesh_triangle_count(m) == 0)
        st = relief_fail(&err, RELIEF_E_RANGE, "%s has no triangles: a point set has no "
                         "depth images (a surface is needed)", in);
    if (st == RELIEF_OK)
        st = relief_grid_of_mesh(m, p->resolution, &g, &err);
    if (st == RELIEF_OK && limit && relief_volume_estimate(&g) * (truth_path ? 2u : 1u) > limit)
        st = relief_fail(&err, RELIEF_E_NOMEM, "--resolution %d: a %d x %d x %d voxel grid needs "
                         "about %.0f MiB, over the limit of %.0f MiB (--max-memory); give a "
                         "lower --resolution", p->resolution, g.n[0], g.n[1], g.n[2],
                         relief_volume_estimate(&g) * (truth_path ? 2.0 : 1.0) / 1048576.0,
                         limit / 1048576.0);
    if (st == RELIEF_OK)
        st = relief_patch_scorer_create(backend, device, &scorer, note, sizeof note, &err);
    if (st != RELIEF_OK)
        goto done;
    if (!quiet && note[0])
        fprintf(stderr, "relief depth-fill: %s\n", note);
    st = relief_mesh_depth_fill(m, p, scorer, &o, &rep, &err);
    if (st == RELIEF_OK && t)
        st = relief_mesh_measure(o, t, &rep.grid, &meas, &err);
    if (st != RELIEF_OK)
        goto done;
    cli_hold_signals(&held);
    st = relief_mesh_write(o, out, NULL, &err);
    if (st == RELIEF_OK && report) {
        mesh_report_ctx r = {in, out, truth_path, variant, p, &rep, t ? &meas : NULL,
                             relief_mesh_vertex_count(o), relief_mesh_triangle_count(o),
                             scorer, note, relief_seconds() - t_start};
        st = relief_atomic_write_text(report, write_mesh_report, &r, &err);
        if (st != RELIEF_OK)
            remove(out);
    }
    cli_release_signals(&held);
    if (st == RELIEF_OK && !quiet) {
        size_t holes = 0, filled = 0;
        for (int k = 0; k < 6; ++k) {
            holes += rep.hole_pixels[k];
            filled += rep.filled[k];
        }
        fprintf(stderr, "relief depth-fill: %s: %d x %d x %d voxels of %.4g; six depth images, "
                "%zu pixels seen through holes, %zu repaired (variant %s); %zu inside voxels; "
                "%zu vertices, %zu triangles; %.2f s\n", in, rep.grid.n[0], rep.grid.n[1],
                rep.grid.n[2], rep.grid.h, holes, filled, variant, rep.inside_voxels,
                relief_mesh_vertex_count(o), relief_mesh_triangle_count(o),
                relief_seconds() - t_start);
        if (t)
            fprintf(stderr, "relief depth-fill: against %s: mean distance %.4g, Hausdorff %.4g "
                    "(%.2f voxels), voxel IoU %.4f\n", truth_path, meas.mean, meas.hausdorff,
                    meas.hausdorff / rep.grid.h, meas.iou);
    }
done:
    if (st != RELIEF_OK)
        rc = cli_fail("depth-fill", &err);
    relief_patch_scorer_destroy(scorer);
    relief_mesh_destroy(m);
    relief_mesh_destroy(t);
    relief_mesh_destroy(o);
    return rc;
}

int cli_cmd_depth_fill(int argc, char **argv, int parse_only)
{
    enum { OPT_MASK = 1000, OPT_VARIANT, OPT_SCALE, OPT_SIGMA, OPT_SEARCH_RADIUS,
           OPT_EXHAUSTIVE, OPT_ORDER, OPT_LAMBDA, OPT_POINTS, OPT_DLEVELS, OPT_RESOLUTION,
           OPT_MEMBRANE, OPT_TILEABLE, OPT_NO_SEAM };
    static const struct option opts[] = {
        {"output", required_argument, 0, 'o'},
        {"variant", required_argument, 0, OPT_VARIANT},
        {"mask", required_argument, 0, OPT_MASK},
        {"scale", required_argument, 0, OPT_SCALE},
        {"window", required_argument, 0, OPT_WINDOW},
        {"sigma", required_argument, 0, OPT_SIGMA},
        {"search-radius", required_argument, 0, OPT_SEARCH_RADIUS},
        {"exhaustive", no_argument, 0, OPT_EXHAUSTIVE},
        {"order", required_argument, 0, OPT_ORDER},
        {"levels", required_argument, 0, OPT_DLEVELS},
        {"resolution", required_argument, 0, OPT_RESOLUTION},
        {"membrane", required_argument, 0, OPT_MEMBRANE},
        {"tileable", no_argument, 0, OPT_TILEABLE},
        {"no-seam", no_argument, 0, OPT_NO_SEAM},
        {"lambda", required_argument, 0, OPT_LAMBDA},
        {"truth", required_argument, 0, OPT_TRUTH},
        {"points", required_argument, 0, OPT_POINTS},
        {"seed", required_argument, 0, OPT_SEED},
        {"backend", required_argument, 0, OPT_BACKEND},
        {"device", required_argument, 0, OPT_DEVICE},
        {"max-memory", required_argument, 0, OPT_MAX_MEMORY},
        {"report", required_argument, 0, OPT_REPORT},
        {"quiet", no_argument, 0, OPT_QUIET},
        {"help", no_argument, 0, 'h'},
        {0, 0, 0, 0}};
    relief_depth_repair_params p = relief_depth_repair_params_default();
    int membrane = -1; /* --membrane: 0 harmonic, 1 thin plate, -1 the mode's default */
    relief_depth_repair_report rep;
    relief_depth_measures meas;
    relief_error err = {RELIEF_OK, ""};
    relief_depth_frame f, truth;
    relief_raster mask = {0, 0, 0, 0, NULL};
    relief_patch_scorer *scorer = NULL;
    relief_backend backend = RELIEF_BACKEND_AUTO;
    relief_params mp = relief_params_default();
    const char *out = NULL, *in, *mask_path = NULL, *report = NULL, *truth_path = NULL,
               *points = NULL, *variant = "decompose";
    char note[1024] = "";
    uint8_t *missing = NULL;
    int64_t *source = NULL;
    size_t missing_in = 0, missing_mask = 0, n = 0;
    int c, quiet = 0, device = -1, rc = 0, have_truth = 0, resolution = 256;
    long v;
    double d, scale = 5000.0, t_start = relief_seconds();
    uint64_t limit;
    in_kind kin, kout;
    relief_status st = RELIEF_OK;
    cli_count_progress pr = {"depth-fill", "synthesis", 0, 0.0, 0.0};
    sigset_t held;

    memset(&f, 0, sizeof f);
    memset(&truth, 0, sizeof truth);
    optind = 0;
    while ((c = getopt_long(argc, argv, "o:h", opts, NULL)) != -1) {
        switch (c) {
        case 'o': out = optarg; break;
        case OPT_MASK: mask_path = optarg; break;
        case OPT_VARIANT:
            if (strcmp(optarg, "plain") == 0)
                p.variant = RELIEF_DEPTH_PLAIN;
            else if (strcmp(optarg, "haar") == 0)
                p.variant = RELIEF_DEPTH_HAAR;
            else if (strcmp(optarg, "decompose") == 0)
                p.variant = RELIEF_DEPTH_DECOMPOSE;
            else
                return cli_usage_error("depth-fill", "--variant: '%s' is not plain, haar or "
                                       "decompose", optarg);
            variant = optarg;
            break;
        case OPT_SCALE:
            if (!cli_parse_real("depth-fill", "--scale", optarg, &d))
                return EXIT_USAGE;
            if (!(d > 0) || d > 1e9)
                return cli_usage_error("depth-fill", "--scale: '%s' is out of range: expected "
                                       "a value > 0 (PNG units per metre)", optarg);
            scale = d;
            break;
        case OPT_WINDOW:
            if (!cli_parse_int_range("depth-fill", "--window", optarg, 3, 1025, &v))
                return EXIT_USAGE;
            if (v % 2 == 0)
                return cli_usage_error("depth-fill", "--window: '%s' is even: the window is "
                                       "centred on a pixel, give an odd number", optarg);
            p.synth.window = (int)v;
            break;
        case OPT_SIGMA:
            if (!cli_parse_real("depth-fill", "--sigma", optarg, &d))
                return EXIT_USAGE;
            if (!(d >= 0.5) || d > 1e6)
                return cli_usage_error("depth-fill", "--sigma: '%s' is out of range: expected "
                                       "0.5 pixels or more", optarg);
            p.synth.sigma = d;
            break;
        case OPT_SEARCH_RADIUS:
            if (!cli_parse_int_range("depth-fill", "--search-radius", optarg, 0, 1000000, &v))
                return EXIT_USAGE;
            p.synth.search_radius = (int)v;
            break;
        case OPT_EXHAUSTIVE: p.synth.exhaustive = 1; break;
        case OPT_ORDER:
            if (strcmp(optarg, "both") == 0)
                p.synth.order = RELIEF_ORDER_BOTH;
            else if (strcmp(optarg, "horizontal") == 0)
                p.synth.order = RELIEF_ORDER_HORIZONTAL;
            else if (strcmp(optarg, "vertical") == 0)
                p.synth.order = RELIEF_ORDER_VERTICAL;
            else
                return cli_usage_error("depth-fill", "--order: '%s' is not both, horizontal "
                                       "or vertical", optarg);
            break;
        case OPT_DLEVELS:
            if (!cli_parse_int_range("depth-fill", "--levels", optarg, 1, 6, &v))
                return EXIT_USAGE;
            p.levels = (int)v;
            break;
        case OPT_TILEABLE: p.synth.tileable = 1; break;
        case OPT_NO_SEAM: p.seam = 0; break;
        case OPT_MEMBRANE:
            if (strcmp(optarg, "thin-plate") == 0)
                membrane = 1;
            else if (strcmp(optarg, "harmonic") == 0)
                membrane = 0;
            else
                return cli_usage_error("depth-fill", "--membrane: '%s' is not thin-plate or "
                                       "harmonic", optarg);
            break;
        case OPT_RESOLUTION:
            if (!cli_parse_int_range("depth-fill", "--resolution", optarg, 8, 1024, &v))
                return EXIT_USAGE;
            resolution = (int)v;
            break;
        case OPT_LAMBDA:
            if (!cli_parse_real("depth-fill", "--lambda", optarg, &d))
                return EXIT_USAGE;
            if (!(d > 0) || d > 1e12)
                return cli_usage_error("depth-fill", "--lambda: '%s' is out of range: expected "
                                       "a value > 0", optarg);
            p.lambda = d;
            break;
        case OPT_TRUTH: truth_path = optarg; break;
        case OPT_POINTS: points = optarg; break;
        case OPT_SEED:
            if (!cli_parse_int_range("depth-fill", "--seed", optarg, 0, 4294967295L, &v))
                return EXIT_USAGE;
            p.synth.seed = (uint32_t)v;
            break;
        case OPT_BACKEND:
            if (!cli_parse_backend("depth-fill", optarg, 0, &backend))
                return EXIT_USAGE;
            break;
        case OPT_DEVICE:
            if (!cli_parse_int_range("depth-fill", "--device", optarg, 0, 1023, &v))
                return EXIT_USAGE;
            device = (int)v;
            break;
        case OPT_MAX_MEMORY:
            if (relief_parse_size(optarg, &mp.max_memory, &err) != RELIEF_OK)
                return cli_usage_error("depth-fill", "--max-memory: %s", err.message);
            break;
        case OPT_REPORT: report = optarg; break;
        case OPT_QUIET: quiet = 1; break;
        case 'h': fputs(depth_fill_help, stdout); return 0;
        default: fprintf(stderr, "Try 'relief depth-fill --help'.\n"); return EXIT_USAGE;
        }
    }
    if (optind >= argc)
        return cli_usage_error("depth-fill", "%smissing input IN", "");
    if (argc - optind > 1)
        return cli_usage_error("depth-fill", "unexpected argument '%s'", argv[optind + 1]);
    in = argv[optind];
    if (!out)
        return cli_usage_error("depth-fill", "%smissing -o OUT", "");
    if (!kind_of_name(in, &kin))
        return cli_usage_error("depth-fill", "IN: '%s' does not end in .pcd, .pfm, .png or a "
                               "mesh's .ply, .obj, .off, .stl", in);
    if (!kind_of_name(out, &kout) || kout != kin)
        return cli_usage_error("depth-fill", "-o: '%s': OUT is written in IN's format: give "
                               "it IN's extension (a mesh: .ply, .obj, .off or .stl)", out);
    if (kin == IN_MESH && (mask_path || points))
        return cli_usage_error("depth-fill", "%s--mask and --points are for depth images, not "
                               "meshes", "");
    if (points && kin != IN_PCD)
        return cli_usage_error("depth-fill", "--points: '%s': points need an organised PCD "
                               "input (a depth image has no camera)", points);
    {
        const char *files[] = {in, mask_path, truth_path};
        const char *outs[] = {out, report, points};
        for (int a = 0; a < 3; ++a)
            for (int b = 0; b < 3; ++b)
                if (files[a] && outs[b] && cli_same_file(files[a], outs[b]))
                    return cli_usage_error("depth-fill", "'%s' is an input; relief never "
                                           "overwrites its input", outs[b]);
        if ((report && cli_same_file(report, out)) || (points && cli_same_file(points, out)) ||
            (report && points && cli_same_file(report, points)))
            return cli_usage_error("depth-fill", "%s-o, --report and --points must name "
                                   "different files", "");
    }
    if (parse_only)
        return 0;

    limit = relief_memory_limit(&mp);
    if (membrane >= 0)
        p.thin_plate = membrane;
    if (kin == IN_MESH) {
        relief_mesh_fill_params mfp = relief_mesh_fill_params_default();
        in_kind kt;
        if (truth_path && (!kind_of_name(truth_path, &kt) || kt != IN_MESH))
            return cli_usage_error("depth-fill", "--truth '%s': a mesh's truth is the complete "
                                   "mesh (.ply, .obj, .off or .stl)", truth_path);
        mfp.resolution = resolution;
        if (membrane < 0)
            p.thin_plate = mfp.depth.thin_plate;
        mfp.depth = p;
        mfp.depth.synth.progress = NULL;
        return mesh_mode(in, out, truth_path, report, variant, &mfp, backend, device, limit,
                         quiet, t_start);
    }
    st = read_depth(in, kin, scale, limit, &f, &err);
    if (st != RELIEF_OK)
        goto done;
    n = (size_t)f.width * f.height;
    if (limit && relief_depth_repair_estimate(f.width, f.height) > limit) {
        st = relief_fail(&err, RELIEF_E_NOMEM, "%s: repairing a %d x %d image needs about "
                         "%.0f MiB, over the limit of %.0f MiB (--max-memory)", in, f.width,
                         f.height, relief_depth_repair_estimate(f.width, f.height) / 1048576.0,
                         limit / 1048576.0);
        goto done;
    }
    if (mask_path) {
        relief_image_limit ml = {limit, 1.0, "the mask"};
        st = relief_raster_read(mask_path, &ml, &mask, &err);
        if (st == RELIEF_OK && (mask.width != f.width || mask.height != f.height))
            st = relief_fail(&err, RELIEF_E_USAGE, "--mask %s is %d x %d pixels, %s is %d x "
                             "%d: they must be the same size", mask_path, mask.width,
                             mask.height, in, f.width, f.height);
        if (st != RELIEF_OK)
            goto done;
    }
    if (truth_path) {
        in_kind kt;
        if (!kind_of_name(truth_path, &kt) || kt != kin) {
            st = relief_fail(&err, RELIEF_E_USAGE, "--truth %s: expected IN's format (%s)",
                             truth_path, kind_name(kin));
            goto done;
        }
        st = read_depth(truth_path, kt, scale, limit, &truth, &err);
        if (st == RELIEF_OK && (truth.width != f.width || truth.height != f.height))
            st = relief_fail(&err, RELIEF_E_USAGE, "--truth %s is %d x %d pixels, %s is %d x "
                             "%d: they must be the same size", truth_path, truth.width,
                             truth.height, in, f.width, f.height);
        if (st != RELIEF_OK)
            goto done;
        have_truth = 1;
    }
    missing = malloc(n);
    source = malloc(n * sizeof *source);
    if (!missing || !source) {
        st = relief_fail(&err, RELIEF_E_NOMEM, "cannot allocate the missing mask");
        goto done;
    }
    for (size_t i = 0; i < n; ++i) {
        int bad = !isfinite(f.z[i]) || f.z[i] == 0.0f, masked = 0;
        if (mask_path) {
            int colours = relief_raster_has_alpha(&mask) ? mask.channels - 1 : mask.channels;
            for (int k = 0; k < colours; ++k)
                masked |= mask.v[i * mask.channels + k] != 0.0f;
        }
        missing[i] = (uint8_t)(bad || masked);
        missing_in += (size_t)bad;
        missing_mask += (size_t)(masked && !bad);
    }
    if (missing_in + missing_mask == n)
        st = relief_fail(&err, RELIEF_E_RANGE, "%s: every pixel is missing: there is nothing "
                         "to repair it from", in);
    if (st == RELIEF_OK)
        st = relief_depth_repair_params_validate(&p, f.width, f.height, &err);
    if (st == RELIEF_OK)
        st = relief_patch_scorer_create(backend, device, &scorer, note, sizeof note, &err);
    if (st != RELIEF_OK)
        goto done;
    if (!quiet && note[0])
        fprintf(stderr, "relief depth-fill: %s\n", note);
    pr.print = !quiet && isatty(2);
    pr.start = relief_seconds();
    p.synth.progress = count_progress;
    p.synth.progress_ctx = &pr;
    if (missing_in + missing_mask == 0 && !quiet)
        fprintf(stderr, "relief depth-fill: %s: no missing pixels: writing it unchanged\n", in);
    st = relief_depth_repair(f.z, missing, f.width, f.height, &p, scorer, source, &rep, &err);
    if (st != RELIEF_OK)
        goto done;
    relief_depth_measure(f.z, have_truth ? truth.z : NULL, missing, f.width, f.height, &meas);

    /* An organised cloud's filled pixels get points through its camera,
     * and the colour of the pixel their texture came from. */
    if (kin == IN_PCD) {
        double cam[4];
        int ok = fit_camera(&f, cam);
        for (size_t i = 0; i < n; ++i) {
            int u = (int)(i % (size_t)f.width), vv = (int)(i / (size_t)f.width);
            float *q = f.xyz + 3 * i;
            if (!missing[i])
                continue;
            q[0] = ok ? (float)((cam[0] * u + cam[1]) * f.z[i]) : NAN;
            q[1] = ok ? (float)((cam[2] * vv + cam[3]) * f.z[i]) : NAN;
            q[2] = ok ? f.z[i] : NAN;
            if (f.rgb) {
                if (source[i] >= 0)
                    memcpy(f.rgb + 3 * i, f.rgb + 3 * (size_t)source[i], 3);
                else
                    memset(f.rgb + 3 * i, 0, 3);
            }
        }
        if (!ok && !quiet)
            fprintf(stderr, "relief depth-fill: warning: %s: no camera could be fitted to its "
                    "points: the filled pixels' points are NaN\n", in);
    }
    cli_hold_signals(&held);
    if (kin == IN_PNG)
        st = write_png_depth(out, &f, scale, &err);
    else
        st = relief_depth_frame_write(out, &f, f.format, &err);
    if (st == RELIEF_OK && points) {
        points_ctx pc = {&f, missing};
        st = relief_atomic_write_text(points, write_points, &pc, &err);
        if (st != RELIEF_OK)
            remove(out);
    }
    if (st == RELIEF_OK && report) {
        report_ctx r = {in, out, mask_path, truth_path, variant, &f, &p, &rep, &meas, scorer,
                        note, missing_in, missing_mask, relief_seconds() - t_start};
        st = relief_atomic_write_text(report, write_report, &r, &err);
        if (st != RELIEF_OK) {
            remove(out); /* all outputs or none */
            if (points)
                remove(points);
        }
    }
    cli_release_signals(&held);
    if (st == RELIEF_OK && !quiet && rep.membrane_iterations >= p.membrane_iterations)
        fprintf(stderr, "relief depth-fill: warning: the membrane stopped at its %d-iteration "
                "cap before converging\n", p.membrane_iterations);
    if (st == RELIEF_OK && !quiet && rep.unreached)
        fprintf(stderr, "relief depth-fill: warning: %zu coefficients joined to no known one "
                "kept zero detail\n", rep.unreached);
    if (st == RELIEF_OK && !quiet && rep.missing) {
        fprintf(stderr, "relief depth-fill: %s: %zu of %zu pixels missing (%.1f %%): %zu "
                "filled, %zu outside the capture left missing; variant %s: %zu synthesised "
                "(%s order), %zu by the membrane, %zu fallbacks; %.2f s on %s\n", in,
                rep.missing, n, 100.0 * rep.missing / n, rep.filled, rep.outside, variant,
                rep.by_synthesis, order_name(rep.kept), rep.by_membrane, rep.by_fallback,
                relief_seconds() - t_start, scorer->device);
        if (have_truth)
            fprintf(stderr, "relief depth-fill: against %s: RMS %.6g over %zu pixels; slope "
                    "jump at the rim %.3g (fill %.4g, the truth's own %.4g, the capture's "
                    "second difference %.4g)\n", truth_path, meas.rms, meas.compared,
                    meas.rim_jump / meas.capture_jump, meas.rim_jump, meas.truth_jump,
                    meas.capture_jump);
    }
done:
    if (st != RELIEF_OK)
        rc = cli_fail("depth-fill", &err);
    relief_patch_scorer_destroy(scorer);
    relief_depth_frame_free(&f);
    relief_depth_frame_free(&truth);
    relief_raster_free(&mask);
    free(missing);
    free(source);
    return rc;
}
