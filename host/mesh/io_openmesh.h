/* The OpenMesh adapter: the one C++ translation unit of relief (mesh files,
 * the storability check, the collapses of a free-form hierarchy). Every entry
 * point catches every exception and returns a status. OpenMesh reports
 * problems on its global `omerr()` stream; the adapter captures that text
 * for the duration of a call and turns it into the error message, so these
 * functions must not run concurrently with other OpenMesh I/O. */
#ifndef RELIEF_HOST_IO_OPENMESH_H
#define RELIEF_HOST_IO_OPENMESH_H

#include <stdio.h>

#include "relief/relief.h"

#ifdef __cplusplus
extern "C" {
#endif

/* What the adapter found besides the mesh. */
typedef struct relief_om_read_result {
    size_t invalid_index_faces; /* dropped: refer to a vertex that does not exist */
    size_t repeated_vertex_faces; /* dropped: a vertex twice in one face */
    size_t nonmanifold_faces;   /* kept, re-attached to their file vertices */
    size_t polygon_faces_split; /* faces of more than 3 corners, fanned */
    char messages[512];         /* what OpenMesh said, newline-separated */
} relief_om_read_result;

/* Read `path` through OpenMesh; `ext` is ".ply", ".obj", ".off" or ".stl",
 * `binary` 1 for a binary file (io_check tells). `ascii_char_label` tells
 * that the file is an ascii PLY whose `label` property is a char type, which
 * OpenMesh reads as a character code. Numbers are read as "0.5" whatever
 * the program's locale; a text OFF, OBJ or STL under a C++ global locale
 * (std::locale::global) that reads "0,5" is RELIEF_E_USAGE (OpenMesh would
 * misread it).
 * On success `*out` holds positions, triangles and, when the file has them,
 * colours, normals and labels. */
relief_status relief_om_read(const char *path, const char *ext, int binary,
                             int ascii_char_label, relief_mesh **out,
                             relief_om_read_result *res, relief_error *err);

/* Write `m` to the stream `f` through OpenMesh in the format of `ext`, its
 * numbers "0.5" whatever the program's locale (C's or C++'s). `ascii`
 * applies to PLY. Colours go to PLY and OFF, labels to PLY as
 * `property int label`. Messages name `shown`. Writes to f only: the
 * caller checks, syncs and closes it (base/output.h). */
relief_status relief_om_write(const relief_mesh *m, FILE *f, const char *shown,
                              const char *ext, int ascii, relief_error *err);

/* Which of n_extra triangles (n_extra x 3 indices into m's vertices) can
 * be added, in order, to m's own triangles by OpenMesh, which stores (and
 * so writes) only what its add_face accepts: accepted[t] 1 or 0. Adding m's
 * triangles then the accepted ones in the same order gives a mesh that
 * relief_mesh_write can write. RELIEF_E_MESH when m's own triangles are not
 * storable already. */
relief_status relief_om_storable(const relief_mesh *m, const uint32_t *extra, size_t n_extra,
                                 uint8_t *accepted, relief_error *err);

/* Coarsen m's triangulation by half-edge collapses (a progressive mesh's
 * step: the surviving vertices keep their positions and ids), for the
 * hierarchy of a surface with no parameter domain (grow/hierarchy.h).
 *   pos:    nv x 3 positions the geometry tests use (not m->pos: the
 *           hierarchy collapses the smooth base, not the relief on it);
 *   nrm:    nv x 3 unit normals of the surface at those positions;
 *   remove: nv flags: 1 for a vertex to collapse away. On return 1 only for
 *           the vertices removed; a vertex whose every collapse would fold a
 *           triangle over (normal more than 60 degrees off the surface's),
 *           leave an edge longer than max_edge, move the border inward or
 *           break the manifold (OpenMesh's link test) stays, 0.
 * Cheapest collapse first (the longest edge it makes), ties by vertex id;
 * then edges are flipped toward the Delaunay triangulation (opposite
 * angles summing over pi) where the flip folds nothing, so the coarse
 * level is as even as the selection that chose its vertices.
 * *tri (malloc'd, *nt x 3) receives the remaining triangles, on m's vertex
 * ids. RELIEF_E_MESH when m's triangles are not manifold. */
relief_status relief_om_collapse(const relief_mesh *m, const double *pos, const double *nrm,
                                 uint8_t *remove, double max_edge, uint32_t **tri, size_t *nt,
                                 relief_error *err);

#ifdef __cplusplus
}
#endif

#endif
