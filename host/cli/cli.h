/* The relief command line as a function, so that the executable (main.c)
 * and an in-process harness (tests/fuzz/fuzz_cli.c) run the same code. */
#ifndef RELIEF_HOST_CLI_H
#define RELIEF_HOST_CLI_H

/* Run `relief argv[1] ...` and return its exit status (0 success, 1 bad input
 * or usage, 2 internal or device failure). argv[0] is the program name; GNU
 * getopt may permute argv[1..argc-1]. With `parse_only` set, a command stops
 * after its options and arguments are parsed and checked, before it reads,
 * generates or writes a mesh or queries devices, and returns 0 there; --help
 * still prints. Reentrant: getopt's state is reset by every command. */
int relief_cli_main(int argc, char **argv, int parse_only);

/* Take SIGINT, SIGTERM, SIGHUP and SIGQUIT for the whole command (those
 * the caller ignores stay ignored): the first stops an engine's call at
 * its next progress report, and its outputs are then not written; a
 * second acts as usual (options.c). */
void cli_take_signals(void);

/* The signal that came since, or 0. */
int cli_signal(void);

#endif
