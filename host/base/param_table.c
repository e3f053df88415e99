/* Setting and writing parameters by name (relief_param, relief/core.h). */
#include "base/param_table.h"

#include <errno.h>
#include <limits.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "base/error.h"
#include "base/memlimit.h"
#include "base/numtext.h"

const char *const relief_backend_names[] = {"auto", "scalar", "opencl", "host", NULL};

const relief_param *relief_param_find(const relief_param *table, size_t count,
                                      const char *name)
{
    for (size_t i = 0; table && name && i < count; ++i)
        if (strcmp(table[i].name, name) == 0)
            return &table[i];
    return NULL;
}

/* A whole decimal integer in lo..hi. */
static int parse_long(const char *s, long long lo, long long hi, long long *out)
{
    char *end;
    long long v;
    errno = 0;
    v = strtoll(s, &end, 10);
    if (end == s || *end != '\0' || errno != 0 || v < lo || v > hi)
        return 0;
    *out = v;
    return 1;
}

/* A whole finite number, as C writes it ("0.5") whatever the caller's locale. */
static int parse_real(const char *s, double *out)
{
    char *end;
    double v;
    errno = 0;
    v = relief_strtod(s, &end);
    if (end == s || *end != '\0' || errno != 0 || !isfinite(v))
        return 0;
    *out = v;
    return 1;
}

static int parse_flag(const char *s, int *out)
{
    static const char *const yes[] = {"1", "yes", "true", "on"}, *const no[] = {"0", "no",
                                                                              "false", "off"};
    for (int i = 0; i < 4; ++i) {
        if (strcasecmp(s, yes[i]) == 0)
            return *out = 1, 1;
        if (strcasecmp(s, no[i]) == 0)
            return *out = 0, 1;
    }
    return 0;
}

static relief_status set_enum(char *field, const relief_param *p, const char *text,
                              relief_error *err)
{
    char list[512] = "";
    size_t at = 0;
    for (int i = 0; p->names[i]; ++i) {
        if (strcmp(text, p->names[i]) == 0) {
            int v = i;
            memcpy(field, &v, sizeof v);
            return RELIEF_OK;
        }
        at += (size_t)snprintf(list + at, at < sizeof list ? sizeof list - at : 0, "%s%s",
                               i ? ", " : "", p->names[i]);
    }
    return relief_fail(err, RELIEF_E_USAGE, "%s: '%s' is not one of %s", p->name, text, list);
}

static relief_status set_reals(char *params, const relief_param *p, const char *text,
                               relief_error *err)
{
    double v[16];
    char buf[512], *tok, *save = NULL;
    int n = 0, count;
    if (strlen(text) >= sizeof buf)
        return relief_fail(err, RELIEF_E_USAGE, "%s: '%.40s...' is too long", p->name, text);
    snprintf(buf, sizeof buf, "%s", text);
    for (tok = strtok_r(buf, ",", &save); tok; tok = strtok_r(NULL, ",", &save)) {
        if (n == (int)p->max || n == 16)
            return relief_fail(err, RELIEF_E_USAGE, "%s: more than %d values in '%s'", p->name,
                               (int)p->max, text);
        if (!parse_real(tok, &v[n++]))
            return relief_fail(err, RELIEF_E_USAGE, "%s: '%s' is not a finite number",
                               p->name, tok);
    }
    if (n < (int)p->min)
        return relief_fail(err, RELIEF_E_USAGE, "%s: %d value%s in '%s', expected %s", p->name,
                           n, n == 1 ? "" : "s", text, p->value);
    memcpy(params + p->offset, v, (size_t)n * sizeof *v);
    count = p->count_is_flag ? 1 : n;
    memcpy(params + p->count_offset, &count, sizeof count);
    return RELIEF_OK;
}

/* relief_param_set's work: messages start with "NAME: ". */
static relief_status param_set(void *params, const relief_param *p, const char *text,
                               relief_error *err)
{
    char *field;
    long long l;
    field = (char *)params + p->offset;
    switch (p->kind) {
    case RELIEF_PARAM_FLAG: {
        int v;
        if (!parse_flag(text, &v))
            break;
        memcpy(field, &v, sizeof v);
        return RELIEF_OK;
    }
    case RELIEF_PARAM_INT:
        if (!parse_long(text, INT_MIN, INT_MAX, &l))
            return relief_fail(err, RELIEF_E_USAGE, "%s: '%s' is not an integer", p->name,
                               text);
        memcpy(field, &(int){(int)l}, sizeof(int));
        return RELIEF_OK;
    case RELIEF_PARAM_SEED:
        if (!parse_long(text, 0, UINT32_MAX, &l))
            return relief_fail(err, RELIEF_E_USAGE, "%s: '%s' is not an integer in "
                               "0..4294967295", p->name, text);
        memcpy(field, &(uint32_t){(uint32_t)l}, sizeof(uint32_t));
        return RELIEF_OK;
    case RELIEF_PARAM_REAL: {
        double v;
        if (!parse_real(text, &v))
            return relief_fail(err, RELIEF_E_USAGE, "%s: '%s' is not a finite number",
                               p->name, text);
        memcpy(field, &v, sizeof v);
        return RELIEF_OK;
    }
    case RELIEF_PARAM_ENUM: return set_enum(field, p, text, err);
    case RELIEF_PARAM_BYTES: {
        uint64_t v = 0; /* "0": the default limit */
        relief_status st = strcmp(text, "0") == 0 ? RELIEF_OK
                                                  : relief_parse_size(text, &v, err);
        if (st != RELIEF_OK) {
            relief_fail_prefix(err, "%s", p->name);
            return st;
        }
        memcpy(field, &v, sizeof v);
        return RELIEF_OK;
    }
    case RELIEF_PARAM_PATH: memcpy(field, &text, sizeof text); return RELIEF_OK;
    case RELIEF_PARAM_REALS: return set_reals((char *)params, p, text, err);
    }
    return relief_fail(err, RELIEF_E_USAGE, "%s: '%s' is not %s", p->name, text,
                       p->kind == RELIEF_PARAM_FLAG ? "0 or 1 (no or yes)" : "a value");
}

relief_status relief_param_set(void *params, const relief_param *p, const char *text,
                               relief_error *err)
{
    relief_status st;
    RELIEF_ENTRY_ERR(err);
    if (!params || !p || !text)
        return relief_fail(err, RELIEF_E_USAGE, "%s is NULL",
                           !params ? "params" : !p ? "the parameter" : "the text");
    st = param_set(params, p, text, err);
    if (st != RELIEF_OK) {
        err->reason = RELIEF_REASON_PARAMETER;
        snprintf(err->param, sizeof err->param, "%s", p->name);
    }
    return st;
}

size_t relief_param_format(const void *params, const relief_param *p, char *buf, size_t size)
{
    const char *field = (const char *)params + p->offset;
    int i;
    double d;
    uint32_t u;
    uint64_t b;
    const char *s;
    switch (p->kind) {
    case RELIEF_PARAM_FLAG:
    case RELIEF_PARAM_INT:
        memcpy(&i, field, sizeof i);
        return (size_t)snprintf(buf, size, "%d", i);
    case RELIEF_PARAM_SEED:
        memcpy(&u, field, sizeof u);
        return (size_t)snprintf(buf, size, "%u", (unsigned)u);
    case RELIEF_PARAM_REAL:
        memcpy(&d, field, sizeof d);
        return (size_t)relief_snprintf_c(buf, size, "%.17g", d);
    case RELIEF_PARAM_ENUM: {
        int n = 0;
        memcpy(&i, field, sizeof i);
        while (p->names[n])
            ++n;
        return (size_t)snprintf(buf, size, "%s", i >= 0 && i < n ? p->names[i] : "unknown");
    }
    case RELIEF_PARAM_BYTES:
        memcpy(&b, field, sizeof b);
        return (size_t)snprintf(buf, size, "%llu", (unsigned long long)b);
    case RELIEF_PARAM_PATH:
        memcpy(&s, field, sizeof s);
        return (size_t)snprintf(buf, size, "%s", s ? s : "");
    case RELIEF_PARAM_REALS: {
        const char *base = (const char *)params;
        size_t at = 0;
        int n;
        memcpy(&n, base + p->count_offset, sizeof n);
        if (p->count_is_flag && n)
            n = (int)p->max;
        for (int k = 0; k < n; ++k) {
            memcpy(&d, field + (size_t)k * sizeof d, sizeof d);
            at += (size_t)relief_snprintf_c(buf + (at < size ? at : size),
                                            at < size ? size - at : 0, "%s%.17g", k ? "," : "",
                                            d);
        }
        if (size && at == 0)
            buf[0] = '\0';
        return at;
    }
    }
    if (size)
        buf[0] = '\0';
    return 0;
}
