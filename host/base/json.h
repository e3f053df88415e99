/* A small streaming JSON writer: keys, nesting and commas handled, strings
 * escaped, non-finite numbers written as null (JSON has no NaN). */
#ifndef RELIEF_HOST_JSON_H
#define RELIEF_HOST_JSON_H

#include <stdio.h>

#define RELIEF_JSON_MAX_DEPTH 32

typedef struct relief_json {
    FILE *f;
    int depth;
    int count[RELIEF_JSON_MAX_DEPTH]; /* items written at each depth */
} relief_json;

/* Start writing to f. Each value function takes the key (NULL at the top
 * level and inside arrays). */
void rj_init(relief_json *j, FILE *f);
void rj_begin_object(relief_json *j, const char *key);
void rj_end_object(relief_json *j);
void rj_begin_array(relief_json *j, const char *key);
void rj_end_array(relief_json *j);
void rj_string(relief_json *j, const char *key, const char *value);
void rj_number(relief_json *j, const char *key, double value);
void rj_int(relief_json *j, const char *key, long long value);
void rj_bool(relief_json *j, const char *key, int value);
void rj_null(relief_json *j, const char *key);
/* `s` as a JSON string, quoted and escaped, at the file's position (for
 * writers that splice members into a finished object). */
void rj_put_string(FILE *f, const char *s);
/* `value` as a string, or null when it is NULL. */
void rj_string_or_null(relief_json *j, const char *key, const char *value);
/* A 3-element array of numbers. */
void rj_vec3(relief_json *j, const char *key, const double v[3]);

/* What write(j, ctx) writes (a whole document), then `end`, as a string in
 * memory (free it); NULL when it cannot be had. */
char *rj_render(void (*write)(relief_json *j, const void *ctx), const void *ctx,
                const char *end);

#endif
