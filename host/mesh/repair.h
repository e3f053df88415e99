/* Mending a triangle soup as read from a file (relief_mesh_repair in
 * include/relief/core.h) and the range check of its coordinates. */
#ifndef RELIEF_HOST_MESH_REPAIR_H
#define RELIEF_HOST_MESH_REPAIR_H

#include "relief/relief.h"

#ifdef __cplusplus
extern "C" {
#endif

/* relief_mesh_repair; `check_storable` 0 skips OpenMesh's add_face pass when
 * no other step changed anything (the reader knows OpenMesh added the file's
 * faces in order already). */
relief_status relief_mesh_repair_impl(relief_mesh *m, relief_repair_info *info,
                                      int check_storable, relief_error *err);

/* RELIEF_E_MESH naming the first vertex whose coordinate is over 1e30 in
 * magnitude, or, of the vertices over 1e15 times farther from the
 * per-axis median point than the next nearer vertex, the first; such a
 * vertex is a unit or export error, and the geometry stages lose every
 * digit of the rest of the mesh to it. Finite coordinates are assumed
 * (relief_mesh_validate). */
relief_status relief_mesh_check_range(const relief_mesh *m, relief_error *err);

#ifdef __cplusplus
}
#endif

#endif
