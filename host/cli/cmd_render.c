/* relief render: a shaded picture of a mesh (report/render.h). */
#include "cli/commands.h"

#include <errno.h>
#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "relief/relief.h"
#include "base/error.h"
#include "base/numtext.h"
#include "cli/options.h"
#include "report/png.h"
#include "report/render.h"

enum { RE_VIEW = OPT_COMMAND, RE_SIZE, RE_COLOUR_BY };

static const cli_own own[] = {
    {"view", RE_VIEW, "AZ,EL", "camera direction from the object, degrees: azimuth about +z "
     "from +x, elevation -90..90 above the xy plane (default: facing the captured part, "
     "turned 25 and 20 degrees so that relief shows)"},
    {"size", RE_SIZE, "WxH", "pixels, 1..8192 each (default 800x600)"},
    {"colour-by", RE_COLOUR_BY, "C", "colour: the mesh's colours; label: captured grey, "
     "completed orange; displacement: height above (red) or below (blue) a primitive fitted "
     "to the captured part; none: grey; auto (default): colour, else label, else none"},
    {NULL, 0, NULL, NULL}};

static const cli_spec spec = {
    "render", "MESH -o OUT.png [--view AZ,EL] [--size WxH] "
    "[--colour-by auto|label|colour|displacement|none]",
    "Render MESH shaded (z-buffer, one light, per-vertex colour) into a PNG, headless.",
    CLI_OUTPUT, "the image; required", NULL, NULL, 0, NULL, own, NULL};

/* "WxH" into two sides. */
static int parse_size(const char *s, int *w, int *h)
{
    char *end;
    const char *second;
    long a, b;
    errno = 0;
    a = strtol(s, &end, 10);
    if (end == s || (*end != 'x' && *end != 'X'))
        goto bad;
    second = end + 1;
    b = strtol(second, &end, 10);
    if (end == second || *end != '\0' || errno != 0)
        goto bad;
    if (a < 1 || b < 1 || a > RELIEF_RENDER_MAX_SIDE || b > RELIEF_RENDER_MAX_SIDE) {
        fprintf(stderr, "relief render: --size: %ldx%ld is out of range: expected 1..%d "
                "pixels per side\n", a, b, RELIEF_RENDER_MAX_SIDE);
        return 0;
    }
    *w = (int)a;
    *h = (int)b;
    return 1;
bad:
    fprintf(stderr, "relief render: --size: '%s' is not WIDTHxHEIGHT in pixels (e.g. "
            "800x600)\nTry 'relief render --help'.\n", s);
    return 0;
}

/* "AZ,EL" in degrees. */
static int parse_view(const char *s, double *az, double *el)
{
    char *end;
    const char *second;
    errno = 0;
    *az = relief_strtod(s, &end);
    if (end == s || *end != ',' || !isfinite(*az))
        goto bad;
    second = end + 1;
    *el = relief_strtod(second, &end);
    if (end == second || *end != '\0' || errno != 0 || !isfinite(*el))
        goto bad;
    if (*el < -90.0 || *el > 90.0) {
        fprintf(stderr, "relief render: --view: elevation %g is out of range: expected "
                "-90..90 degrees\n", *el);
        return 0;
    }
    return 1;
bad:
    fprintf(stderr, "relief render: --view: '%s' is not AZIMUTH,ELEVATION in degrees (e.g. "
            "30,20)\nTry 'relief render --help'.\n", s);
    return 0;
}

/* --view, --size, --colour-by into the options. */
static int take(void *ctx, int id, const char *arg)
{
    static const relief_colour_by bys[] = {RELIEF_COLOUR_BY_AUTO, RELIEF_COLOUR_BY_LABEL,
                                           RELIEF_COLOUR_BY_COLOUR,
                                           RELIEF_COLOUR_BY_DISPLACEMENT, RELIEF_COLOUR_BY_NONE};
    relief_render_options *ro = ctx;
    if (id == RE_VIEW)
        return ro->has_view = parse_view(arg, &ro->azimuth, &ro->elevation);
    if (id == RE_SIZE)
        return parse_size(arg, &ro->width, &ro->height);
    for (size_t i = 0; i < sizeof bys / sizeof bys[0]; ++i)
        if (strcmp(arg, relief_colour_by_name(bys[i])) == 0) {
            ro->colour_by = bys[i];
            return 1;
        }
    cli_usage_error("render", "--colour-by: '%s' is not one of auto, label, colour, "
                    "displacement, none", arg);
    return 0;
}

static relief_status write_png(void *ctx, size_t i, relief_sink *s, relief_error *err)
{
    const relief_rgb_image *img = ctx;
    (void)i;
    return relief_png_write_to(s, img->rgb, img->width, img->height, err);
}

int cli_cmd_render(int argc, char **argv, int parse_only)
{
    cli_common cm = cli_common_init("render");
    relief_render_options ro = relief_render_options_default();
    relief_render_info info;
    relief_error err = {0};
    relief_rgb_image img = {0, 0, NULL};
    relief_mesh *mesh = NULL;
    cli_output out = {"-o", NULL, CLI_OUT_FILE};
    const char *in;
    relief_status st;
    int rc = cli_parse(&spec, &cm, NULL, take, &ro, argc, argv);

    if (rc)
        return rc < 0 ? 0 : rc;
    if (!cli_one_input(&cm, argc, argv, "input MESH", &in))
        return EXIT_USAGE;
    if (strcasecmp(cli_ext_of(cm.out), ".png") != 0)
        return cli_usage_error("render", "-o: '%s' does not end in .png; relief renders PNG "
                           "images", cm.out);
    out.path = cm.out;
    const int check_rc = cli_check_outputs("render", &in, 1, &out, 1);
    if (check_rc)
        return check_rc;
    if (parse_only)
        return 0;
    st = cli_read_mesh("render", in, 0, &mesh, NULL, &err);
    if (st == RELIEF_OK) {
        st = relief_render(mesh, &ro, &img, &info, &err);
        if (st == RELIEF_E_MESH) { /* name the file the mesh came from */
            char why[RELIEF_ERROR_MESSAGE_MAX];
            snprintf(why, sizeof why, "%s", err.message);
            relief_fail(&err, st, "%s: %s", in, why);
        }
    }
    if (st == RELIEF_OK)
        st = cli_write_outputs(&out, 1, write_png, &img, NULL, &err);
    if (st == RELIEF_OK)
        fprintf(stderr, "relief render: %s -> %s (%dx%d, view %.1f,%.1f, colour by %s)\n", in,
                cm.out, img.width, img.height, info.azimuth, info.elevation,
                relief_colour_by_name(info.colour_by));
    relief_rgb_image_free(&img);
    relief_mesh_destroy(mesh);
    return st == RELIEF_OK ? 0 : cli_fail("render", &err);
}
