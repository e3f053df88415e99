/* relief devices: the OpenCL devices relief can use. */
#include "cli/commands.h"

#include <getopt.h>
#include <stdio.h>

#include "relief/relief.h"
#include "cli/options.h"

static const cli_spec spec = {
    "devices", "", "List the OpenCL platforms and devices relief can use, with their compute "
    "units and memory.", 0, NULL, NULL, NULL, 0, NULL, NULL, NULL};

int cli_cmd_devices(int argc, char **argv, int parse_only)
{
    cli_common cm = cli_common_init("devices");
    relief_device_info dev[64];
    relief_error err = {0};
    size_t n = 0;
    int rc = cli_parse(&spec, &cm, NULL, NULL, NULL, argc, argv);

    if (rc)
        return rc < 0 ? 0 : rc;
    if (optind < argc)
        return cli_usage_error("devices", "unexpected argument '%s'", argv[optind]);
    if (parse_only)
        return 0;
    if (relief_devices(dev, sizeof dev / sizeof dev[0], &n, &err) != RELIEF_OK)
        return cli_fail("devices", &err);
    if (n == 0) {
        printf("no OpenCL platform or device found; --backend auto scores on the host's threads\n");
        return 0;
    }
    for (size_t i = 0; i < n && i < sizeof dev / sizeof dev[0]; ++i)
        printf("device %d: %s [%s] on %s\n"
               "          %s, driver %s, %u compute units, %.1f GiB global memory, "
               "%.1f GiB max buffer\n",
               dev[i].index, dev[i].name, dev[i].type, dev[i].platform, dev[i].version,
               dev[i].driver, dev[i].compute_units,
               (double)dev[i].global_mem_bytes / 1073741824.0,
               (double)dev[i].max_alloc_bytes / 1073741824.0);
    return 0;
}
