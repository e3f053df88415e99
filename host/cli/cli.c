/* relief: the command-line tool. One executable, one file per command
 * (cmd_*.c, commands.h) and the parsing they share (options.h);
 * getopt_long options, exit codes 0 (success), 1 (bad input or usage), 2
 * (internal or device failure). Each subcommand sets optind = 0,
 * which makes GNU getopt forget all state from an earlier parse (a pointer
 * into the previous argv among it), so relief_cli_main can run many times in
 * one process (tests/fuzz/fuzz_cli.c). */
#include <stdio.h>
#include <string.h>

#include "relief/relief.h"
#include "cli/cli.h"
#include "cli/commands.h"
#include "cli/options.h"

static const char main_help[] =
    "usage: relief COMMAND [options]\n"
    "\n"
    "Fill what scans, depth frames and photographs miss with detail sampled\n"
    "from the capture itself (non-parametric sampling): a scan's hidden side, a\n"
    "photograph's hole, a depth frame's missing pixels, a point set's hole, the\n"
    "wall behind the things in front of it.\n"
    "\n"
    "commands:\n"
    "  complete IN -o OUT    fit, smooth completion and relief/colour growth\n"
    "  smooth IN -o OUT      fit and smooth completion only\n"
    "  fit IN                fit a primitive and print it\n"
    "  synth KIND -o OUT     write a synthetic partial surface with ground truth\n"
    "  cut IN -o OUT         cut a hole out of a whole mesh, with ground truth\n"
    "  eval COMPLETED        measure a completion\n"
    "  render MESH -o P.png  a shaded picture of a mesh\n"
    "  image-fill IN -o OUT  fill the holes of an image (PNG, JPEG)\n"
    "  depth-fill IN -o OUT  repair the holes of a depth image (PCD, PFM, PNG)\n"
    "  complete-points IN -o OUT.ply\n"
    "                        complete a point set with no primitive under it\n"
    "  occluders IN -o MASK.png\n"
    "                        find the foreground objects of an RGB-D frame from depth\n"
    "  remove-occluders IN -o OUT\n"
    "                        and see the surface behind them, in colour and depth\n"
    "  devices               list OpenCL devices\n"
    "\n"
    "  complete, smooth, image-fill, depth-fill and complete-points take several\n"
    "  inputs with -o OUTDIR/: one run each, every good output kept, a summary.\n"
    "\n"
    "  relief COMMAND --help    options of a command\n"
    "  relief --version         version and build options\n"
    "  relief --man             the manual page, relief(1), in troff\n"
    "\n"
    "Exit status: 0 success, 1 bad input or usage, 2 internal or device failure.\n";

/* Every command, in the order the manual lists them. */
static const char *const commands[] = {
    "complete", "smooth", "fit", "synth", "cut", "eval", "render", "image-fill", "depth-fill",
    "complete-points", "occluders", "remove-occluders", "devices", NULL};

/* relief(1): its head, then each command's section from the command's own
 * spec (--help-man), the same words as its --help. */
static int man_page(void)
{
    int rc = 0;
    printf(".TH RELIEF 1 \"\" \"relief %s\" \"User Commands\"\n"
           ".SH NAME\nrelief \\- fill what scans, depth frames and photographs miss\n"
           ".SH SYNOPSIS\n.B relief\n.I COMMAND\n[options]\n"
           ".SH DESCRIPTION\nrelief fills what a capture misses with detail sampled from the "
           "capture itself (non\\-parametric sampling): a scan's hidden side, a photograph's "
           "hole, a depth frame's missing pixels, a point set's hole, the wall behind the "
           "things in front of it. Each command below is one call of the library, "
           "librelief.\n.SH COMMANDS\n", RELIEF_VERSION_STRING);
    for (const char *const *c = commands; *c && rc == 0; ++c) {
        char *args[] = {"relief", (char *)*c, "--help-man", NULL};
        fflush(stdout);
        rc = relief_cli_main(3, args, 1);
    }
    printf(".SH EXIT STATUS\n0 success; 1 bad input or usage (one line on stderr names what "
           "is wrong; no output is written); 2 an internal or device failure.\n"
           ".SH SEE ALSO\nThe documentation in the source's docs/ folder, one page per "
           "command.\n");
    return rc;
}

int relief_cli_main(int argc, char **argv, int parse_only)
{
    const char *cmd;
    if (argc < 2) {
        fputs(main_help, stderr);
        return EXIT_USAGE;
    }
    cmd = argv[1];
    if (strcmp(cmd, "--help") == 0 || strcmp(cmd, "-h") == 0 || strcmp(cmd, "help") == 0) {
        fputs(main_help, stdout);
        return 0;
    }
    if (strcmp(cmd, "--man") == 0)
        return man_page();
    if (strcmp(cmd, "--version") == 0 || strcmp(cmd, "-V") == 0) {
        printf("relief %s (OpenCL backend: %s)\n", RELIEF_VERSION_STRING,
#ifdef RELIEF_HAVE_OPENCL
               "built"
#else
               "not built"
#endif
        );
        return 0;
    }
    /* Subcommands see argv from their own name on, as getopt expects. */
    if (strcmp(cmd, "complete") == 0)
        return cli_cmd_complete(argc - 1, argv + 1, parse_only);
    if (strcmp(cmd, "smooth") == 0)
        return cli_cmd_smooth(argc - 1, argv + 1, parse_only);
    if (strcmp(cmd, "cut") == 0)
        return cli_cmd_cut(argc - 1, argv + 1, parse_only);
    if (strcmp(cmd, "synth") == 0)
        return cli_cmd_synth(argc - 1, argv + 1, parse_only);
    if (strcmp(cmd, "fit") == 0)
        return cli_cmd_fit(argc - 1, argv + 1, parse_only);
    if (strcmp(cmd, "eval") == 0)
        return cli_cmd_eval(argc - 1, argv + 1, parse_only);
    if (strcmp(cmd, "devices") == 0)
        return cli_cmd_devices(argc - 1, argv + 1, parse_only);
    if (strcmp(cmd, "render") == 0)
        return cli_cmd_render(argc - 1, argv + 1, parse_only);
    if (strcmp(cmd, "image-fill") == 0)
        return cli_cmd_image_fill(argc - 1, argv + 1, parse_only);
    if (strcmp(cmd, "complete-points") == 0)
        return cli_cmd_complete_points(argc - 1, argv + 1, parse_only);
    if (strcmp(cmd, "depth-fill") == 0)
        return cli_cmd_depth_fill(argc - 1, argv + 1, parse_only);
    if (strcmp(cmd, "occluders") == 0)
        return cli_cmd_occluders(argc - 1, argv + 1, parse_only);
    if (strcmp(cmd, "remove-occluders") == 0)
        return cli_cmd_remove_occluders(argc - 1, argv + 1, parse_only);
    fprintf(stderr, "relief: unknown command '%s'\n\n%s", cmd, main_help);
    return EXIT_USAGE;
}
