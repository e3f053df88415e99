/* Whole files into memory, for the readers that decode from a buffer (the
 * image and depth readers, whose fuzz harnesses feed them bytes). */
#ifndef RELIEF_HOST_FILE_H
#define RELIEF_HOST_FILE_H

#include <stddef.h>
#include <stdint.h>

#include "relief/relief.h"

/* Read all of `path` into *data (malloc'ed, the caller frees it; one byte
 * more than *n, a NUL, so that text parsers may stop on it) and *n.
 * RELIEF_E_IO naming the path and the system's reason; RELIEF_E_NOMEM. */
relief_status relief_read_file(const char *path, uint8_t **data, size_t *n, relief_error *err);

#endif
