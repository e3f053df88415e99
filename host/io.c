/* Mesh I/O: structural check, OpenMesh read, validation; atomic writes. */
#define _GNU_SOURCE /* mkstemps */
#include <errno.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "error.h"
#include "io_check.h"
#include "io_openmesh.h"
#include "mesh.h"

relief_status relief_mesh_read(const char *path, relief_mesh **out,
                               relief_read_info *info, relief_error *err)
{
    relief_file_check chk;
    relief_om_read_result res;
    relief_mesh *m = NULL;
    relief_status st;
    size_t degenerate = 0;

    if (!path || !out)
        return relief_fail(err, RELIEF_E_USAGE, "relief_mesh_read: NULL argument");
    st = relief_io_check(path, &chk, err);
    if (st != RELIEF_OK)
        return st;
    st = relief_om_read(path, chk.ext, chk.ascii_char_label, &m, &res, err);
    if (st != RELIEF_OK)
        return st;

    /* What the structural check could not see (binary files) shows up here. */
    if (res.invalid_index_faces > 0)
        st = relief_fail(err, RELIEF_E_MESH,
                         "%s: %zu face(s) could not be added: they refer to vertices "
                         "that do not exist or use a vertex twice",
                         path, res.invalid_index_faces);
    else if (res.repeated_vertex_faces > 0)
        st = relief_fail(err, RELIEF_E_MESH, "%s: %zu face(s) use a vertex twice",
                         path, res.repeated_vertex_faces);
    else if (chk.vertices >= 0 && chk.format != RELIEF_FILE_STL &&
             (long long)m->nv != chk.vertices)
        st = relief_fail(err, RELIEF_E_PARSE,
                         "%s: the file declares %lld vertices but %zu could be read "
                         "(truncated or malformed)",
                         path, chk.vertices, m->nv);
    else if (chk.faces > 0 && m->nt == 0)
        st = relief_fail(err, RELIEF_E_PARSE,
                         "%s: the file declares %lld faces but none could be read%s%s",
                         path, chk.faces, res.messages[0] ? ": " : "", res.messages);
    if (st == RELIEF_OK) {
        st = relief_mesh_validate(m, err);
        if (st != RELIEF_OK) {
            /* Prefix the file name: the validator knows only the mesh. */
            char msg[RELIEF_ERROR_MESSAGE_MAX];
            snprintf(msg, sizeof msg, "%s", err ? err->message : "");
            relief_fail(err, st, "%s: %s", path, msg);
        }
    }
    if (st != RELIEF_OK) {
        relief_mesh_destroy(m);
        return st;
    }
    for (size_t t = 0; t < m->nt; ++t)
        if (relief_mesh_triangle_area(m, t) == 0.0)
            ++degenerate;
    if (info) {
        memset(info, 0, sizeof *info);
        snprintf(info->format, sizeof info->format, "%s", chk.ext + 1);
        info->binary = chk.binary;
        info->nonmanifold_triangles = res.nonmanifold_faces;
        info->degenerate_triangles = degenerate;
    }
    *out = m;
    return RELIEF_OK;
}

relief_status relief_mesh_write(const relief_mesh *mesh, const char *path,
                                const relief_write_options *opts,
                                relief_error *err)
{
    static const char *const exts[] = {".ply", ".obj", ".off", ".stl"};
    relief_file_format fmt;
    char *tmp = NULL;
    size_t len;
    int fd;
    relief_status st;

    if (!mesh || !path)
        return relief_fail(err, RELIEF_E_USAGE, "relief_mesh_write: NULL argument");
    fmt = relief_file_format_of(path);
    if (fmt == RELIEF_FILE_UNKNOWN)
        return relief_fail(err, RELIEF_E_FORMAT,
                           "%s: unknown output format; expected a name ending in .ply, "
                           ".obj, .off or .stl",
                           path);
    st = relief_mesh_validate(mesh, err);
    if (st != RELIEF_OK)
        return st;

    /* A temporary name beside the target keeps the rename on one file
     * system; it ends in the format's extension because OpenMesh picks the
     * writer by extension. */
    len = strlen(path) + 32;
    tmp = malloc(len);
    if (!tmp)
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate a file name");
    snprintf(tmp, len, "%s.tmp-XXXXXX%s", path, exts[fmt]);
    fd = mkstemps(tmp, 4);
    if (fd < 0) {
        st = relief_fail(err, RELIEF_E_IO, "%s: cannot create a temporary file: %s",
                         path, strerror(errno));
        free(tmp);
        return st;
    }
    {
        /* mkstemps makes the file 0600; give it what a plain create would. */
        mode_t mask = umask(0);
        umask(mask);
        if (fchmod(fd, 0666 & ~mask) != 0) { /* not fatal: keep 0600 */
        }
    }
    close(fd);
    st = relief_om_write(mesh, tmp, exts[fmt], opts ? opts->ascii : 0, err);
    if (st == RELIEF_OK && rename(tmp, path) != 0)
        st = relief_fail(err, RELIEF_E_IO, "%s: cannot rename the finished file into "
                         "place: %s", path, strerror(errno));
    if (st != RELIEF_OK)
        unlink(tmp);
    free(tmp);
    return st;
}
