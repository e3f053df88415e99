/* The commands, one file each (cmd_*.c); cli.c dispatches to them. Each
 * takes argv from its own name on, as getopt expects, and follows
 * relief_cli_main's contract (cli.h): exit status, parse_only, reentrant. */
#ifndef RELIEF_HOST_CLI_COMMANDS_H
#define RELIEF_HOST_CLI_COMMANDS_H

int cli_cmd_complete(int argc, char **argv, int parse_only);
int cli_cmd_smooth(int argc, char **argv, int parse_only);
int cli_cmd_cut(int argc, char **argv, int parse_only);
int cli_cmd_synth(int argc, char **argv, int parse_only);
int cli_cmd_fit(int argc, char **argv, int parse_only);
int cli_cmd_eval(int argc, char **argv, int parse_only);
int cli_cmd_render(int argc, char **argv, int parse_only);
int cli_cmd_devices(int argc, char **argv, int parse_only);
int cli_cmd_image_fill(int argc, char **argv, int parse_only);
int cli_cmd_depth_fill(int argc, char **argv, int parse_only);
int cli_cmd_complete_points(int argc, char **argv, int parse_only);
int cli_cmd_occluders(int argc, char **argv, int parse_only);
int cli_cmd_remove_occluders(int argc, char **argv, int parse_only);

#endif
