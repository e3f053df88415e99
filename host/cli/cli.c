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
    "Complete the hidden part of a partially captured surface: fit a plane,\n"
    "sphere or cylinder, then grow the capture's relief and colour over the\n"
    "missing part by non-parametric sampling.\n"
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
    "\n"
    "Exit status: 0 success, 1 bad input or usage, 2 internal or device failure.\n";

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
