/* relief image-fill: hole filling in images (paper 004; image/fill.h). */
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
#include "image/fill.h"
#include "image/image_io.h"
#include "image/patch.h"

static const char image_fill_help[] =
    "usage: relief image-fill IN -o OUT [--mask MASK] [options]\n"
    "\n"
    "Fill the holes of an image (paper 004): a 1-D interpolation pass along rows\n"
    "and columns where a gap's ends agree, then copy-paste synthesis of windows\n"
    "matched over a Gaussian pyramid. IN is PNG (8 or 16 bits, grey, RGB, with or\n"
    "without alpha) or JPEG; the hole is MASK's non-zero pixels, or IN's transparent\n"
    "pixels without --mask. OUT is PNG or JPEG by its extension; pixels outside\n"
    "the hole are written back unchanged.\n"
    "\n"
    "  -o, --output OUT      the filled image; required, never IN\n"
    "  --mask MASK           PNG or JPEG of IN's size: non-zero = hole\n"
    "  --window W            starting window, odd pixels 3..1025 (default 17)\n"
    "  --min-window W        smallest window before the 3 x 3 fallback (default 5)\n"
    "  --atlas               texture atlases: --window 129 --min-window 9\n"
    "  --tau T               accept a match when its RMS difference is under T\n"
    "                        (default 36 on 0..255, x 257 for 16-bit images)\n"
    "  --search-radius R     search the (2R+1)^2 region around each pixel\n"
    "                        (default: the whole image)\n"
    "  --exhaustive          every window at full resolution (slow; the reference\n"
    "                        the pyramid is measured against)\n"
    "  --no-interp           skip the 1-D interpolation pass\n"
    "  --interp-diff D       1-D pass: a gap's two ends differ by at most D in every\n"
    "                        channel (default 16 on 0..255)\n"
    "  --interp-sd S         1-D pass: the 4 pixels beyond each end have a standard\n"
    "                        deviation of at most S (default 3 on 0..255)\n"
    "  --seed N              the fallback's random choice (default 1)\n"
    "  --backend B           auto, scalar or opencl (default auto: OpenCL when a\n"
    "                        device starts, else scalar); outputs are identical\n"
    "  --device N            OpenCL device (see 'relief devices')\n"
    "  --max-memory SIZE     refuse images needing more host memory (default 80 %\n"
    "                        of physical memory)\n"
    "  --report R.json       counts, windows tried, pyramid levels, stage times\n"
    "  --quiet               no progress or notes on stderr\n";

typedef struct report_ctx {
    const char *in, *out, *mask;
    const relief_raster *img;
    const relief_fill_params *p;
    const relief_fill_report *r;
    const relief_patch_scorer *scorer;
    const char *note;
    double seconds_total;
} report_ctx;

static int write_report(FILE *f, void *ctx)
{
    const report_ctx *c = ctx;
    const relief_fill_report *r = c->r;
    relief_json j;
    rj_init(&j, f);
    rj_begin_object(&j, NULL);
    rj_string(&j, "command", "image-fill");
    rj_string(&j, "input", c->in);
    rj_string(&j, "output", c->out);
    if (c->mask)
        rj_string(&j, "mask", c->mask);
    else
        rj_null(&j, "mask");
    rj_begin_object(&j, "image");
    rj_int(&j, "width", c->img->width);
    rj_int(&j, "height", c->img->height);
    rj_int(&j, "channels", c->img->channels);
    rj_int(&j, "bit_depth", c->img->bit_depth);
    rj_end_object(&j);
    rj_begin_object(&j, "parameters");
    rj_int(&j, "window", c->p->window);
    rj_int(&j, "min_window", c->p->min_window);
    rj_number(&j, "tau", r->tau);
    rj_number(&j, "max_hole_fraction", c->p->max_hole_fraction);
    rj_int(&j, "search_radius", c->p->search_radius);
    rj_bool(&j, "exhaustive", c->p->exhaustive);
    rj_bool(&j, "interp", c->p->interp);
    rj_number(&j, "interp_diff", r->interp_diff);
    rj_number(&j, "interp_sd", r->interp_sd);
    rj_int(&j, "seed", c->p->seed);
    rj_end_object(&j);
    rj_begin_object(&j, "pixels");
    rj_int(&j, "hole", (long long)r->hole_pixels);
    rj_int(&j, "by_rows", (long long)r->by_rows);
    rj_int(&j, "by_columns", (long long)r->by_columns);
    rj_int(&j, "by_copy", (long long)r->by_copy);
    rj_int(&j, "by_fallback", (long long)r->by_fallback);
    rj_end_object(&j);
    rj_begin_object(&j, "search");
    rj_int(&j, "queries", (long long)r->queries);
    rj_int(&j, "windows_tried", (long long)r->searches);
    rj_int(&j, "windows_accepted", (long long)r->accepted);
    rj_int(&j, "candidates_scored", (long long)r->candidates);
    rj_int(&j, "pyramid_levels", r->levels);
    rj_int(&j, "start_level", r->start_level);
    rj_int(&j, "top_m", r->top_m);
    rj_end_object(&j);
    rj_begin_object(&j, "seconds");
    rj_number(&j, "interp", r->seconds_interp);
    rj_number(&j, "copy_paste", r->seconds_copy);
    rj_number(&j, "scoring", r->seconds_score);
    rj_number(&j, "total", c->seconds_total);
    rj_end_object(&j);
    rj_string(&j, "backend", relief_backend_name(c->scorer->backend));
    rj_string(&j, "device", c->scorer->device);
    rj_string(&j, "backend_note", c->note);
    rj_end_object(&j);
    fputc('\n', f);
    return ferror(f);
}

/* The hole: MASK's non-zero pixels (any channel but alpha), or IN's
 * transparent ones. *holes counts them. */
static relief_status make_hole(const relief_raster *img, const relief_raster *mask,
                               const char *in, uint8_t **out, size_t *holes,
                               relief_error *err)
{
    size_t n = (size_t)img->width * img->height;
    uint8_t *hole;
    if (!mask && !relief_raster_has_alpha(img))
        return relief_fail(err, RELIEF_E_USAGE, "%s has no alpha channel, so no hole: give "
                           "the hole as --mask MASK", in);
    hole = malloc(n);
    if (!hole)
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the hole mask");
    *holes = 0;
    for (size_t i = 0; i < n; ++i) {
        int h = 0;
        if (mask) {
            int colours = relief_raster_has_alpha(mask) ? mask->channels - 1 : mask->channels;
            for (int c = 0; c < colours; ++c)
                h |= mask->v[i * mask->channels + c] != 0.0f;
        } else {
            h = img->v[i * img->channels + img->channels - 1] == 0.0f;
        }
        hole[i] = (uint8_t)h;
        *holes += (size_t)h;
    }
    *out = hole;
    return RELIEF_OK;
}

int cli_cmd_image_fill(int argc, char **argv, int parse_only)
{
    enum { OPT_MASK = 1000, OPT_MIN_WINDOW, OPT_ATLAS, OPT_TAU, OPT_SEARCH_RADIUS,
           OPT_EXHAUSTIVE, OPT_NO_INTERP, OPT_INTERP_DIFF, OPT_INTERP_SD };
    static const struct option opts[] = {
        {"output", required_argument, 0, 'o'},
        {"mask", required_argument, 0, OPT_MASK},
        {"window", required_argument, 0, OPT_WINDOW},
        {"min-window", required_argument, 0, OPT_MIN_WINDOW},
        {"atlas", no_argument, 0, OPT_ATLAS},
        {"tau", required_argument, 0, OPT_TAU},
        {"search-radius", required_argument, 0, OPT_SEARCH_RADIUS},
        {"exhaustive", no_argument, 0, OPT_EXHAUSTIVE},
        {"no-interp", no_argument, 0, OPT_NO_INTERP},
        {"interp-diff", required_argument, 0, OPT_INTERP_DIFF},
        {"interp-sd", required_argument, 0, OPT_INTERP_SD},
        {"seed", required_argument, 0, OPT_SEED},
        {"backend", required_argument, 0, OPT_BACKEND},
        {"device", required_argument, 0, OPT_DEVICE},
        {"max-memory", required_argument, 0, OPT_MAX_MEMORY},
        {"report", required_argument, 0, OPT_REPORT},
        {"quiet", no_argument, 0, OPT_QUIET},
        {"help", no_argument, 0, 'h'},
        {0, 0, 0, 0}};
    relief_fill_params p = relief_fill_params_default();
    relief_fill_report rep;
    relief_error err = {RELIEF_OK, ""};
    relief_raster img = {0, 0, 0, 0, NULL}, mask = {0, 0, 0, 0, NULL};
    relief_patch_scorer *scorer = NULL;
    relief_backend backend = RELIEF_BACKEND_AUTO;
    relief_params mp = relief_params_default();
    relief_image_limit lim;
    const char *out = NULL, *in, *mask_path = NULL, *report = NULL;
    char note[1024] = "";
    uint8_t *hole = NULL;
    size_t holes = 0;
    int c, quiet = 0, device = -1, window_set = 0, min_window_set = 0, atlas = 0, rc = 0;
    long v;
    double d, t_start = relief_seconds();
    relief_status st = RELIEF_OK;
    cli_count_progress pr = {"image-fill", "pixels", 0, 0.0, 0.0};
    sigset_t held;

    optind = 0;
    while ((c = getopt_long(argc, argv, "o:h", opts, NULL)) != -1) {
        switch (c) {
        case 'o': out = optarg; break;
        case OPT_MASK: mask_path = optarg; break;
        case OPT_WINDOW:
            if (!cli_parse_int_range("image-fill", "--window", optarg, 3, 1025, &v))
                return EXIT_USAGE;
            p.window = (int)v;
            window_set = 1;
            break;
        case OPT_MIN_WINDOW:
            if (!cli_parse_int_range("image-fill", "--min-window", optarg, 3, 1025, &v))
                return EXIT_USAGE;
            p.min_window = (int)v;
            min_window_set = 1;
            break;
        case OPT_ATLAS: atlas = 1; break;
        case OPT_TAU:
            if (!cli_parse_real("image-fill", "--tau", optarg, &d))
                return EXIT_USAGE;
            if (d <= 0)
                return cli_usage_error("image-fill", "--tau: '%s' is out of range: expected a "
                                       "value > 0", optarg);
            p.tau = d;
            break;
        case OPT_SEARCH_RADIUS:
            if (!cli_parse_int_range("image-fill", "--search-radius", optarg, 1, 1000000, &v))
                return EXIT_USAGE;
            p.search_radius = (int)v;
            break;
        case OPT_EXHAUSTIVE: p.exhaustive = 1; break;
        case OPT_NO_INTERP: p.interp = 0; break;
        case OPT_INTERP_DIFF:
        case OPT_INTERP_SD:
            if (!cli_parse_real("image-fill", c == OPT_INTERP_DIFF ? "--interp-diff"
                                                                   : "--interp-sd",
                                optarg, &d))
                return EXIT_USAGE;
            if (d < 0)
                return cli_usage_error("image-fill", "'%s' is out of range: the 1-D pass's "
                                       "thresholds are >= 0", optarg);
            if (c == OPT_INTERP_DIFF)
                p.interp_diff = d;
            else
                p.interp_sd = d;
            break;
        case OPT_SEED:
            if (!cli_parse_int_range("image-fill", "--seed", optarg, 0, 4294967295L, &v))
                return EXIT_USAGE;
            p.seed = (uint32_t)v;
            break;
        case OPT_BACKEND:
            if (!cli_parse_backend("image-fill", optarg, 0, &backend))
                return EXIT_USAGE;
            break;
        case OPT_DEVICE:
            if (!cli_parse_int_range("image-fill", "--device", optarg, 0, 1023, &v))
                return EXIT_USAGE;
            device = (int)v;
            break;
        case OPT_MAX_MEMORY:
            if (relief_parse_size(optarg, &mp.max_memory, &err) != RELIEF_OK)
                return cli_usage_error("image-fill", "--max-memory: %s", err.message);
            break;
        case OPT_REPORT: report = optarg; break;
        case OPT_QUIET: quiet = 1; break;
        case 'h': fputs(image_fill_help, stdout); return 0;
        default: fprintf(stderr, "Try 'relief image-fill --help'.\n"); return EXIT_USAGE;
        }
    }
    if (atlas) {
        if (!window_set)
            p.window = 129;
        if (!min_window_set)
            p.min_window = 9;
    }
    if (optind >= argc)
        return cli_usage_error("image-fill", "%smissing input image IN", "");
    if (argc - optind > 1)
        return cli_usage_error("image-fill", "unexpected argument '%s'", argv[optind + 1]);
    in = argv[optind];
    if (!out)
        return cli_usage_error("image-fill", "%smissing -o OUT", "");
    if (relief_image_format_of_name(out) == RELIEF_IMAGE_UNKNOWN)
        return cli_usage_error("image-fill", "-o: '%s' does not end in .png, .jpg or .jpeg",
                               out);
    if (p.window % 2 == 0 || p.min_window % 2 == 0 || p.min_window > p.window)
        return cli_usage_error("image-fill", "%s--window and --min-window must be odd, "
                               "--min-window at most --window", "");
    if (cli_same_file(in, out) || (mask_path && cli_same_file(mask_path, out)))
        return cli_usage_error("image-fill", "-o: '%s' is an input; relief never overwrites "
                               "its input", out);
    if (report && (cli_same_file(in, report) || cli_same_file(out, report) ||
                   (mask_path && cli_same_file(mask_path, report))))
        return cli_usage_error("image-fill", "--report: '%s' names another file of the run",
                               report);
    if (parse_only)
        return 0;

    lim.limit = relief_memory_limit(&mp);
    lim.factor = 5.0; /* relief_fill_estimate over the raster, at one channel */
    lim.what = "filling it";
    st = relief_raster_read(in, &lim, &img, &err);
    if (st == RELIEF_OK && mask_path) {
        relief_image_limit ml = {lim.limit, 1.0, "the mask"};
        st = relief_raster_read(mask_path, &ml, &mask, &err);
        if (st == RELIEF_OK && (mask.width != img.width || mask.height != img.height))
            st = relief_fail(&err, RELIEF_E_USAGE, "--mask %s is %d x %d pixels, %s is %d x "
                             "%d: they must be the same size", mask_path, mask.width,
                             mask.height, in, img.width, img.height);
    }
    if (st == RELIEF_OK && relief_image_format_of_name(out) == RELIEF_IMAGE_JPEG &&
        img.bit_depth != 8)
        st = relief_fail(&err, RELIEF_E_FORMAT, "%s has 16 bits per channel and JPEG holds 8: "
                         "write OUT as .png", in);
    if (st == RELIEF_OK)
        st = make_hole(&img, mask_path ? &mask : NULL, in, &hole, &holes, &err);
    if (st == RELIEF_OK)
        st = relief_fill_params_validate(&p, img.width, img.height, &err);
    if (st == RELIEF_OK)
        st = relief_patch_scorer_create(backend, device, &scorer, note, sizeof note, &err);
    if (st != RELIEF_OK)
        goto done;
    if (!quiet && note[0])
        fprintf(stderr, "relief image-fill: %s\n", note);
    if (holes == 0) {
        if (!quiet)
            fprintf(stderr, "relief image-fill: %s: no hole pixels (%s): writing the image "
                    "unchanged\n", in, mask_path ? "the mask is all zero" : "no pixel is "
                    "transparent");
    } else {
        pr.print = !quiet && isatty(2);
        pr.start = relief_seconds();
        p.progress = cli_on_progress;
        p.progress_ctx = &pr;
        st = relief_fill(&img, hole, &p, scorer, &rep, &err);
        if (st != RELIEF_OK)
            goto done;
    }
    if (holes == 0)
        memset(&rep, 0, sizeof rep);
    cli_hold_signals(&held);
    st = relief_raster_write(out, &img, &err);
    if (st == RELIEF_OK && report) {
        report_ctx r = {in, out, mask_path, &img, &p, &rep, scorer, note,
                        relief_seconds() - t_start};
        st = relief_atomic_write_text(report, write_report, &r, &err);
        if (st != RELIEF_OK)
            remove(out); /* all outputs or none */
    }
    cli_release_signals(&held);
    if (st == RELIEF_OK && !quiet && holes)
        fprintf(stderr, "relief image-fill: %zu hole pixels: %zu by rows, %zu by columns, %zu "
                "copied (%zu of %zu windows accepted), %zu by the fallback; %.2f s on %s\n",
                rep.hole_pixels, rep.by_rows, rep.by_columns, rep.by_copy, rep.accepted,
                rep.searches, rep.by_fallback, relief_seconds() - t_start, scorer->device);
done:
    if (st != RELIEF_OK)
        rc = cli_fail("image-fill", &err);
    relief_patch_scorer_destroy(scorer);
    relief_raster_free(&img);
    relief_raster_free(&mask);
    free(hole);
    return rc;
}
