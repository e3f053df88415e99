/* The engines' parameter tables (relief_param) against the engines' own
 * checks, through the public API only: every parameter set by name from
 * its text, its default written and read back unchanged, and each range
 * the table states held to _validate: the bounds and the special values
 * accepted, just outside refused naming the parameter, NaN refused, every
 * enumeration name accepted and one past them refused. A table that says
 * one thing while the engine checks another fails here. Each refusal of a
 * value put straight into the struct (a bound's neighbour, NaN, an
 * enumeration past its names, a flag of 2, a list of NaNs) names the
 * table's entry in err.param with RELIEF_REASON_PARAMETER (issue 60 item
 * 4): what a client decides on, never the message. */
#include <float.h>
#include <math.h>
#include <stdlib.h>

#include "api_test.h"

typedef relief_status (*validate_fn)(const void *params, relief_error *err);

/* Room for any engine's params struct, aligned as any of them. */
typedef union buffer {
    long double ld;
    double d;
    uint64_t u;
    void *p;
    unsigned char b[4096];
} buffer;

typedef struct engine {
    const char *name;
    const relief_param *table;
    size_t n;
    size_t size;                       /* of the params struct */
    void (*defaults)(void *params);    /* a fresh params struct */
    void (*prepare)(void *params, const relief_param *p); /* so that the other fields
                                                             allow p's whole range */
    validate_fn validate;
} engine;

/* ---------------------------------------------------------- the engines */

static void complete_defaults(void *p) { *(relief_complete_params *)p = relief_complete_params_default(); }
static relief_status complete_validate(const void *p, relief_error *e) { return relief_complete_params_validate(p, e); }
static void image_defaults(void *p) { *(relief_image_fill_params *)p = relief_image_fill_params_default(); }
/* min_window is at most window: the widest window and the narrowest
 * smallest window let each reach its bounds. */
static void image_prepare(void *p, const relief_param *q)
{
    (void)q;
    ((relief_image_fill_params *)p)->window = 1025;
    ((relief_image_fill_params *)p)->min_window = 3;
}
static relief_status image_validate(const void *p, relief_error *e) { return relief_image_fill_params_validate(p, e); }
static void depth_defaults(void *p) { *(relief_depth_fill_params *)p = relief_depth_fill_params_default(); }
static relief_status depth_validate(const void *p, relief_error *e) { return relief_depth_fill_params_validate(p, e); }
static void points_defaults(void *p) { *(relief_complete_points_params *)p = relief_complete_points_params_default(); }
/* A backend or device is refused with the kd-tree: brute takes them; what
 * colour needs a hole mask. */
static void points_prepare(void *p, const relief_param *q)
{
    relief_complete_points_params *pp = p;
    pp->grid_search = RELIEF_GRID_SEARCH_BRUTE;
    if (strcmp(q->name, "what") == 0) {
        pp->has_hole_ball = 1;
        pp->hole_ball[3] = 1.0;
    }
}
static relief_status points_validate(const void *p, relief_error *e) { return relief_complete_points_params_validate(p, e); }
static void occluder_defaults(void *p) { *(relief_occluder_params *)p = relief_occluder_params_default(); }
/* background mesh needs its mesh: one is there (never read by validate). */
static void occluder_prepare(void *p, const relief_param *q)
{
    static char not_read;
    (void)q;
    ((relief_occluder_params *)p)->background_mesh = (const relief_mesh *)(void *)&not_read;
}
static relief_status occluder_validate(const void *p, relief_error *e) { return relief_occluder_params_validate(p, e); }

/* ------------------------------------------------------------ the checks */

/* Does err name p as the parameter it refused (issue 60 item 4): the
 * reason RELIEF_REASON_PARAMETER and err.param p's name, which a client
 * reads instead of the message? */
static int names_param(const relief_error *err, const relief_param *p)
{
    return err->reason == RELIEF_REASON_PARAMETER && strcmp(err->param, p->name) == 0;
}

/* v as relief reads it ("0.5"), whatever this program's locale: under
 * tests/comma_locale.sh its own printf writes "0,5". */
static void set_number(void *params, const relief_param *p, double v)
{
    char text[64], *comma;
    relief_error err = {0};
    if (p->kind == RELIEF_PARAM_REAL)
        snprintf(text, sizeof text, "%.17g", v);
    else
        snprintf(text, sizeof text, "%.0f", v);
    if ((comma = strchr(text, ',')) != NULL)
        *comma = '.';
    CHECK_STATUS(relief_param_set(params, p, text, &err), RELIEF_OK, err, NULL);
}

/* params with p set to v must be accepted (ok) or refused naming p. */
static void expect(const engine *e, const relief_param *p, double v, int ok)
{
    buffer buf;
    unsigned char *params = buf.b;
    relief_error err = {0};
    relief_status st;
    e->defaults(params);
    if (e->prepare)
        e->prepare(params, p);
    set_number(params, p, v);
    st = e->validate(params, &err);
    if (ok)
        CHECK(st == RELIEF_OK, "%s: %s = %.17g refused: %s", e->name, p->name, v, err.message);
    else
        CHECK(st == RELIEF_E_RANGE && strstr(err.message, p->name), "%s: %s = %.17g: %s (%s)",
              e->name, p->name, v, relief_status_name(st), err.message);
}

/* v put straight into p's field, as a caller fills the struct (no text, so
 * relief_param_set names nothing): an int (a flag, an enumeration), a
 * double. */
static void put(void *params, const relief_param *p, double v)
{
    unsigned char *field = (unsigned char *)params + p->offset;
    if (p->kind == RELIEF_PARAM_REAL) {
        memcpy(field, &v, sizeof v);
    } else {
        const int i = (int)v;
        memcpy(field, &i, sizeof i);
    }
}

/* params with p's field set to v in the struct must be refused by
 * _validate with RELIEF_E_RANGE naming p in err.param. */
static void expect_named(const engine *e, const relief_param *p, double v)
{
    buffer buf;
    unsigned char *params = buf.b;
    relief_error err = {0};
    relief_status st;
    e->defaults(params);
    if (e->prepare)
        e->prepare(params, p);
    put(params, p, v);
    st = e->validate(params, &err);
    CHECK(st == RELIEF_E_RANGE && names_param(&err, p),
          "%s: %s = %.17g in the struct: %s, param '%s', reason %s (%s)", e->name, p->name, v,
          relief_status_name(st), err.param, relief_reason_name(err.reason), err.message);
}

/* A list of reals (a ball, a box, a point) given, every value NaN: refused
 * naming it. */
static void expect_reals_named(const engine *e, const relief_param *p)
{
    buffer buf;
    unsigned char *params = buf.b;
    relief_error err = {0};
    relief_status st;
    const double nan = NAN;
    const int count = p->count_is_flag ? 1 : (int)p->max;
    e->defaults(params);
    if (e->prepare)
        e->prepare(params, p);
    for (int i = 0; i < (int)p->max; ++i)
        memcpy(params + p->offset + (size_t)i * sizeof nan, &nan, sizeof nan);
    memcpy(params + p->count_offset, &count, sizeof count);
    st = e->validate(params, &err);
    CHECK(st == RELIEF_E_RANGE && names_param(&err, p),
          "%s: %s NaN in the struct: %s, param '%s', reason %s (%s)", e->name, p->name,
          relief_status_name(st), err.param, relief_reason_name(err.reason), err.message);
}

/* Just outside a bound: the next integer, or a millionth beyond. */
static double outside(const relief_param *p, double bound, int below)
{
    const double step = p->kind == RELIEF_PARAM_REAL ? 1e-6 * fmax(1.0, fabs(bound)) : 1.0;
    return below ? bound - step : bound + step;
}

static int special(const relief_param *p, double v)
{
    for (int i = 0; i < p->n_special; ++i)
        if (p->special[i] == v)
            return 1;
    return 0;
}

static void check_range(const engine *e, const relief_param *p)
{
    const double lo = p->min, hi = p->kind == RELIEF_PARAM_SEED ? 4294967295.0 : p->max;
    if (isfinite(lo)) {
        expect(e, p, lo, 1);
        if (p->kind != RELIEF_PARAM_SEED && !special(p, outside(p, lo, 1))) {
            expect(e, p, outside(p, lo, 1), 0);
            expect_named(e, p, outside(p, lo, 1));
        }
    }
    if (isfinite(hi)) {
        expect(e, p, hi, 1);
        if (p->kind != RELIEF_PARAM_SEED && !special(p, outside(p, hi, 0))) {
            expect(e, p, outside(p, hi, 0), 0);
            expect_named(e, p, outside(p, hi, 0));
        }
    }
    for (int i = 0; i < p->n_special; ++i)
        expect(e, p, p->special[i], 1);
    if (p->kind == RELIEF_PARAM_REAL) { /* NaN cannot come as text: put it there */
        buffer buf;
        unsigned char *params = buf.b;
        relief_error err = {0};
        const double nan = NAN;
        e->defaults(params);
        memcpy(params + p->offset, &nan, sizeof nan);
        CHECK(e->validate(params, &err) == RELIEF_E_RANGE && strstr(err.message, p->name) &&
                  names_param(&err, p),
              "%s: %s = NaN: param '%s' (%s)", e->name, p->name, err.param, err.message);
    }
}

static void check_enum(const engine *e, const relief_param *p)
{
    buffer buf;
    unsigned char *params = buf.b;
    relief_error err = {0};
    int n = 0;
    for (; p->names[n]; ++n) {
        e->defaults(params);
        if (e->prepare)
            e->prepare(params, p);
        CHECK_STATUS(relief_param_set(params, p, p->names[n], &err), RELIEF_OK, err, NULL);
        CHECK(e->validate(params, &err) == RELIEF_OK, "%s: %s %s refused: %s", e->name,
              p->name, p->names[n], err.message);
    }
    CHECK_STATUS(relief_param_set(params, p, "no-such-name", &err), RELIEF_E_USAGE, err,
                 p->name);
    e->defaults(params);
    memcpy(params + p->offset, &n, sizeof n);
    CHECK(e->validate(params, &err) == RELIEF_E_RANGE && names_param(&err, p),
          "%s: %s %d (past the names): param '%s' (%s)", e->name, p->name, n, err.param,
          err.message);
}

/* The default, written as text and set again, changes nothing. */
static void check_round_trip(const engine *e, const relief_param *p)
{
    buffer ba, bb;
    unsigned char *a = ba.b, *b = bb.b;
    char text[512], again[512];
    relief_error err = {0};
    e->defaults(a);
    e->defaults(b);
    relief_param_format(a, p, text, sizeof text);
    if (p->kind == RELIEF_PARAM_PATH || (p->kind == RELIEF_PARAM_REALS && !text[0]))
        return; /* nothing to set: NULL, or no values */
    CHECK_STATUS(relief_param_set(b, p, text, &err), RELIEF_OK, err, NULL);
    relief_param_format(b, p, again, sizeof again);
    CHECK(strcmp(text, again) == 0 && e->validate(b, &err) == RELIEF_OK,
          "%s: %s: '%s' set back reads '%s'", e->name, p->name, text, again);
}

static void check_engine(const engine *e)
{
    CHECK(e->table && e->n > 0 && e->size <= 4096, "%s: no table", e->name);
    for (size_t i = 0; i < e->n; ++i) {
        const relief_param *p = &e->table[i];
        CHECK(p->name && p->help && p->help[0] && p->offset < e->size, "%s: entry %zu",
              e->name, i);
        CHECK(relief_param_find(e->table, e->n, p->name) == p, "%s: %s found elsewhere",
              e->name, p->name);
        CHECK(p->kind == RELIEF_PARAM_FLAG || p->value, "%s: %s has no value shown", e->name,
              p->name);
        check_round_trip(e, p);
        if (p->kind == RELIEF_PARAM_INT || p->kind == RELIEF_PARAM_REAL ||
            p->kind == RELIEF_PARAM_SEED)
            check_range(e, p);
        else if (p->kind == RELIEF_PARAM_ENUM)
            check_enum(e, p);
        else if (p->kind == RELIEF_PARAM_FLAG) {
            expect(e, p, 0, 1);
            expect(e, p, 1, 1);
            expect_named(e, p, 2);
        } else if (p->kind == RELIEF_PARAM_REALS)
            expect_reals_named(e, p);
    }
    CHECK(relief_param_find(e->table, e->n, "no_such_parameter") == NULL, "found nothing");
}

static void check_text(void)
{
    relief_image_fill_params p = relief_image_fill_params_default();
    relief_error err = {0};
    size_t n;
    const relief_param *t = relief_image_fill_param_table(&n);
    CHECK_STATUS(relief_param_set(&p, relief_param_find(t, n, "window"), "x9", &err),
                 RELIEF_E_USAGE, err, "window");
    CHECK_STATUS(relief_param_set(&p, relief_param_find(t, n, "tau"), "nan", &err),
                 RELIEF_E_USAGE, err, "tau");
    CHECK_STATUS(relief_param_set(&p, relief_param_find(t, n, "interp"), "maybe", &err),
                 RELIEF_E_USAGE, err, "interp");
    CHECK_STATUS(relief_param_set(&p, relief_param_find(t, n, "max_memory"), "4G", &err),
                 RELIEF_OK, err, NULL);
    CHECK(p.run.max_memory == 4ull << 30, "4G");
    CHECK_STATUS(relief_param_set(&p, relief_param_find(t, n, "interp"), "no", &err),
                 RELIEF_OK, err, NULL);
    CHECK(p.interp == 0, "interp no");
    CHECK_STATUS(relief_param_set(&p, NULL, "1", &err), RELIEF_E_USAGE, err, NULL);
}

int main(void)
{
    engine engines[6];
    size_t k = 0;
    if (!api_test_locale())
        return 2;
    engines[k++] = (engine){"complete", NULL, 0, sizeof(relief_complete_params),
                            complete_defaults, NULL, complete_validate};
    engines[0].table = relief_complete_param_table(&engines[0].n);
    engines[k++] = (engine){"image-fill", NULL, 0, sizeof(relief_image_fill_params),
                            image_defaults, image_prepare, image_validate};
    engines[1].table = relief_image_fill_param_table(&engines[1].n);
    engines[k++] = (engine){"depth-fill", NULL, 0, sizeof(relief_depth_fill_params),
                            depth_defaults, NULL, depth_validate};
    engines[2].table = relief_depth_fill_param_table(&engines[2].n);
    engines[k++] = (engine){"complete-points", NULL, 0, sizeof(relief_complete_points_params),
                            points_defaults, points_prepare, points_validate};
    engines[3].table = relief_complete_points_param_table(&engines[3].n);
    engines[k++] = (engine){"occluders", NULL, 0, sizeof(relief_occluder_params),
                            occluder_defaults, occluder_prepare, occluder_validate};
    engines[4].table = relief_occluder_param_table(&engines[4].n);
    engines[k] = engines[0];
    engines[k].name = "smooth";
    engines[k].table = relief_smooth_param_table(&engines[k].n);
    ++k;
    for (size_t i = 0; i < k; ++i)
        check_engine(&engines[i]);
    check_text();
    API_TEST_END();
}
