/* relief_points_read (relief/points.h): a mesh or point file, or a PCD
 * cloud as a point set. */
#include "relief/relief.h"

#include <stdio.h>
#include <string.h>
#include <strings.h>

#include "base/error.h"
#include "depth/depth_io.h"

/* A PCD cloud's finite points; the sensor at the origin, as PCL's
 * VIEWPOINT default has it. */
static relief_status read_pcd(const char *path, uint64_t max_points, relief_mesh **out,
                              relief_points_read_info *info, relief_error *err)
{
    relief_depth_frame f;
    relief_status st = relief_pcd_read_cloud(path, max_points, &f, err);
    if (st != RELIEF_OK)
        return st;
    st = relief_depth_frame_points(&f, path, out, &info->non_finite_dropped, err);
    info->width = (size_t)f.width;
    info->height = (size_t)f.height;
    relief_depth_frame_free(&f);
    snprintf(info->format, sizeof info->format, "pcd");
    info->has_viewpoint = 1;
    return st;
}

relief_status relief_points_read(const char *path, uint64_t max_points, relief_mesh **out,
                                 relief_points_read_info *info, relief_error *err)
{
    RELIEF_ENTRY_ERR(err);
    relief_points_read_info ri;
    relief_mesh *m = NULL;
    relief_status st;
    const char *ext;

    if (!path || !out)
        return relief_fail(err, RELIEF_E_USAGE, "relief_points_read: %s is NULL",
                           !path ? "path" : "out");
    memset(&ri, 0, sizeof ri);
    ext = strrchr(path, '.');
    if (ext && strcasecmp(ext, ".pcd") == 0) {
        st = read_pcd(path, max_points, &m, &ri, err);
    } else {
        /* Raw: the points are the file's vertices, all of them; welding
         * or dropping some for the sake of the triangles would lose
         * samples. */
        relief_read_info mi;
        relief_read_options raw = {1};
        st = relief_mesh_read_with(path, &raw, &m, &mi, err);
        if (st == RELIEF_OK)
            snprintf(ri.format, sizeof ri.format, "%s", mi.format);
    }
    if (st != RELIEF_OK)
        return st;
    *out = m;
    if (info)
        *info = ri;
    return RELIEF_OK;
}
