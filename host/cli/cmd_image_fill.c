/* relief image-fill: hole filling in images (paper 004), a client of
 * relief_image_fill (relief/image.h): options, the files, the summary. */
#include "cli/commands.h"

#include <getopt.h>
#include <stdio.h>
#include <strings.h>

#include "relief/relief.h"
#include "base/error.h"
#include "base/memlimit.h"
#include "cli/batch.h"
#include "cli/options.h"
#include "image/image_io.h"

enum { IF_ATLAS = OPT_COMMAND };

static const cli_own own[] = {
    {"atlas", IF_ATLAS, NULL, "texture atlases: --window 129 --min-window 9 (paper 004), "
     "unless given"},
    {NULL, 0, NULL, NULL}};

static cli_spec spec(void)
{
    cli_spec s = {"image-fill", "IN -o OUT [--mask MASK] [options]",
                  "Fill the holes of an image (paper 004): a 1-D interpolation pass along "
                  "rows and columns where a gap's ends agree, then copy-paste synthesis of "
                  "windows matched over a Gaussian pyramid. IN is PNG (8 or 16 bits, grey, "
                  "RGB, with or without alpha) or JPEG; the hole is MASK's non-zero pixels, "
                  "or IN's transparent pixels without --mask. OUT is PNG or JPEG by its "
                  "extension; pixels outside the hole are written back unchanged.",
                  CLI_OUTPUT | CLI_REPORT | CLI_QUIET | CLI_MASK | CLI_LIMIT,
                  "the filled image; required, never IN",
                  "PNG or JPEG of IN's size: non-zero = hole", NULL, 0, NULL, own, NULL};
    s.params = relief_image_fill_param_table(&s.n_params);
    return s;
}

typedef struct image_args {
    int atlas;
} image_args;

static int take(void *ctx, int id, const char *arg)
{
    (void)arg;
    ((image_args *)ctx)->atlas = id == IF_ATLAS;
    return 1;
}

/* The options into cm and p. Returns -1 to go on, else the exit status. */
static int parse(int argc, char **argv, cli_common *cm, relief_image_fill_params *p)
{
    const cli_spec s = spec();
    image_args a = {0};
    int rc = cli_parse(&s, cm, p, take, &a, argc, argv);
    if (rc)
        return rc < 0 ? 0 : rc;
    /* Paper 004's windows for atlases, unless given (in any spelling). */
    if (a.atlas && !cli_param_given(cm, &s, "window"))
        p->window = 129;
    if (a.atlas && !cli_param_given(cm, &s, "min_window"))
        p->min_window = 9;
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

/* What write_one writes: the filled image and the report, with the
 * mask's name. */
typedef struct image_out {
    const cli_common *cm;
    const relief_image *img;
    const char *json;
} image_out;

static relief_status write_one(void *ctx, size_t i, relief_sink *s, relief_error *err)
{
    static const char *const keys[] = {"mask"};
    const image_out *o = ctx;
    return i == 0 ? relief_image_write_to(s, o->img, err)
                  : cli_json_to(s, o->json, 1, keys, &o->cm->mask, err);
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
    else if (r->em_steps)
        fprintf(stderr, "relief image-fill: %zu hole pixels: %zu by rows, %zu by columns, %zu "
                "voted (%d levels, %zu vote-and-search steps); %.2f s on %s\n", r->hole_pixels,
                r->by_rows, r->by_columns, r->by_copy, r->pyramid_levels, r->em_steps,
                r->seconds_total, r->device);
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
    relief_error err = {0};
    uint64_t limit = p->run.max_memory ? p->run.max_memory : relief_default_memory_limit();
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
        cli_progress_start(&pr, cm, &p->run);
        st = relief_image_fill(&img, cm->mask ? &mask : NULL, p, &rep, &err);
        cli_progress_end(&pr);
        cli_progress_explain(&pr, st, &err);
        if (st == RELIEF_OK) {
            const cli_output outs[] = {{"-o", cm->out, CLI_OUT_FILE},
                                       {"--report", cm->report, CLI_OUT_FILE}};
            image_out o = {cm, &img, rep.json};
            st = cli_write_outputs(outs, 2, write_one, &o, NULL, &err);
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

/* The parsed command line: what the run on each input takes. */
typedef struct image_job {
    cli_common cm;
    relief_image_fill_params p;
} image_job;

/* One input with j's options: the checks, then, unless parse_only, the
 * run. Returns the exit status. */
static int one(image_job *j, const char *in, int parse_only)
{
    relief_error err = {0};
    const char *ins[] = {in, j->cm.mask};
    const cli_output outs[] = {{"-o", j->cm.out, CLI_OUT_FILE},
                               {"--report", j->cm.report, CLI_OUT_FILE}};
    if (!image_ext(j->cm.out))
        return cli_usage_error(j->cm.cmd, "-o: '%s' does not end in .png, .jpg or .jpeg",
                               j->cm.out);
    if (relief_image_fill_params_validate(&j->p, &err) != RELIEF_OK)
        return cli_fail(j->cm.cmd, &err);
    const int check_rc = cli_check_outputs(j->cm.cmd, ins, 2, outs, 2);
    if (check_rc)
        return check_rc;
    return parse_only ? 0 : run(&j->cm, in, &j->p);
}

/* A batch's run on one input (batch.h): a copy of the job, quiet. */
static int batch_one(const void *job, const char *in, const char *out)
{
    image_job j = *(const image_job *)job;
    j.cm.out = out, j.cm.quiet = 1;
    return one(&j, in, 0);
}

int cli_cmd_image_fill(int argc, char **argv, int parse_only)
{
    image_job j = {cli_common_init("image-fill"), relief_image_fill_params_default()};
    const char *in = NULL;
    int rc = parse(argc, argv, &j.cm, &j.p);
    if (rc >= 0)
        return rc;
    if (cli_batch_asked(&j.cm, argc)) {
        const cli_batch b = {NULL, batch_one, &j, {{"--report", j.cm.report}}};
        return cli_batch_run(&j.cm, &b, argv + optind, argc - optind, parse_only);
    }
    if (!cli_one_input(&j.cm, argc, argv, "input image IN", &in))
        return EXIT_USAGE;
    return one(&j, in, parse_only);
}
