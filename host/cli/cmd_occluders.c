/* relief occluders and relief remove-occluders: an RGB-D frame's
 * foreground objects found from its depth, and the surface behind them
 * (paper 004, chapter 2; relief/occluders.h): the options, the frame (an
 * organised PCD with colour, or a colour image with its depth image), one
 * call, the outputs (all or none) and the summary. */
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
#include "base/numtext.h"
#include "cli/options.h"
#include "depth/depth_io.h"
#include "image/image_io.h"
#include "depth/frame.h"
#include "cli/camera_files.h"

enum { OC_DEPTH = OPT_COMMAND, OC_SCALE, OC_OVERLAY, OC_BG_MESH, OC_SAVE_MASK, OC_POINTS,
       OC_DEPTH_OUT, OC_COLOUR_OUT, OC_FILL_METHOD, OC_FILL_WINDOW, OC_DEPTH_VARIANT, OC_VIEWS, OC_POSES,
       OC_DEPTH_FORMAT, OC_INTRINSICS, OC_VIEW_INTRINSICS, OC_FRAME_INDEX, OC_VIEW_INDEX };

static const char *const frame_help =
    "IN is an organised PCD with colour (x y z rgb: a depth camera's frame), or a colour "
    "image (PNG, JPEG, or binary PPM / PGM) with --depth, its registered 16-bit depth PNG or "
    "PGM (--scale values per metre, default 5000; --depth-format for NYU's and SUN RGB-D's "
    "encodings; --intrinsics, numbers or Open3D's camera JSON, default a Kinect's scaled to "
    "the width).";

/* The options both commands take: the frame, the background, the views. */
#define FIND_OWN                                                                          \
    {"depth", OC_DEPTH, "DEPTH.png", "IN is a colour image: its registered 16-bit depth "   \
     "(PNG or PGM)"},                                                                        \
    {"scale", OC_SCALE, "S", "DEPTH.png's values per metre (default 5000, TUM and Kinect; " \
     "sun: 1000)"},                                                                          \
    {"depth-format", OC_DEPTH_FORMAT, "F", "how --depth's samples are depths: auto "        \
     "(default: a PNG or PGM at --scale, by its first bytes), png, pgm (big-endian, as "    \
     "Netpbm says), nyu (NYU Depth v2's raw Kinect disparities, a PGM stored "              \
     "little-endian) or sun (SUN RGB-D's PNG, bits rotated, millimetres)"},                 \
    {"background-mesh", OC_BG_MESH, "MESH", "the background is MESH (PLY, OBJ, OFF, STL; "  \
     "the frame's camera coordinates), not planes found in the depth"},                    \
    {"overlay", OC_OVERLAY, "O.png", "the colour with the occluders tinted red"},          \
    {"intrinsics", OC_INTRINSICS, "FX,FY,CX,CY|CAMERA.json", "a depth image's pinhole "    \
     "camera, pixels, or Open3D's camera JSON (width, height, intrinsic_matrix column by "  \
     "column) of IN's size (default: a PCD's camera fitted to its points; for a depth "    \
     "image fx = fy = 525 x width / 640 and the centre)"},                                  \
    {"views", OC_VIEWS, "V1,V2", "registered neighbouring views (PNG, JPEG, or PCD with "   \
     "colour; through IN's camera, or --view-intrinsics): paper 004's second cue, eq. 2.1"}, \
    {"poses", OC_POSES, "P.txt", "the views' poses: one line each of R and t as 12 "       \
     "numbers, row by row (x_view = R x + t, x in IN's camera coordinates; '#' starts a "  \
     "comment), or Open3D's trajectory log (camera-to-world 4 x 4 per entry; each view's " \
     "pose inverse(T_view) T_frame)"},                                                      \
    {"frame-index", OC_FRAME_INDEX, "I", "with a trajectory log: IN's entry, from 0 "      \
     "(default 0)"},                                                                        \
    {"view-index", OC_VIEW_INDEX, "J,K", "with a trajectory log: the views' entries, one " \
     "per view (default: the entries in order, IN's left out)"},                            \
    {"view-intrinsics", OC_VIEW_INTRINSICS, "FX,FY,CX,CY|CAMERA.json", "the views' camera " \
     "(every view's), as --intrinsics; then the views may be of another size (default: "  \
     "IN's camera and size)"}

static const cli_own find_own[] = {
    FIND_OWN,
    {"points", OC_POINTS, "OUT.ply", "the frame's points, coloured, with a 'label' property: "
     "1 on the occluders (a colour and depth input is back-projected through its camera)"},
    {NULL, 0, NULL, NULL}};

/* --intrinsics is the command's own: it also takes a camera file. */
static const char *const skip[] = {"intrinsics", NULL};

static const cli_own remove_own[] = {
    FIND_OWN,
    {"occluders", OC_SAVE_MASK, "MASK.png", "the occluder mask used (255 = occluder)"},
    {"depth-out", OC_DEPTH_OUT, "D.png", "(colour and depth input) the repaired depth, a "
     "16-bit PNG at --scale; required with --depth"},
    {"colour-out", OC_COLOUR_OUT, "C.png", "(PCD input) the colour after the removal as a "
     "picture"},
    {"points", OC_POINTS, "OUT.ply", "the frame's points after the removal, coloured, with a "
     "'label' property: 1 for the points put behind the occluders (a colour and depth input "
     "is back-projected through its camera)"},
    {"fill-method", OC_FILL_METHOD, "M", "image-fill's method for the colour: wexler "
     "(default: multi-scale patch voting) or jain (paper 004's copy-paste)"},
    {"fill-window", OC_FILL_WINDOW, "W", "image-fill's starting window for the colour with "
     "--fill-method jain (default 17)"},
    {"depth-variant", OC_DEPTH_VARIANT, "V", "depth-fill's variant for the depth behind: "
     "plain, haar or decompose (default)"},
    {NULL, 0, NULL, NULL}};

typedef struct occ_args {
    cli_common cm;
    relief_remove_params p;
    int remove;
    const char *in, *depth, *overlay, *bg_mesh, *save_mask, *points, *depth_out, *colour_out;
    const char *views_arg, *poses;
    const char *camera_file, *view_camera_file; /* --intrinsics, --view-intrinsics files */
    cli_camera view_camera;                     /* --view-intrinsics */
    int has_view_camera;
    cli_pose_pick pick;                         /* --frame-index, --view-index */
    int view_index[RELIEF_OCCLUDER_MAX_VIEWS], n_view_index, pick_given;
    relief_occluder_view views[RELIEF_OCCLUDER_MAX_VIEWS];
    char view_names[RELIEF_OCCLUDER_MAX_VIEWS][1024];
    uint8_t *view_rgb[RELIEF_OCCLUDER_MAX_VIEWS]; /* owned */
    int n_views;
    double scale;
    relief_depth_encoding encoding; /* --depth-format */
    int encoding_given;
    cli_output outs[7]; /* -o, --overlay, --report, --occluders, --points, --depth-out,
                           --colour-out */
} occ_args;

static cli_spec spec(int remove)
{
    cli_spec s = {"occluders", "IN -o MASK.png [--depth DEPTH.png] [options]",
                  NULL, CLI_OUTPUT | CLI_REPORT | CLI_QUIET,
                  "the mask, a PNG of IN's size: 255 on the occluders; required",
                  NULL, NULL, 0, skip, find_own, NULL};
    static char about[2][1400];
    snprintf(about[0], sizeof about[0], "Find the occluders of an RGB-D frame from its depth "
             "(paper 004, section 2.1): the background's planes by RANSAC (those with nearly "
             "nothing behind them: walls, a floor, a facade), the points more than --margin in "
             "front of them as seeds, grown by colour constancy inside a --window square "
             "around each seed into the pixels whose depth is missing or, at the rim, on the "
             "background; the mask dilated, marking background as foreground rather than the "
             "reverse. %s", frame_help);
    snprintf(about[1], sizeof about[1], "Remove the occluders of an RGB-D frame: the mask "
             "(found as `relief occluders` finds it, or --mask), the colour behind filled by "
             "image-fill (its default, multi-scale patch voting; --fill-method jain: paper 004, "
             "chapter 3) and the depth behind repaired by depth-fill "
             "(paper 003) as the residual about the background, so that the new points lie on "
             "the background with its own roughness. %s OUT is written as IN: a PCD (the "
             "occluders' points replaced, the other pixels' bits kept), or the colour image "
             "with --depth-out for the depth.", frame_help);
    s.about = about[0];
    if (remove) {
        s.name = "remove-occluders";
        s.usage = "IN -o OUT [--mask MASK] [--depth DEPTH.png --depth-out D.png] [options]";
        s.about = about[1];
        s.shared |= CLI_MASK | CLI_LIMIT;
        s.out_help = "the frame without its occluders, IN's format; required, never IN";
        s.mask_help = "the occluders, a PNG of IN's size (non-zero), instead of finding them";
        s.own = remove_own;
    }
    s.params = relief_occluder_param_table(&s.n_params);
    return s;
}

/* --view-index J,K,...: log entries, one per view. */
static int view_indices(occ_args *a, const char *cmd, const char *arg)
{
    const char *at = arg;
    a->n_view_index = 0, a->pick_given = 1;
    while (*at) {
        char *end;
        long e = strtol(at, &end, 10);
        if (end == at || e < 0 || e > 1000000 || (*end && *end != ',') ||
            a->n_view_index == RELIEF_OCCLUDER_MAX_VIEWS)
            return !cli_usage_error(cmd, "--view-index '%s': expected 1 to 16 log entries "
                                    "(whole numbers from 0), comma separated", arg);
        a->view_index[a->n_view_index++] = (int)e;
        at = end + (*end == ',');
    }
    if (a->n_view_index == 0)
        return !cli_usage_error(cmd, "--view-index '%s': expected 1 to 16 log entries", arg);
    return 1;
}

static int take(void *ctx, int c, const char *arg)
{
    occ_args *a = ctx;
    static const char *const variants[] = CLI_NAMES(RELIEF_DEPTH_VARIANT_LIST);
    const char *cmd = a->remove ? "remove-occluders" : "occluders";
    long w;
    int v;
    switch (c) {
    case OC_DEPTH: a->depth = arg; return 1;
    case OC_SCALE: return cli_parse_real(cmd, "--scale", arg, &a->scale);
    case OC_OVERLAY: a->overlay = arg; return 1;
    case OC_BG_MESH: a->bg_mesh = arg; return 1;
    case OC_SAVE_MASK: a->save_mask = arg; return 1;
    case OC_POINTS: a->points = arg; return 1;
    case OC_DEPTH_OUT: a->depth_out = arg; return 1;
    case OC_COLOUR_OUT: a->colour_out = arg; return 1;
    case OC_VIEWS: a->views_arg = arg; return 1;
    case OC_POSES: a->poses = arg; return 1;
    case OC_INTRINSICS: {
        cli_camera c;
        a->camera_file = NULL, a->p.find.has_intrinsics = 0;
        if (!cli_camera_numbers(arg, &c))
            a->camera_file = arg; /* read with the frame */
        else
            a->p.find.has_intrinsics = 1, memcpy(a->p.find.intrinsics, c.k, sizeof c.k);
        return 1;
    }
    case OC_VIEW_INTRINSICS:
        a->view_camera_file = NULL, a->has_view_camera = 1;
        if (!cli_camera_numbers(arg, &a->view_camera))
            a->view_camera_file = arg;
        return 1;
    case OC_FRAME_INDEX:
        if (!cli_parse_long(cmd, "--frame-index", arg, 0, 1000000, &w))
            return 0;
        a->pick.frame = (int)w, a->pick_given = 1;
        return 1;
    case OC_VIEW_INDEX: return view_indices(a, cmd, arg);
    case OC_DEPTH_FORMAT: {
        static const char *const encodings[] = CLI_NAMES(RELIEF_DEPTH_ENCODING_LIST);
        if (!CLI_PARSE_ENUM(cmd, "--depth-format", arg, encodings, &v))
            return 0;
        a->encoding = (relief_depth_encoding)v;
        a->encoding_given = 1;
        return 1;
    }
    case OC_FILL_METHOD: {
        static const char *const methods[] = CLI_NAMES(RELIEF_IMAGE_FILL_METHOD_LIST);
        if (!CLI_PARSE_ENUM(cmd, "--fill-method", arg, methods, &v))
            return 0;
        a->p.colour.method = (relief_image_fill_method)v;
        return 1;
    }
    case OC_FILL_WINDOW:
        if (!cli_parse_long(cmd, "--fill-window", arg, 3, 1025, &w))
            return 0;
        a->p.colour.window = (int)w;
        return 1;
    case OC_DEPTH_VARIANT:
        if (!CLI_PARSE_ENUM(cmd, "--depth-variant", arg, variants, &v))
            return 0;
        a->p.depth.variant = (relief_depth_variant)v;
        return 1;
    }
    return 0;
}

/* A colour image relief writes (out) or reads (also binary Netpbm). */
static int is_image_name(const char *path, int out)
{
    const char *e = cli_ext_of(path);
    return !strcasecmp(e, ".png") || !strcasecmp(e, ".jpg") || !strcasecmp(e, ".jpeg") ||
           (!out && (!strcasecmp(e, ".ppm") || !strcasecmp(e, ".pgm") || !strcasecmp(e, ".pnm")));
}

/* --views into view_names, with --poses: 1 when they fit together. */
static int split_views(occ_args *a)
{
    const char *at = a->views_arg, *cmd = a->cm.cmd;
    if (!a->views_arg != !a->poses)
        return !cli_usage_error(cmd, "%s--views and --poses go together: the views and each "
                                "one's pose", "");
    while (at && *at) {
        size_t len = strcspn(at, ",");
        if (a->n_views == RELIEF_OCCLUDER_MAX_VIEWS || len == 0 ||
            len >= sizeof a->view_names[0])
            return !cli_usage_error(cmd, "--views '%s': expected 1 to 16 file names, comma "
                                    "separated", a->views_arg);
        memcpy(a->view_names[a->n_views], at, len);
        a->view_names[a->n_views++][len] = '\0';
        at += len + (at[len] == ',');
    }
    if (a->pick_given && !a->poses)
        return !cli_usage_error(cmd, "%s--frame-index and --view-index pick entries of --poses' "
                                "trajectory log: give --views and --poses", "");
    if (a->n_view_index && a->n_view_index != a->n_views)
        return !cli_usage_error(cmd, "--view-index: one entry per view; %s", a->n_views == 1
                                ? "1 view given" : "a different number of views given");
    if (a->has_view_camera && !a->views_arg)
        return !cli_usage_error(cmd, "%s--view-intrinsics is the views' camera: give --views",
                                "");
    a->pick.n_views = a->n_views;
    a->pick.view = a->n_view_index ? a->view_index : NULL;
    return 1;
}

/* The operands and the files' names: 0 when they fit together, else the
 * exit status (said). */
static int check_files(occ_args *a, int argc, char **argv)
{
    const char *cmd = a->cm.cmd, *out, *ins[7 + RELIEF_OCCLUDER_MAX_VIEWS];
    int pcd;
    if (!cli_one_input(&a->cm, argc, argv, "input IN", &a->in))
        return EXIT_USAGE;
    out = a->cm.out;
    pcd = !strcasecmp(cli_ext_of(a->in), ".pcd");
    if (!pcd && !is_image_name(a->in, 0))
        return cli_usage_error(cmd, "IN: '%s' is neither an organised PCD (.pcd) nor a colour "
                                "image (.png, .jpg, .ppm) with --depth", a->in);
    if (a->encoding_given && !a->depth)
        return cli_usage_error(cmd, "--depth-format %s: it says how --depth's samples are "
                                "depths; give --depth", relief_depth_encoding_name(a->encoding));
    if (pcd == (a->depth != NULL))
        return cli_usage_error(cmd, pcd ? "--depth %s: a PCD carries its own depth"
                                         : "IN '%s' is a colour image: give its depth with "
                                           "--depth DEPTH.png", pcd ? a->depth : a->in);
    if (a->remove && !a->depth != !a->depth_out)
        return cli_usage_error(cmd, "%s--depth-out is the repaired depth of a colour and depth "
                                "input: give both or neither", "");
    if (!a->remove && strcasecmp(cli_ext_of(out), ".png"))
        return cli_usage_error(cmd, "-o: '%s': the mask is a PNG", out);
    if (a->remove && (pcd ? strcasecmp(cli_ext_of(out), ".pcd") != 0 : !is_image_name(out, 1)))
        return cli_usage_error(cmd, "-o: '%s': OUT is written as IN: give it IN's kind "
                                "(.pcd, or .png / .jpg for a colour image)", out);
    if (a->depth_out && strcasecmp(cli_ext_of(a->depth_out), ".png"))
        return cli_usage_error(cmd, "--depth-out '%s': the depth is a 16-bit PNG", a->depth_out);
    if (!split_views(a))
        return EXIT_USAGE;
    ins[0] = a->in, ins[1] = a->depth, ins[2] = a->cm.mask, ins[3] = a->bg_mesh;
    ins[4] = a->poses, ins[5] = a->camera_file, ins[6] = a->view_camera_file;
    for (int k = 0; k < a->n_views; ++k)
        ins[7 + k] = a->view_names[k];
    a->outs[0] = (cli_output){"-o", out, CLI_OUT_FILE};
    a->outs[1] = (cli_output){"--overlay", a->overlay, CLI_OUT_FILE};
    a->outs[2] = (cli_output){"--report", a->cm.report, CLI_OUT_FILE};
    a->outs[3] = (cli_output){"--occluders", a->save_mask, CLI_OUT_FILE};
    a->outs[4] = (cli_output){"--points", a->points, CLI_OUT_FILE};
    a->outs[5] = (cli_output){"--depth-out", a->depth_out, CLI_OUT_FILE};
    a->outs[6] = (cli_output){"--colour-out", a->colour_out, CLI_OUT_FILE};
    if (a->colour_out && !is_image_name(a->colour_out, 1))
        return cli_usage_error(cmd, "--colour-out '%s': a PNG or JPEG", a->colour_out);
    return cli_check_outputs(cmd, ins, 7 + (size_t)a->n_views, a->outs, 7);
}

static int parse_args(int argc, char **argv, occ_args *a, int remove)
{
    cli_spec s = spec(remove);
    relief_error err = {0};
    int rc;
    memset(a, 0, sizeof *a);
    a->remove = remove;
    a->cm = cli_common_init(s.name);
    a->p = relief_remove_params_default();
    rc = cli_parse(&s, &a->cm, &a->p.find, take, a, argc, argv);
    if (rc)
        return rc < 0 ? 0 : rc;
    if ((rc = check_files(a, argc, argv)) != 0)
        return rc;
    a->p.find.run.input_name = a->in;
    a->p.find.run.output_name = a->cm.out;
    a->p.colour.run.backend = a->p.depth.run.backend = a->p.find.run.backend;
    a->p.colour.run.device = a->p.depth.run.device = a->p.find.run.device;
    a->p.colour.run.max_memory = a->p.depth.run.max_memory = a->p.find.run.max_memory;
    a->p.colour.run.threads = a->p.depth.run.threads = a->p.find.run.threads;
    if (a->bg_mesh && a->p.find.background == RELIEF_BACKGROUND_PLANES)
        a->p.find.background = RELIEF_BACKGROUND_MESH;
    if (a->p.find.background == RELIEF_BACKGROUND_MESH && !a->bg_mesh)
        return cli_usage_error(s.name, "%s--background mesh needs --background-mesh MESH", "");
    if (a->bg_mesh && a->p.find.background != RELIEF_BACKGROUND_MESH)
        return cli_usage_error(s.name, "--background-mesh %s: the background is the mesh; "
                               "leave --background out or give mesh", a->bg_mesh);
    {
        /* The ranges, before anything is read (the mesh comes later). */
        relief_occluder_params q = a->p.find;
        q.background = RELIEF_BACKGROUND_PLANES;
        if (relief_occluder_params_validate(&q, &err) != RELIEF_OK ||
            relief_image_fill_params_validate(&a->p.colour, &err) != RELIEF_OK)
            return cli_fail(s.name, &err);
    }
    return -1;
}

static uint64_t read_limit(const occ_args *a)
{
    return a->p.find.run.max_memory ? a->p.find.run.max_memory : relief_default_memory_limit();
}

/* The frame: a PCD with colour, or a colour image and its depth. */
static relief_status read_frame(const occ_args *a, relief_depth_image *f, relief_error *err)
{
    relief_image c = {0, 0, 0, 0, 0, NULL};
    relief_status st = relief_depth_read_as(a->depth ? a->depth : a->in, a->encoding, a->scale,
                                            read_limit(a) / 64, f, err);
    if (st == RELIEF_OK && !a->depth && f->format == RELIEF_DEPTH_PFM)
        st = relief_fail(err, RELIEF_E_FORMAT, "%s is a PFM named .pcd", a->in);
    if (st == RELIEF_OK && !a->depth && !f->rgb)
        st = relief_fail(err, RELIEF_E_USAGE, "%s has no colour (no rgb field): occluders "
                         "are grown by colour; give a PCD with rgb, or a colour image with "
                         "--depth", a->in);
    if (st == RELIEF_OK && a->depth && f->format != RELIEF_DEPTH_PNG16)
        st = relief_fail(err, RELIEF_E_FORMAT, "--depth %s: expected a 16-bit depth PNG or "
                         "PGM, not a %s file", a->depth, relief_depth_format_name(f->format));
    if (st == RELIEF_OK && a->depth)
        st = relief_image_read(a->in, read_limit(a), &c, err);
    if (st == RELIEF_OK && a->depth && (c.width != f->width || c.height != f->height))
        st = relief_fail(err, RELIEF_E_USAGE, "%s is %d x %d pixels, --depth %s is %d x %d: "
                         "they must be the same size (registered)", a->in, c.width, c.height,
                         a->depth, f->width, f->height);
    if (st == RELIEF_OK && a->depth &&
        !(f->rgb = malloc((size_t)f->width * f->height * 3)))
        st = relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the frame's colour");
    if (st == RELIEF_OK && a->depth)
        cli_image_rgb8(&c, f->rgb);
    relief_image_free(&c);
    if (st != RELIEF_OK)
        relief_depth_image_free(f);
    return st;
}

/* The overlay: the colour, the occluders half red. */
static relief_status write_overlay(relief_sink *s, const relief_depth_image *f,
                                   const uint8_t *mask, relief_error *err)
{
    size_t n = (size_t)f->width * f->height;
    uint8_t *px = malloc(n * 3);
    relief_status st;
    if (!px)
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the overlay");
    for (size_t i = 0; i < n; ++i)
        for (int k = 0; k < 3; ++k)
            px[3 * i + k] = mask[i] ? (uint8_t)((f->rgb[3 * i + k] + (k == 0 ? 255 : 0)) / 2)
                                    : f->rgb[3 * i + k];
    st = relief_image_write_to(s, &(relief_image){f->width, f->height, 3, 8, 0, px}, err);
    free(px);
    return st;
}

/* What write_one writes. */
typedef struct occ_out {
    const occ_args *a;
    const relief_depth_image *in;  /* the frame as read (the overlay's colour) */
    const relief_depth_image *out; /* after the removal (remove-occluders) */
    const uint8_t *mask;           /* 1 = occluder */
    const char *json;
} occ_out;

/* The mask (0 / 1) as a PNG, 255 on the occluders. */
static relief_status write_mask(relief_sink *s, int w, int h, const uint8_t *label,
                                relief_error *err)
{
    size_t n = (size_t)w * h;
    uint8_t *px = malloc(n);
    relief_status st;
    if (!px)
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the mask's picture");
    for (size_t i = 0; i < n; ++i)
        px[i] = label[i] ? 255 : 0;
    st = relief_image_write_to(s, &(relief_image){w, h, 1, 8, 0, px}, err);
    free(px);
    return st;
}

static relief_status write_one(void *ctx, size_t i, relief_sink *s, relief_error *err)
{
    const occ_out *o = ctx;
    const relief_depth_image *f = o->out;
    switch (i) {
    case 0:
        if (!o->a->remove)
            return write_mask(s, f->width, f->height, o->mask, err);
        if (!o->a->depth)
            return relief_depth_write_to(s, f, f->format, 0.0, err);
        return relief_image_write_to(s, &(relief_image){f->width, f->height, 3, 8, 0, f->rgb},
                                     err);
    case 1: return write_overlay(s, o->in, o->mask, err);
    case 2: return cli_json_to(s, o->json, 0, NULL, NULL, err);
    case 3: return write_mask(s, f->width, f->height, o->mask, err);
    case 4: return relief_depth_points_write_to(s, f, o->mask, err);
    case 5: return relief_depth_write_to(s, f, RELIEF_DEPTH_PNG16, o->a->scale, err);
    default:
        return relief_image_write_to(s, &(relief_image){f->width, f->height, 3, 8, 0, f->rgb},
                                     err);
    }
}

static void say_find(const occ_args *a, const relief_occluder_report *r)
{
    const char *cmd = a->cm.cmd;
    char bg[64];
    if (a->bg_mesh)
        snprintf(bg, sizeof bg, "the mesh");
    else
        snprintf(bg, sizeof bg, "%d plane%s", r->planes, r->planes == 1 ? "" : "s");
    fprintf(stderr, "relief %s: %s: %d x %d, %zu pixels captured; background: %s (noise "
            "%.3g z^2, margin %.3g at the median depth), %zu points on it, %zu behind\n", cmd,
            a->in, r->width, r->height, r->captured, bg, r->noise, r->margin,
            r->on_background, r->behind);
    fprintf(stderr, "relief %s: %zu seeds in %zu groups (%zu dropped), grown by %zu where the "
            "depth is missing and %zu at the rim, dilated by %zu: %zu occluder pixels (%.1f "
            "%%)\n", cmd, r->seeds, r->seed_groups, r->seeds_dropped, r->grown_missing,
            r->grown_edge, r->dilated, r->occluder_pixels,
            100.0 * r->occluder_pixels / ((double)r->width * r->height));
    if (r->views)
        fprintf(stderr, "relief %s: %d views (eq. 2.1): %zu seeds where the depth is missing; "
                "verdicts %zu foreground, %zu background, %zu unknown\n", cmd, r->views,
                r->parallax_seeds, r->view_foreground, r->view_background, r->view_unknown);
}

/* View k's colour, of f's size: a colour image, or a PCD's colour. */
static relief_status read_view(occ_args *a, int k, const relief_depth_image *f,
                               relief_error *err)
{
    const char *path = a->view_names[k];
    relief_depth_image d;
    relief_image c = {0, 0, 0, 0, 0, NULL};
    relief_status st;
    int w = 0, h = 0;
    memset(&d, 0, sizeof d);
    if (!strcasecmp(cli_ext_of(path), ".pcd")) {
        st = relief_depth_read(path, 0.0, read_limit(a) / 64, &d, err);
        if (st == RELIEF_OK && !d.rgb)
            st = relief_fail(err, RELIEF_E_USAGE, "--views %s: no colour (no rgb field)", path);
        w = d.width, h = d.height;
    } else {
        st = relief_image_read(path, read_limit(a), &c, err);
        w = c.width, h = c.height;
    }
    if (st == RELIEF_OK && !a->has_view_camera && (w != f->width || h != f->height))
        st = relief_fail(err, RELIEF_E_USAGE, "--views %s is %d x %d pixels, %s is %d x %d: "
                         "through IN's camera they must be the same size (or give "
                         "--view-intrinsics)", path, w, h, a->in, f->width, f->height);
    if (st == RELIEF_OK && a->view_camera.width &&
        (w != a->view_camera.width || h != a->view_camera.height))
        st = relief_fail(err, RELIEF_E_USAGE, "--views %s is %d x %d pixels, --view-intrinsics "
                         "%s is a camera of %d x %d", path, w, h, a->view_camera_file,
                         a->view_camera.width, a->view_camera.height);
    if (st == RELIEF_OK && !(a->view_rgb[k] = malloc((size_t)w * h * 3)))
        st = relief_fail(err, RELIEF_E_NOMEM, "cannot allocate view %s", path);
    if (st == RELIEF_OK && d.rgb)
        memcpy(a->view_rgb[k], d.rgb, (size_t)w * h * 3);
    else if (st == RELIEF_OK)
        cli_image_rgb8(&c, a->view_rgb[k]);
    memset(&a->views[k], 0, sizeof a->views[k]);
    a->views[k].width = w, a->views[k].height = h, a->views[k].rgb = a->view_rgb[k];
    if (a->has_view_camera)
        memcpy(a->views[k].intrinsics, a->view_camera.k, sizeof a->view_camera.k);
    relief_depth_image_free(&d);
    relief_image_free(&c);
    return st;
}

/* The cameras given as files (--intrinsics, --view-intrinsics): read,
 * IN's checked against its size. */
static relief_status read_cameras(occ_args *a, const relief_depth_image *f, relief_error *err)
{
    cli_camera c;
    relief_status st = RELIEF_OK;
    if (a->camera_file)
        st = cli_read_camera_json("--intrinsics", a->camera_file, &c, err);
    if (st == RELIEF_OK && a->camera_file && (c.width != f->width || c.height != f->height))
        st = relief_fail(err, RELIEF_E_USAGE, "--intrinsics %s is a camera of %d x %d pixels, "
                         "%s is %d x %d", a->camera_file, c.width, c.height, a->in, f->width,
                         f->height);
    if (st == RELIEF_OK && a->camera_file) {
        a->p.find.has_intrinsics = 1;
        memcpy(a->p.find.intrinsics, c.k, sizeof c.k);
    }
    if (st == RELIEF_OK && a->view_camera_file)
        st = cli_read_camera_json("--view-intrinsics", a->view_camera_file, &a->view_camera,
                                  err);
    return st;
}

/* The views' colours and poses. */
static relief_status read_views(occ_args *a, const relief_depth_image *f, relief_error *err)
{
    double pose[RELIEF_OCCLUDER_MAX_VIEWS][12];
    int is_log;
    relief_status st = RELIEF_OK;
    for (int k = 0; st == RELIEF_OK && k < a->n_views; ++k)
        st = read_view(a, k, f, err);
    if (st == RELIEF_OK && a->n_views)
        st = cli_read_poses(a->poses, &a->pick, a->pick_given, pose, &is_log, err);
    for (int k = 0; st == RELIEF_OK && k < a->n_views; ++k)
        memcpy(a->views[k].pose, pose[k], sizeof pose[k]);
    return st;
}

/* The inputs: the frame, the background mesh, the given mask. */
static relief_status read_inputs(occ_args *a, relief_depth_image *f, relief_mesh **bg,
                                 relief_image *mask, relief_error *err)
{
    relief_status st = read_frame(a, f, err);
    if (st == RELIEF_OK)
        st = read_cameras(a, f, err);
    if (st == RELIEF_OK)
        st = read_views(a, f, err);
    a->p.find.views = a->n_views ? a->views : NULL;
    a->p.find.n_views = a->n_views;
    if (st == RELIEF_OK && a->bg_mesh)
        st = cli_read_mesh(a->cm.cmd, a->bg_mesh, a->cm.quiet, bg, NULL, err);
    a->p.find.background_mesh = *bg;
    if (st == RELIEF_OK && a->cm.mask)
        st = relief_image_read(a->cm.mask, read_limit(a), mask, err);
    if (st == RELIEF_OK && a->cm.mask && (mask->width != f->width || mask->height != f->height))
        st = relief_fail(err, RELIEF_E_USAGE, "--mask %s is %d x %d pixels, %s is %d x %d: "
                         "they must be the same size", a->cm.mask, mask->width, mask->height,
                         a->in, f->width, f->height);
    return st;
}

/* A colour and depth frame's points for --points: each pixel's depth
 * back-projected through the camera the finding used (the report's: x / z
 * = c0 u + c1, y / z = c2 v + c3), as a PCD carries them. */
static relief_status give_points(relief_depth_image *f, const double cam[4], relief_error *err)
{
    if (f->xyz)
        return RELIEF_OK;
    if (!(f->xyz = malloc((size_t)f->width * f->height * 3 * sizeof *f->xyz)))
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the frame's points");
    for (int v = 0; v < f->height; ++v)
        for (int u = 0; u < f->width; ++u) {
            size_t i = (size_t)v * f->width + u;
            float z = isfinite(f->z[i]) && f->z[i] > 0.0f ? f->z[i] : NAN;
            f->xyz[3 * i] = (float)((cam[0] * u + cam[1]) * z);
            f->xyz[3 * i + 1] = (float)((cam[2] * v + cam[3]) * z);
            f->xyz[3 * i + 2] = z;
        }
    return RELIEF_OK;
}

static void free_views(occ_args *a)
{
    for (int k = 0; k < a->n_views; ++k)
        free(a->view_rgb[k]);
}

static int find_mode(occ_args *a)
{
    relief_error err = {0};
    relief_depth_image f;
    relief_image found = {0, 0, 0, 0, 0, NULL}, none = {0, 0, 0, 0, 0, NULL};
    relief_mesh *bg = NULL;
    relief_occluder_report r;
    relief_status st;
    memset(&f, 0, sizeof f);
    memset(&r, 0, sizeof r);
    st = read_inputs(a, &f, &bg, &none, &err);
    if (st == RELIEF_OK)
        st = relief_find_occluders(&f, &a->p.find, &found, &r, &err);
    if (st == RELIEF_OK && a->points)
        st = give_points(&f, r.camera, &err);
    if (st == RELIEF_OK) {
        occ_out o = {a, &f, &f, found.data, r.json};
        for (size_t i = 0; i < (size_t)f.width * f.height; ++i)
            ((uint8_t *)found.data)[i] = ((uint8_t *)found.data)[i] != 0;
        st = cli_write_outputs(a->outs, 7, write_one, &o, NULL, &err);
    }
    if (st == RELIEF_OK && !a->cm.quiet)
        say_find(a, &r);
    relief_depth_image_free(&f);
    relief_mesh_destroy(bg);
    relief_image_free(&found);
    relief_occluder_report_free(&r);
    free_views(a);
    return st == RELIEF_OK ? 0 : cli_fail(a->cm.cmd, &err);
}

/* A copy of f (what the removal changes). */
static relief_status copy_frame(const relief_depth_image *f, relief_depth_image *g,
                                relief_error *err)
{
    size_t n = (size_t)f->width * f->height;
    *g = *f;
    g->z = malloc(n * sizeof *g->z);
    g->xyz = f->xyz ? malloc(n * 3 * sizeof *g->xyz) : NULL;
    g->rgb = malloc(n * 3);
    if (!g->z || !g->rgb || (f->xyz && !g->xyz)) {
        relief_depth_image_free(g);
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the output frame");
    }
    memcpy(g->z, f->z, n * sizeof *g->z);
    if (f->xyz)
        memcpy(g->xyz, f->xyz, n * 3 * sizeof *g->xyz);
    memcpy(g->rgb, f->rgb, n * 3);
    return RELIEF_OK;
}

static void say_remove(const occ_args *a, const relief_remove_report *r)
{
    if (!a->cm.mask)
        say_find(a, &r->find);
    fprintf(stderr, "relief remove-occluders: %zu occluder pixels: colour filled, %zu given "
            "the background's depth (RMS %.3g about it), %zu left missing (no background "
            "behind); %.2f s\n", r->find.occluder_pixels, r->replaced, r->background_rms,
            r->left_missing, r->seconds_total);
}

static int remove_mode(occ_args *a)
{
    relief_error err = {0};
    relief_depth_image f, g;
    relief_image mask = {0, 0, 0, 0, 0, NULL};
    relief_mesh *bg = NULL;
    relief_remove_report r;
    uint8_t *label = NULL;
    cli_progress pr;
    relief_status st;
    memset(&f, 0, sizeof f);
    memset(&g, 0, sizeof g);
    memset(&r, 0, sizeof r);
    st = read_inputs(a, &f, &bg, &mask, &err);
    if (st == RELIEF_OK)
        st = copy_frame(&f, &g, &err);
    if (st == RELIEF_OK) {
        cli_progress_start(&pr, &a->cm, &a->p.colour.run);
        st = relief_remove_occluders(&g, a->cm.mask ? &mask : NULL, &a->p, &r, &err);
        cli_progress_end(&pr);
        cli_progress_explain(&pr, st, &err);
    }
    if (st == RELIEF_OK && a->points)
        st = give_points(&g, r.find.camera, &err);
    if (st == RELIEF_OK && !(label = malloc((size_t)f.width * f.height)))
        st = relief_fail(&err, RELIEF_E_NOMEM, "cannot allocate the labels");
    if (st == RELIEF_OK)
        memcpy(label, r.mask, (size_t)f.width * f.height); /* 0 / 1, found or given */
    if (st == RELIEF_OK) {
        occ_out o = {a, &f, &g, label, r.json};
        st = cli_write_outputs(a->outs, 7, write_one, &o, NULL, &err);
    }
    if (st == RELIEF_OK && !a->cm.quiet)
        say_remove(a, &r);
    relief_depth_image_free(&f);
    relief_depth_image_free(&g);
    relief_mesh_destroy(bg);
    relief_image_free(&mask);
    relief_remove_report_free(&r);
    free(label);
    free_views(a);
    return st == RELIEF_OK ? 0 : cli_fail(a->cm.cmd, &err);
}

int cli_cmd_occluders(int argc, char **argv, int parse_only)
{
    occ_args a;
    int rc = parse_args(argc, argv, &a, 0);
    if (rc >= 0 || parse_only)
        return rc >= 0 ? rc : 0;
    return find_mode(&a);
}

int cli_cmd_remove_occluders(int argc, char **argv, int parse_only)
{
    occ_args a;
    int rc = parse_args(argc, argv, &a, 1);
    if (rc >= 0 || parse_only)
        return rc >= 0 ? rc : 0;
    return remove_mode(&a);
}
