/* The relief executable: the command line lives in cli.c. */
#include "cli/cli.h"

int main(int argc, char **argv)
{
    return relief_cli_main(argc, argv, 0);
}
