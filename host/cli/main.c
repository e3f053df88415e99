/* The relief executable: the command line lives in the cli/ library (cli.c
 * dispatches to one file per command). */
#include "cli/cli.h"

#include <signal.h>

int main(int argc, char **argv)
{
    int rc, sig;
    cli_take_signals();
    rc = relief_cli_main(argc, argv, 0);
    /* A signal the command held (its outputs are whole, or none was
     * written): die of it now, as the caller's shell expects of a program
     * it interrupted, so that its loop stops too. */
    if ((sig = cli_signal()) != 0) {
        signal(sig, SIG_DFL);
        raise(sig);
    }
    return rc;
}
