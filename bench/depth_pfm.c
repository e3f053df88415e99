/* The bench's converter: any depth file relief reads (organised PCD of
 * every DATA kind, PFM) to a PFM of its depths (NaN missing as +inf), so
 * that bench/depth_fill.py can hand the same float image to OpenCV.
 *   depth_pfm IN OUT.pfm */
#include <stdio.h>

#include "depth/depth_io.h"

int main(int argc, char **argv)
{
    relief_depth_frame f;
    relief_error err = {RELIEF_OK, ""};
    if (argc != 3) {
        fprintf(stderr, "usage: depth_pfm IN OUT.pfm\n");
        return 2;
    }
    if (relief_depth_read(argv[1], 0, &f, &err) != RELIEF_OK ||
        relief_depth_write(argv[2], &f, RELIEF_DEPTH_PFM, &err) != RELIEF_OK) {
        fprintf(stderr, "depth_pfm: %s\n", err.message);
        relief_depth_frame_free(&f);
        return 1;
    }
    relief_depth_frame_free(&f);
    return 0;
}
