#include "base/file.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "base/error.h"

relief_status relief_read_file(const char *path, uint8_t **data, size_t *n, relief_error *err)
{
    FILE *f = fopen(path, "rb");
    uint8_t *d = NULL;
    size_t len = 0, cap = 0;

    *data = NULL;
    *n = 0;
    if (!f)
        return relief_fail(err, RELIEF_E_IO, "%s: cannot open: %s", path, strerror(errno));
    for (;;) {
        size_t got;
        if (cap - len < 2) {
            uint8_t *grown;
            cap = cap ? 2 * cap : 1 << 16;
            grown = realloc(d, cap);
            if (!grown) {
                free(d);
                fclose(f);
                return relief_fail(err, RELIEF_E_NOMEM, "%s: cannot hold the file", path);
            }
            d = grown;
        }
        got = fread(d + len, 1, cap - len - 1, f);
        len += got;
        if (got == 0)
            break;
    }
    if (ferror(f)) {
        int e = errno;
        free(d);
        fclose(f);
        return relief_fail(err, RELIEF_E_IO, "%s: cannot read: %s", path, strerror(e));
    }
    fclose(f);
    d[len] = '\0';
    *data = d;
    *n = len;
    return RELIEF_OK;
}
