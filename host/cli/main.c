/* The relief executable: the command line lives in the cli/ library (cli.c
 * dispatches to one file per command). */
#include "cli/cli.h"

int main(int argc, char **argv)
{
    return relief_cli_main(argc, argv, 0);
}
