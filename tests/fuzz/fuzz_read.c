/* libFuzzer harness for one mesh reader: the input's bytes are written to a
 * file named with FUZZ_EXT (".ply", ".obj", ".off" or ".stl", a compile
 * definition) and read through relief_mesh_read, the path every command
 * takes, so the structural check (io_check.c) and OpenMesh both see them.
 *
 * Besides the sanitizers, it checks what the API promises: a read that
 * succeeds gives a mesh that validates (at least one vertex, finite
 * coordinates, triangle indices in range and distinct); a read that fails
 * says why, naming the file, with a status of bad input (exit 1) or out of
 * memory, never an internal error. A broken promise aborts. */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "relief/relief.h"

#ifndef FUZZ_EXT
#error "compile with -DFUZZ_EXT=\".ply\" (or .obj, .off, .stl)"
#endif

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

/* The input file, in a folder of its own made on the first call and removed
 * at exit. A harness is one process reading one input at a time, so this is
 * the one piece of state it keeps. */
static char input_dir[64];
static char input_path[96];

static void remove_input(void)
{
    unlink(input_path);
    rmdir(input_dir);
}

static void fail(const char *what, const char *detail)
{
    fprintf(stderr, "fuzz_read%s: %s: %s\n", FUZZ_EXT, what, detail);
    abort();
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    relief_mesh *mesh = NULL;
    relief_read_info info;
    relief_error err = {0};
    relief_status st;
    FILE *f;

    if (!input_dir[0]) {
        const char *tmp = getenv("TMPDIR");
        snprintf(input_dir, sizeof input_dir, "%s/relief-fuzz-XXXXXX",
                 tmp && strlen(tmp) < 32 ? tmp : "/tmp");
        if (!mkdtemp(input_dir))
            fail("cannot make a temporary folder", input_dir);
        snprintf(input_path, sizeof input_path, "%s/input%s", input_dir, FUZZ_EXT);
        atexit(remove_input);
    }
    f = fopen(input_path, "wb");
    if (!f || (size > 0 && fwrite(data, 1, size, f) != size) || fclose(f) != 0)
        fail("cannot write the input file", input_path);

    st = relief_mesh_read(input_path, &mesh, &info, &err);
    if (st == RELIEF_OK) {
        relief_error verr = {0};
        if (!mesh)
            fail("read succeeded without a mesh", input_path);
        if (relief_mesh_validate(mesh, &verr) != RELIEF_OK)
            fail("read succeeded with an invalid mesh", verr.message);
        if (strcmp(info.format, &FUZZ_EXT[1]) != 0)
            fail("read reports another format", info.format);
        /* The repair's promise: what it gives is manifold, oriented and
         * stored by OpenMesh whole, so a second repair finds nothing. */
        relief_repair_info again;
        char what[512];
        if (relief_mesh_repair(mesh, &again, &verr) != RELIEF_OK)
            fail("the repaired mesh cannot be repaired again", verr.message);
        if (relief_repair_info_describe(&again, what, sizeof what) > 0)
            fail("a second repair changed the mesh", what);
    } else {
        if (mesh)
            fail("read failed but set the mesh", err.message);
        if (err.status != st || strncmp(err.message, input_path, strlen(input_path)) != 0)
            fail("error message does not name the file", err.message);
        if (relief_status_exit_code(st) != 1 && st != RELIEF_E_NOMEM)
            fail("rejected as an internal failure, not as bad input", err.message);
    }
    relief_mesh_destroy(mesh);
    return 0;
}
