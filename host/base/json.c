#include "base/json.h"

#include <math.h>
#include <stdlib.h>

#include "base/numtext.h"

void rj_init(relief_json *j, FILE *f)
{
    j->f = f;
    j->depth = 0;
    j->count[0] = 0;
}

void rj_put_string(FILE *f, const char *s)
{
    fputc('"', f);
    for (; *s; ++s) {
        unsigned char c = (unsigned char)*s;
        if (c == '"' || c == '\\')
            fprintf(f, "\\%c", c);
        else if (c == '\n')
            fputs("\\n", f);
        else if (c < 0x20)
            fprintf(f, "\\u%04x", c);
        else
            fputc(c, f);
    }
    fputc('"', f);
}

/* Comma, newline and indentation before an item, then its key. */
static void item(relief_json *j, const char *key)
{
    if (j->count[j->depth]++ > 0)
        fputc(',', j->f);
    if (j->depth > 0)
        fprintf(j->f, "\n%*s", 2 * j->depth, "");
    if (key) {
        rj_put_string(j->f, key);
        fputs(": ", j->f);
    }
}

static void open_(relief_json *j, const char *key, char c)
{
    item(j, key);
    fputc(c, j->f);
    if (j->depth + 1 < RELIEF_JSON_MAX_DEPTH)
        j->count[++j->depth] = 0;
}

static void close_(relief_json *j, char c)
{
    int had = j->count[j->depth] > 0;
    if (j->depth > 0)
        --j->depth;
    if (had)
        fprintf(j->f, "\n%*s", 2 * j->depth, "");
    fputc(c, j->f);
    if (j->depth == 0)
        fputc('\n', j->f);
}

void rj_begin_object(relief_json *j, const char *key) { open_(j, key, '{'); }
void rj_end_object(relief_json *j) { close_(j, '}'); }
void rj_begin_array(relief_json *j, const char *key) { open_(j, key, '['); }
void rj_end_array(relief_json *j) { close_(j, ']'); }

void rj_string(relief_json *j, const char *key, const char *value)
{
    item(j, key);
    rj_put_string(j->f, value ? value : "");
}

void rj_number(relief_json *j, const char *key, double value)
{
    item(j, key);
    if (isfinite(value))
        relief_fprintf_c(j->f, "%.10g", value); /* "0.5" whatever the locale */
    else
        fputs("null", j->f);
}

void rj_int(relief_json *j, const char *key, long long value)
{
    item(j, key);
    fprintf(j->f, "%lld", value);
}

void rj_bool(relief_json *j, const char *key, int value)
{
    item(j, key);
    fputs(value ? "true" : "false", j->f);
}

void rj_null(relief_json *j, const char *key)
{
    item(j, key);
    fputs("null", j->f);
}

void rj_vec3(relief_json *j, const char *key, const double v[3])
{
    item(j, key);
    relief_fprintf_c(j->f, "[%.10g, %.10g, %.10g]", v[0], v[1], v[2]);
}

void rj_string_or_null(relief_json *j, const char *key, const char *value)
{
    if (value)
        rj_string(j, key, value);
    else
        rj_null(j, key);
}

char *rj_render(void (*write)(relief_json *j, const void *ctx), const void *ctx,
                const char *end)
{
    char *buf = NULL;
    size_t len = 0;
    FILE *f = open_memstream(&buf, &len);
    relief_json j;
    int bad;
    if (!f)
        return NULL;
    rj_init(&j, f);
    write(&j, ctx);
    fputs(end, f);
    bad = ferror(f);
    if (fclose(f) != 0 || bad) {
        free(buf);
        return NULL;
    }
    return buf;
}
