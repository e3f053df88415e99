/* The auto rule (device/device.h). */
#include "device/device.h"

#include <string.h>

int relief_device_is_accelerator(const relief_device_info *info)
{
    return strcmp(info->type, "gpu") == 0 || strcmp(info->type, "accelerator") == 0;
}

int relief_device_first_accelerator(const relief_device_info *info, size_t n)
{
    for (size_t i = 0; i < n; ++i)
        if (relief_device_is_accelerator(&info[i]))
            return (int)i;
    return -1;
}
