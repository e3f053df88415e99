/* relief image-fill: hole filling in images (paper 004), a client of
 * relief_image_fill (relief/image.h): options, the files, the summary. */
#include "cli/commands.h"

#include <getopt.h>
#include <signal.h>
#include <stdio.h>
#include <strings.h>

#include "relief/relief.h"
#include "base/error.h"
#include "base/memlimit.h"
#include "cli/options.h"

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
    "  --tau T               accept a match when its RMS difference is under T > 0\n"
    "                        (default 36 on 0..255, x 257 for 16-bit images)\n"
    "  --search-radius R     search the (2R+1)^2 region around each pixel\n"
    "                        (default 0: the whole image)\n"
    "  --exhaustive          every window at full resolution (slow; the reference\n"
    "                        the pyramid is measured against)\n"
    "  --no-interp           skip the 1-D interpolation pass\n"
    "  --interp-diff D       1-D pass: a gap's two ends differ by at most D in every\n"
    "                        channel (default 16 on 0..255)\n"
    "  --interp-sd S         1-D pass: the 4 pixels beyond each end have a standard\n"
    "                        deviation of at most S (default 3 on 0..255)\n"
    "  --seed N              the fallback's random choice (default 1)\n"
    "  --backend B           auto, scalar or opencl (default auto: OpenCL on a GPU,\n"
    "                        else scalar; host runs as scalar); outputs are identical\n"
    "  --device N            OpenCL device (see 'relief devices')\n"
    "  --max-memory SIZE     refuse images needing more host memory (default 80 %\n"
    "                        of physical memory)\n"
    "  --report R.json       counts, windows tried, pyramid levels, stage times\n"
    "  --quiet               no progress or notes on stderr\n";

enum {
    IF_WINDOW = OPT_COMMAND, IF_MIN_WINDOW, IF_ATLAS, IF_TAU, IF_SEARCH_RADIUS, IF_EXHAUSTIVE,
    IF_NO_INTERP, IF_INTERP_DIFF, IF_INTERP_SD
};

/* One of the command's own options: 1 taken, 0 a bad value (said). */
static int own_option(int c, const char *arg, relief_image_fill_params *p, int *window_set,
                      int *min_window_set, int *atlas)
{
    const char *cmd = "image-fill";
    switch (c) {
    case IF_WINDOW: *window_set = 1; return cli_parse_int(cmd, "--window", arg, &p->window);
    case IF_MIN_WINDOW:
        *min_window_set = 1;
        return cli_parse_int(cmd, "--min-window", arg, &p->min_window);
    case IF_ATLAS: *atlas = 1; return 1;
    case IF_TAU: return cli_parse_real(cmd, "--tau", arg, &p->tau);
    case IF_SEARCH_RADIUS:
        return cli_parse_int(cmd, "--search-radius", arg, &p->search_radius);
    case IF_EXHAUSTIVE: p->exhaustive = 1; return 1;
    case IF_NO_INTERP: p->interp = 0; return 1;
    case IF_INTERP_DIFF: return cli_parse_real(cmd, "--interp-diff", arg, &p->interp_diff);
    case IF_INTERP_SD: return cli_parse_real(cmd, "--interp-sd", arg, &p->interp_sd);
    }
    fprintf(stderr, "Try 'relief image-fill --help'.\n");
    return 0;
}

/* The options into cm and p. Returns -1 to go on, else the exit status. */
static int parse(int argc, char **argv, cli_common *cm, relief_image_fill_params *p)
{
    static const struct option own[] = {
        {"window", required_argument, 0, IF_WINDOW},
        {"min-window", required_argument, 0, IF_MIN_WINDOW},
        {"atlas", no_argument, 0, IF_ATLAS},
        {"tau", required_argument, 0, IF_TAU},
        {"search-radius", required_argument, 0, IF_SEARCH_RADIUS},
        {"exhaustive", no_argument, 0, IF_EXHAUSTIVE},
        {"no-interp", no_argument, 0, IF_NO_INTERP},
        {"interp-diff", required_argument, 0, IF_INTERP_DIFF},
        {"interp-sd", required_argument, 0, IF_INTERP_SD},
        {0, 0, 0, 0}};
    struct option opts[32];
    int c, window_set = 0, min_window_set = 0, atlas = 0;

    cli_options(CLI_ENGINE | CLI_MASK, own, opts, sizeof opts / sizeof opts[0]);
    optind = 0;
    while ((c = getopt_long(argc, argv, "o:h", opts, NULL)) != -1) {
        int taken = cli_common_option(cm, c, optarg);
        if (taken < 0)
            return EXIT_USAGE;
        if (c == 'h') {
            fputs(image_fill_help, stdout);
            return 0;
        }
        if (!taken && !own_option(c, optarg, p, &window_set, &min_window_set, &atlas))
            return EXIT_USAGE;
    }
    /* Paper 004's windows for atlases, unless given. */
    if (atlas && !window_set)
        p->window = 129;
    if (atlas && !min_window_set)
        p->min_window = 9;
    if (cm->seed_given)
        p->seed = cm->seed;
    p->run.backend = cm->run.backend;
    p->run.device = cm->run.device;
    p->run.max_memory = cm->run.max_memory;
    return -1;
}

/* Does `path` end in .png, .jpg or .jpeg? 2 for JPEG. */
static int image_ext(const char *path)
{
    const char *e = cli_ext_of(path);
    if (strcasecmp(e, ".png") == 0)
        return 1;
    return strcasecmp(e, ".jpg") == 0 || strcasecmp(e, ".jpeg") == 0 ? 2 : 0;
}

/* The filled image and the report (with the mask's name), both or none. */
static relief_status write_outputs(const cli_common *cm, const relief_image *img,
                                   const relief_image_fill_report *rep, relief_error *err)
{
    static const char *const keys[] = {"mask"};
    const char *values[] = {cm->mask};
    relief_status st;
    sigset_t held;
    cli_hold_signals(&held);
    st = relief_image_write(img, cm->out, err);
    if (st == RELIEF_OK && cm->report) {
        st = cli_write_json(cm->report, rep->json, 1, keys, values, err);
        if (st != RELIEF_OK)
            remove(cm->out); /* all outputs or none */
    }
    cli_release_signals(&held);
    return st;
}

/* What the fill did, on stderr. */
static void summary(const cli_common *cm, const char *in, const relief_image_fill_report *r)
{
    if (cm->quiet)
        return;
    if (r->backend_note[0])
        fprintf(stderr, "relief image-fill: %s\n", r->backend_note);
    if (r->hole_pixels == 0)
        fprintf(stderr, "relief image-fill: %s: no hole pixels (%s): writing the image "
                "unchanged\n", in, cm->mask ? "the mask is all zero" : "no pixel is "
                "transparent");
    else
        fprintf(stderr, "relief image-fill: %zu hole pixels: %zu by rows, %zu by columns, %zu "
                "copied (%zu of %zu windows accepted), %zu by the fallback; %.2f s on %s\n",
                r->hole_pixels, r->by_rows, r->by_columns, r->by_copy, r->windows_accepted,
                r->windows_tried, r->by_fallback, r->seconds_total, r->device);
}

/* Read IN and MASK, fill, write OUT and the report. */
static int run(const cli_common *cm, const char *in, relief_image_fill_params *p)
{
    relief_image img = {0, 0, 0, 0, 0, NULL}, mask = {0, 0, 0, 0, 0, NULL};
    relief_image_fill_report rep;
    relief_error err = {RELIEF_OK, ""};
    uint64_t limit = cm->run.max_memory ? cm->run.max_memory : relief_default_memory_limit();
    cli_progress pr;
    relief_status st = relief_image_read(in, limit, &img, &err);
    int rc = 0;

    if (st == RELIEF_OK && cm->mask)
        st = relief_image_read(cm->mask, limit, &mask, &err);
    if (st == RELIEF_OK && image_ext(cm->out) == 2 && img.bit_depth != 8)
        st = relief_fail(&err, RELIEF_E_FORMAT, "%s has 16 bits per channel and JPEG holds 8: "
                         "write OUT as .png", in);
    if (st == RELIEF_OK) {
        p->run.input_name = in;
        p->run.output_name = cm->out;
        p->run.progress = cli_progress_fn;
        p->run.progress_ctx = &pr;
        cli_progress_start(&pr, cm->cmd, cm->quiet);
        st = relief_image_fill(&img, cm->mask ? &mask : NULL, p, &rep, &err);
        cli_progress_end(&pr);
        if (st == RELIEF_OK) {
            st = write_outputs(cm, &img, &rep, &err);
            if (st == RELIEF_OK)
                summary(cm, in, &rep);
            relief_image_fill_report_free(&rep);
        }
    }
    if (st != RELIEF_OK)
        rc = cli_fail(cm->cmd, &err);
    relief_image_free(&img);
    relief_image_free(&mask);
    return rc;
}

int cli_cmd_image_fill(int argc, char **argv, int parse_only)
{
    cli_common cm = cli_common_init("image-fill");
    relief_image_fill_params p = relief_image_fill_params_default();
    relief_error err = {RELIEF_OK, ""};
    const char *in = NULL;
    int rc = parse(argc, argv, &cm, &p);

    if (rc >= 0)
        return rc;
    if (!cli_one_input(&cm, argc, argv, "input image IN", &in))
        return EXIT_USAGE;
    if (!image_ext(cm.out))
        return cli_usage_error(cm.cmd, "-o: '%s' does not end in .png, .jpg or .jpeg",
                               cm.out);
    if (relief_image_fill_params_validate(&p, &err) != RELIEF_OK)
        return cli_fail(cm.cmd, &err);
    {
        const char *ins[] = {in, cm.mask}, *outs[] = {cm.out, cm.report};
        if (cli_outputs_clash(cm.cmd, ins, 2, outs, 2))
            return EXIT_USAGE;
    }
    if (parse_only)
        return 0;
    return run(&cm, in, &p);
}
