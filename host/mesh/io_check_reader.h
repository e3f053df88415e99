/* The line reader and the checks relief_io_check's format checkers share
 * (io_check.c: OFF, OBJ, STL and the entry; io_check_ply.c: PLY). Internal
 * to mesh/: each error names the file and the line. */
#ifndef RELIEF_HOST_IO_CHECK_READER_H
#define RELIEF_HOST_IO_CHECK_READER_H

#include <stdio.h>

#include "relief/relief.h"
#include "mesh/io_check.h"

#define MAX_TOKENS 64

typedef struct reader {
    FILE *f;
    const char *path;
    char *line;
    size_t cap;
    long lineno;
    char *tok[MAX_TOKENS];
    int ntok;
    long nul_line; /* first line holding a NUL byte, 0 if none */
} reader;

/* Next line split into whitespace tokens; '#' starts a comment when
 * `comments` is set. 0 at end of file or at a NUL byte (r->nul_line). */
int io_next_line(reader *r, int comments);
/* The next line with at least one token. */
int io_next_nonblank(reader *r, int comments);
/* A whole token as a double / a long long; 0 when it is not one. A double
 * is written with '.' whatever the caller's locale ("0.5", as every mesh
 * format has it). */
int io_parse_double(const char *s, double *out);
int io_parse_long(const char *s, long long *out);
/* Three finite coordinates in tokens first..first+2 of the line. */
relief_status io_check_coords(reader *r, int first, const char *what, long long index,
                              relief_error *err);
/* Face corners, 0-based, against the vertex count and for repeats. */
relief_status io_check_corners(const reader *r, const long long *idx, int n, long long face,
                               long long nv, relief_error *err);
/* The PLY checker (io_check_ply.c); fsize: the file's bytes. */
relief_status io_check_ply(reader *r, relief_file_check *out, long long fsize,
                           relief_error *err);

#endif
