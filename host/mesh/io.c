/* Mesh I/O: structural check, OpenMesh read, validation; whole writes. */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/output.h"
#include "base/error.h"
#include "mesh/io_check.h"
#include "mesh/io_openmesh.h"
#include "mesh/mesh.h"
#include "mesh/repair.h"

/* Prefix the file name to err's message: the mesh checks know only the
 * mesh. Returns st. */
static relief_status name_file(relief_status st, const char *path, relief_error *err)
{
    char msg[RELIEF_ERROR_MESSAGE_MAX];
    snprintf(msg, sizeof msg, "%s", err ? err->message : "");
    return relief_fail(err, st, "%s: %s", path, msg);
}

relief_status relief_mesh_read(const char *path, relief_mesh **out,
                               relief_read_info *info, relief_error *err)
{
    RELIEF_ENTRY_ERR(err);
    return relief_mesh_read_with(path, NULL, out, info, err);
}

relief_status relief_mesh_read_with(const char *path, const relief_read_options *opts,
                                    relief_mesh **out, relief_read_info *info,
                                    relief_error *err)
{
    RELIEF_ENTRY_ERR(err);
    relief_file_check chk;
    relief_om_read_result res;
    relief_mesh *m = NULL;
    relief_status st;
    relief_repair_info rep;

    if (!path || !out)
        return relief_fail(err, RELIEF_E_USAGE, "relief_mesh_read: NULL argument");
    st = relief_io_check(path, &chk, err);
    if (st != RELIEF_OK)
        return st;
    st = relief_om_read(path, chk.ext, chk.binary, chk.ascii_char_label, &m, &res, err);
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
    if (st == RELIEF_OK && (st = relief_mesh_validate(m, err)) != RELIEF_OK)
        name_file(st, path, err);
    if (st == RELIEF_OK && (st = relief_mesh_check_range(m, err)) != RELIEF_OK)
        name_file(st, path, err);
    memset(&rep, 0, sizeof rep);
    /* OpenMesh added the file's faces in order when it flagged none: then
     * only a step that changes something needs its add_face pass again. */
    if (st == RELIEF_OK && !(opts && opts->raw) &&
        (st = relief_mesh_repair_impl(m, &rep, res.nonmanifold_faces > 0, err)) != RELIEF_OK)
        name_file(st, path, err);
    /* Again on what the repair kept: welding and dropping can leave a vertex
     * that much farther out than the rest (fuzz_read_stl found one), and a
     * mesh read must pass the check relief_mesh_repair makes of it. */
    if (st == RELIEF_OK && (st = relief_mesh_check_range(m, err)) != RELIEF_OK)
        name_file(st, path, err);
    if (st != RELIEF_OK) {
        relief_mesh_destroy(m);
        return st;
    }
    if (info) {
        memset(info, 0, sizeof *info);
        snprintf(info->format, sizeof info->format, "%s", chk.ext + 1);
        info->binary = chk.binary;
        info->nonmanifold_triangles = res.nonmanifold_faces;
        info->repair = rep;
        info->repaired = relief_repair_info_describe(&rep, NULL, 0) > 0;
    }
    *out = m;
    return RELIEF_OK;
}

/* What mesh_sink writes. */
typedef struct mesh_job {
    const relief_mesh *mesh;
    const relief_write_options *opts;
} mesh_job;

relief_status relief_mesh_write_to(const relief_mesh *mesh, relief_sink *s,
                                   const relief_write_options *opts, relief_error *err)
{
    static const char *const exts[] = {".ply", ".obj", ".off", ".stl"};
    relief_file_format fmt = relief_file_format_of(s->path);
    relief_status st;
    if (fmt == RELIEF_FILE_UNKNOWN)
        return relief_fail(err, RELIEF_E_FORMAT,
                           "%s: unknown output format; expected a name ending in .ply, "
                           ".obj, .off or .stl",
                           s->path);
    if ((st = relief_mesh_validate(mesh, err)) != RELIEF_OK)
        return st;
    return relief_om_write(mesh, s->f, s->path, exts[fmt], opts ? opts->ascii : 0, err);
}

static relief_status mesh_sink(relief_sink *s, void *ctx, relief_error *err)
{
    const mesh_job *job = ctx;
    return relief_mesh_write_to(job->mesh, s, job->opts, err);
}

relief_status relief_mesh_write(const relief_mesh *mesh, const char *path,
                                const relief_write_options *opts,
                                relief_error *err)
{
    mesh_job job = {mesh, opts};
    RELIEF_ENTRY_ERR(err);
    if (!mesh || !path)
        return relief_fail(err, RELIEF_E_USAGE, "relief_mesh_write: NULL argument");
    /* Refused before any file is made: an unknown extension, a bad mesh. */
    if (relief_file_format_of(path) == RELIEF_FILE_UNKNOWN)
        return relief_fail(err, RELIEF_E_FORMAT,
                           "%s: unknown output format; expected a name ending in .ply, "
                           ".obj, .off or .stl",
                           path);
    if (relief_mesh_validate(mesh, err) != RELIEF_OK)
        return err->status;
    return relief_output_file(path, mesh_sink, &job, err);
}
