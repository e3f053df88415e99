/* The cameras and poses a command reads from files: a pinhole camera as
 * numbers or as Open3D's camera JSON, and the poses of neighbouring views
 * as relative [R | t] lines or as Open3D's trajectory log of camera-to-world
 * poses (RGB-D sequences: Redwood, ICL-NUIM, a SLAM system's output). */
#ifndef RELIEF_HOST_CLI_CAMERA_FILES_H
#define RELIEF_HOST_CLI_CAMERA_FILES_H

#include "relief/relief.h"

/* A pinhole camera; width and height 0 when the source does not say. */
typedef struct cli_camera {
    double k[4]; /* fx, fy, cx, cy in pixels */
    int width, height;
} cli_camera;

/* `arg` is FX,FY,CX,CY: 1 and *c set; anything else is a file's name: 0. */
int cli_camera_numbers(const char *arg, cli_camera *c);

/* Open3D's PinholeCameraIntrinsic JSON (`width`, `height` and
 * `intrinsic_matrix`, the 3 x 3 matrix column by column: fx at 0, fy at 4,
 * cx at 6, cy at 7). RELIEF_E_IO, RELIEF_E_PARSE naming `opt`, the file
 * and what is missing or wrong. */
relief_status cli_read_camera_json(const char *opt, const char *path, cli_camera *c,
                                   relief_error *err);

/* Which entries of a trajectory log are the frame and the views. */
typedef struct cli_pose_pick {
    int frame;       /* the frame's entry, from 0 (default 0) */
    int n_views;     /* views to pose */
    const int *view; /* their entries, or NULL: the entries in order, the
                        frame's left out */
} cli_pose_pick;

/* The views' poses (x_view = R x + t, x in the frame's camera coordinates)
 * from `path`: one line of 12 numbers per view (R row by row, then t; '#'
 * starts a comment), or, told by a first line of 3 whole numbers, Open3D's
 * trajectory log (per entry a line of 3 ids, then 4 rows of a camera-to-
 * world 4 x 4 matrix T), each pose inverse(T_view) T_frame. `pick` is only
 * for a log (*is_log says which it was). RELIEF_E_PARSE naming the file's
 * line; RELIEF_E_USAGE for an entry the log does not hold or a pick given
 * to a file of lines. */
relief_status cli_read_poses(const char *path, const cli_pose_pick *pick, int given_pick,
                             double (*pose)[12], int *is_log, relief_error *err);

#endif
