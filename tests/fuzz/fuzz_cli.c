/* libFuzzer harness for the command line's parsing: the input is split at
 * NUL bytes into arguments after "relief" (the first is the command) and
 * run through relief_cli_main in parse-only mode, which stops each command
 * before it reads, generates or writes anything. What is exercised: getopt_long
 * and every option's value parser and range check, relief_params_validate,
 * the output name and same-file checks, usage messages and --help. It checks
 * the exit status is one the CLI documents (0, 1 or 2). */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli/cli.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

#define MAX_ARGS 64

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    char *argv[MAX_ARGS + 2];
    char *copy = malloc(size + 1);
    int argc = 0, rc;

    if (!copy)
        return 0;
    memcpy(copy, data, size);
    copy[size] = '\0';
    argv[argc++] = "relief";
    /* Each NUL-terminated piece is one argument; a trailing NUL adds none. */
    for (size_t at = 0; at < size && argc <= MAX_ARGS; at += strlen(copy + at) + 1)
        argv[argc++] = copy + at;
    argv[argc] = NULL;
    rc = relief_cli_main(argc, argv, 1);
    free(copy);
    if (rc < 0 || rc > 2) {
        fprintf(stderr, "fuzz_cli: exit status %d is not 0, 1 or 2\n", rc);
        abort();
    }
    return 0;
}
