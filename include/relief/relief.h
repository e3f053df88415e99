/* relief: completion of what a capture missed, by non-parametric sampling.
 *
 * Public C API of librelief. Everything here is plain C11: opaque handles,
 * a status enum with relief_strerror(), parameter structs with documented
 * defaults. No C++ type ever appears in a public header.
 *
 * This header includes them all: the core (relief/core.h: status, errors,
 * run options and progress, meshes and their files, synthetic surfaces,
 * devices) and one header per engine (each brings the core with it):
 *   relief/complete.h  relief_complete, relief_smooth, relief_fit (papers 000, 001)
 *   relief/image.h     images, their files, relief_image_fill (paper 004)
 *   relief/depth.h     depth frames, their files, relief_depth_fill (paper 003)
 *   relief/points.h    relief_complete_points (paper 002)
 *   relief/eval.h      relief_eval, the measures of a completion
 * Link with `pkg-config --cflags --libs relief`, or in CMake
 * find_package(relief CONFIG) and target_link_libraries(... relief::relief).
 *
 * The library never writes to stdout or stderr and holds no global state:
 * every entry point may be called from several threads at once on
 * different data, and gives the bytes it gives when the calls are made one
 * after the other.
 *
 * Conventions
 * - Functions that can fail return relief_status and take a trailing
 *   `relief_error *err` (may be NULL) that receives a message naming what
 *   went wrong: the file, the line or element, the parameter and its range.
 * - Outputs (`**out` pointers, files) are written only on success.
 * - Arrays are row-major: "n x 3" means n consecutive triples.
 * - Positions are in the input's units; colours are linear [0, 1] floats.
 */
#ifndef RELIEF_RELIEF_H
#define RELIEF_RELIEF_H

#include "relief/core.h"
#include "relief/complete.h"
#include "relief/image.h"
#include "relief/depth.h"
#include "relief/points.h"
#include "relief/eval.h"
#include "relief/occluders.h"

#endif /* RELIEF_RELIEF_H */
