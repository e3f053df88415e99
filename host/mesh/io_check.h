/* Structural check of a mesh file before OpenMesh reads it.
 *
 * OpenMesh's readers say little when a file is wrong (often only "could not
 * read"), and drop bad faces silently. This pass reads the file's structure
 * itself so that an error can name the line (ascii formats) or the element
 * and byte counts (binary formats): bad magic, bad header, truncation,
 * non-numeric or non-finite coordinates, faces with fewer than three
 * corners, indices out of range or repeated. It does not build a mesh. */
#ifndef RELIEF_HOST_IO_CHECK_H
#define RELIEF_HOST_IO_CHECK_H

#include "relief/relief.h"

typedef enum relief_file_format {
    RELIEF_FILE_PLY,
    RELIEF_FILE_OBJ,
    RELIEF_FILE_OFF,
    RELIEF_FILE_STL,
    RELIEF_FILE_UNKNOWN
} relief_file_format;

typedef struct relief_file_check {
    relief_file_format format;
    const char *ext;          /* ".ply", ".obj", ".off", ".stl" */
    int binary;               /* 1: binary PLY, OFF or STL */
    long long vertices;       /* declared or counted vertices; -1 unknown */
    long long faces;          /* declared or counted faces; -1 unknown */
    int ascii_char_label;     /* ascii PLY with a char-typed `label` */
} relief_file_check;

/* Format by the path's extension, case-insensitive; RELIEF_FILE_UNKNOWN if
 * none of .ply .obj .off .stl. */
relief_file_format relief_file_format_of(const char *path);

/* Check `path`'s structure; fills `out` on success. */
relief_status relief_io_check(const char *path, relief_file_check *out,
                              relief_error *err);

#endif
