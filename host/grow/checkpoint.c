/* Checkpoints of a growth (checkpoint.h): one flat binary record, built in
 * memory, checksummed, and written through a temporary file. */
#include "grow/checkpoint.h"
#include "base/params.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "base/output.h"
#include "base/error.h"
#include "base/numtext.h"
#include "grow/hierarchy.h"
#include "mesh/mesh.h"
#include "smooth/oversample.h"

#define MAGIC "RELIEFCK"
#define FORMAT 4u /* 2: the matches and a hierarchy's place; 3: the sources; 4: the
                     previous level's heights unsmoothed */
#define ORDER 0x01020304u

/* ------------------------------------------------------------ fingerprint */

static uint64_t fnv1a(uint64_t h, const void *data, size_t n)
{
    const unsigned char *p = data;
    for (size_t i = 0; i < n; ++i) {
        h ^= p[i];
        h *= 0x100000001b3ull;
    }
    return h;
}

#define FNV_START 0xcbf29ce484222325ull

/* The shortest %g text that reads back as exactly v ("0.1", not
 * "0.10000000000000001"): the key must tell every double apart. In the C
 * locale: a checkpoint made under one locale resumes under another. */
static void exact(char *buf, size_t cap, double v)
{
    for (int prec = 6; prec <= 17; ++prec) {
        relief_snprintf_c(buf, cap, "%.*g", prec, v);
        if (relief_strtod(buf, NULL) == v)
            return;
    }
}

void relief_checkpoint_key_make(const relief_mesh *in, const relief_params *p,
                                const relief_smooth_options *so,
                                const relief_grow_options *go, relief_checkpoint_key *key)
{
    relief_smooth_options sd = relief_smooth_options_default();
    uint64_t h = FNV_START, counts[2] = {in->nv, in->nt};
    char extent[128] = "none", error[32], mu[32], spacing[32], pct[32], coherence[32],
         spike_k[32];
    if (!so)
        so = &sd;
    h = fnv1a(h, counts, sizeof counts);
    h = fnv1a(h, in->pos, in->nv * 3 * sizeof *in->pos);
    if (in->nt)
        h = fnv1a(h, in->tri, in->nt * 3 * sizeof *in->tri);
    if (in->col)
        h = fnv1a(h, in->col, in->nv * 3 * sizeof *in->col);
    if (in->label) /* hole_labels chooses the holes by them */
        h = fnv1a(h, in->label, in->nv * sizeof *in->label);
    key->input_hash = h;
    if (p->has_extent) {
        size_t at = 0;
        for (int i = 0; i < p->n_extent; ++i) {
            char v[32];
            exact(v, sizeof v, p->extent[i]);
            at += (size_t)snprintf(extent + at, sizeof extent - at, "%s%s", i ? "," : "", v);
        }
    }
    exact(error, sizeof error, p->error);
    exact(mu, sizeof mu, p->mu);
    exact(coherence, sizeof coherence, p->coherence);
    exact(spacing, sizeof spacing, p->spacing);
    exact(pct, sizeof pct, so->spacing_percentile);
    exact(spike_k, sizeof spike_k, so->spike_k);
    /* Everything that changes the result; backend, device and pruning do
     * not (the tests hold them to byte-identical outputs). */
    snprintf(key->params, sizeof key->params,
             "fit=%s window=%d rotations=%d error=%s mu=%s seed=%u levels=%d "
             "oversample=%d oversample_scheme=%s spacing=%s extent=%s frames=%s "
             "spacing_percentile=%s bootstrap=%d coherence=%s spike_k=%s fill=%s search=%s "
             "search_k=%d",
             relief_fit_model_name(p->fit), p->window, p->rotations, error, mu,
             (unsigned)p->seed, p->levels, p->oversample,
             relief_oversample_scheme_name(so->oversample_scheme), spacing, extent,
             so->frames == RELIEF_FRAMES_PAPER ? "paper" : "primitive", pct,
             go ? go->bootstrap : 0, coherence, spike_k, relief_fill_region_name(so->fill),
             relief_search_name(p->search), p->search_k);
}

/* --------------------------------------------------------------- writing */

typedef struct buffer {
    unsigned char *data;
    size_t n, cap;
    int failed;
} buffer;

static void put(buffer *b, const void *p, size_t n)
{
    if (b->failed || n == 0) /* n == 0: p may be NULL (level 1 has no previous level) */
        return;
    if (b->n + n > b->cap) {
        size_t cap = b->cap ? b->cap : 4096;
        unsigned char *d;
        while (cap < b->n + n)
            cap *= 2;
        d = realloc(b->data, cap);
        if (!d) {
            b->failed = 1;
            return;
        }
        b->data = d;
        b->cap = cap;
    }
    memcpy(b->data + b->n, p, n);
    b->n += n;
}

static void put_u64(buffer *b, uint64_t v) { put(b, &v, sizeof v); }
static void put_u32(buffer *b, uint32_t v) { put(b, &v, sizeof v); }
static void put_f64(buffer *b, double v) { put(b, &v, sizeof v); }

/* The stats as they lie in memory (size_t and double fields only, so no
 * padding), behind their size: a relief whose stats differ refuses them. */
static void put_stats(buffer *b, const relief_grow_stats *s)
{
    put_u32(b, (uint32_t)sizeof *s);
    put(b, s, sizeof *s);
}

/* The header: magic, format, byte order, the version (16 bytes, NUL
 * padded), the input's hash and the params text: what a reader checks
 * before it trusts the rest. */
static void put_head(buffer *b, const relief_checkpoint_key *key)
{
    char version[16] = {0};
    uint32_t plen = (uint32_t)strlen(key->params);

    put(b, MAGIC, 8);
    put_u32(b, FORMAT);
    put_u32(b, ORDER);
    snprintf(version, sizeof version, "%s", RELIEF_VERSION_STRING);
    put(b, version, sizeof version);
    put_u64(b, key->input_hash);
    put_u32(b, plen);
    put(b, key->params, plen);
}

/* The growth itself, per target (nt = nv - n_samples entries; disp and
 * colours 3 per target), then the list, the pass, the random generator,
 * the stats and the optional matches. */
static void put_growth(buffer *b, const relief_grow_state *g)
{
    const size_t nt = g->nv - g->n_samples;

    put_u64(b, g->nv);
    put_u64(b, g->n_samples);
    put_u32(b, g->mesh_colour != NULL);
    put(b, g->textured, nt);
    for (size_t i = 0; i < nt; ++i)
        put_u32(b, (uint32_t)g->window[i]);
    put(b, g->disp, nt * 3 * sizeof *g->disp);
    put(b, g->colour, nt * 3 * sizeof *g->colour);
    if (g->mesh_colour)
        put(b, g->mesh_colour, nt * 3 * sizeof *g->mesh_colour);
    put(b, g->source, nt * sizeof *g->source);
    put_u64(b, g->n_list);
    put(b, g->list, g->n_list * sizeof *g->list);
    put_u64(b, g->next);
    put_u64(b, g->pass_accepted);
    put_u32(b, (uint32_t)g->pass_any_valid);
    put_u32(b, (uint32_t)g->pass_all_min_window);
    put_f64(b, g->error);
    put(b, g->rng.mt, sizeof g->rng.mt);
    put_u32(b, (uint32_t)g->rng.index);
    put_stats(b, &g->stats);
    put_u32(b, g->matched != NULL);
    if (g->matched)
        put(b, g->matched, nt * sizeof *g->matched);
}

/* The hierarchy's place, behind a flag: the previous level's heights and
 * matches (prev_nv each) and the finished levels' stats (level - 1). */
static void put_hier(buffer *b, const relief_hierarchy_state *h)
{
    put_u32(b, h != NULL);
    if (!h)
        return;
    put_u32(b, (uint32_t)h->levels);
    put_u32(b, (uint32_t)h->level);
    put_u64(b, h->prev_nv);
    put(b, h->heights_prev, h->prev_nv * sizeof *h->heights_prev);
    put(b, h->match_prev, h->prev_nv * sizeof *h->match_prev);
    /* As the stats: in memory (size_t and double only), behind their size. */
    put_u32(b, (uint32_t)sizeof *h->done);
    put(b, h->done, (size_t)(h->level - 1) * sizeof *h->done);
}

/* What bytes_sink writes. */
/* Writes the n bytes to path whole or not at all (base/output.h). */
static relief_status write_whole(const char *path, const unsigned char *data, size_t n,
                                 relief_error *err)
{
    relief_bytes b = {data, n};
    return relief_output_file(path, relief_sink_bytes, &b, err);
}

relief_status relief_checkpoint_check_path(const char *path, int *exists, relief_error *err)
{
    char head[8];
    struct stat sb;
    FILE *f;
    size_t got;
    *exists = 0;
    if (stat(path, &sb) != 0)
        return errno == ENOENT ? RELIEF_OK
                               : relief_fail_errno(err, errno, path, "cannot inspect");
    if (!S_ISREG(sb.st_mode))
        return relief_fail_reason(err, RELIEF_E_IO, RELIEF_REASON_NOT_RELIEFS, "%s: is there "
                                  "and is not a file; a checkpoint names a file", path);
    if (!(f = fopen(path, "rb")))
        return relief_fail_errno(err, errno, path, "cannot read");
    got = fread(head, 1, sizeof head, f);
    fclose(f);
    if (got != sizeof head || memcmp(head, MAGIC, sizeof head) != 0)
        return relief_fail_reason(err, RELIEF_E_IO, RELIEF_REASON_NOT_RELIEFS, "%s: is there "
                                  "and is no relief checkpoint (no '%s' magic): relief "
                                  "replaces only a checkpoint it wrote; name another file",
                                  path, MAGIC);
    *exists = 1;
    return RELIEF_OK;
}

relief_status relief_checkpoint_write(const char *path, const relief_checkpoint_key *key,
                                      const relief_grow_state *g, relief_error *err)
{
    buffer b = {NULL, 0, 0, 0};
    relief_status st;

    put_head(&b, key);
    put_growth(&b, g);
    put_hier(&b, g->hier);
    put_u64(&b, fnv1a(FNV_START, b.data, b.n));
    if (b.failed) {
        free(b.data);
        return relief_fail(err, RELIEF_E_NOMEM, "the checkpoint is not saved: %s: cannot "
                           "allocate it", path);
    }
    /* Said as what it is: a run cancelled on a full disk exits as the
     * signal says, and its one line must tell that nothing was saved. */
    if ((st = write_whole(path, b.data, b.n, err)) != RELIEF_OK)
        relief_fail_prefix(err, "the checkpoint is not saved");
    free(b.data);
    return st;
}

/* --------------------------------------------------------------- reading */

struct relief_checkpoint {
    relief_grow_state state;
    uint8_t *textured;
    int *window;
    double *disp;
    float *colour, *mesh_colour;
    uint32_t *source, *list, *matched;
    relief_hierarchy_state hier;
    double *heights_prev;
    uint32_t *match_prev;
    relief_level_stats done[RELIEF_MAX_LEVELS];
};

void relief_checkpoint_destroy(relief_checkpoint *c)
{
    if (!c)
        return;
    free(c->match_prev);
    free(c->heights_prev);
    free(c->matched);
    free(c->list);
    free(c->source);
    free(c->mesh_colour);
    free(c->colour);
    free(c->disp);
    free(c->window);
    free(c->textured);
    free(c);
}

const relief_grow_state *relief_checkpoint_state(const relief_checkpoint *c)
{
    return &c->state;
}

typedef struct reader {
    const unsigned char *p;
    size_t n, at;
    int short_read;
} reader;

static int get(reader *r, void *out, size_t n)
{
    if (n == 0)
        return !r->short_read;
    if (r->short_read || n > r->n - r->at) {
        r->short_read = 1;
        return 0;
    }
    memcpy(out, r->p + r->at, n);
    r->at += n;
    return 1;
}

static uint64_t get_u64(reader *r)
{
    uint64_t v = 0;
    get(r, &v, sizeof v);
    return v;
}

static uint32_t get_u32(reader *r)
{
    uint32_t v = 0;
    get(r, &v, sizeof v);
    return v;
}

static double get_f64(reader *r)
{
    double v = 0;
    get(r, &v, sizeof v);
    return v;
}

static int get_stats(reader *r, relief_grow_stats *s)
{
    return get_u32(r) == sizeof *s && get(r, s, sizeof *s);
}

/* Read a whole file. */
static relief_status slurp(const char *path, unsigned char **data, size_t *n,
                           relief_error *err)
{
    FILE *f = fopen(path, "rb");
    unsigned char *buf = NULL;
    size_t cap = 0, len = 0;
    if (!f)
        return relief_fail(err, RELIEF_E_IO, "%s: cannot open: %s", path, strerror(errno));
    for (;;) {
        size_t got;
        if (len == cap) {
            unsigned char *b2;
            cap = cap ? 2 * cap : 65536;
            b2 = realloc(buf, cap);
            if (!b2) {
                free(buf);
                fclose(f);
                return relief_fail(err, RELIEF_E_NOMEM, "%s: cannot allocate %zu bytes", path,
                                   cap);
            }
            buf = b2;
        }
        got = fread(buf + len, 1, cap - len, f);
        len += got;
        if (got == 0)
            break;
    }
    if (ferror(f)) {
        free(buf);
        fclose(f);
        return relief_fail(err, RELIEF_E_IO, "%s: cannot read: %s", path, strerror(errno));
    }
    fclose(f);
    *data = buf;
    *n = len;
    return RELIEF_OK;
}

/* The first space-separated "name=value" of a that b does not have. */
static void first_difference(const char *a, const char *b, char *out, size_t cap,
                             char *theirs, size_t tcap)
{
    while (*a || *b) {
        size_t la = strcspn(a, " "), lb = strcspn(b, " ");
        if (la != lb || memcmp(a, b, la) != 0) {
            snprintf(out, cap, "%.*s", (int)la, a);
            snprintf(theirs, tcap, "%.*s", (int)lb, b);
            return;
        }
        a += la + (a[la] == ' ');
        b += lb + (b[lb] == ' ');
    }
    snprintf(out, cap, "?");
    snprintf(theirs, tcap, "?");
}

/* The matches of a growth that keeps them: a textured target's is a
 * vertex, an untextured one's UINT32_MAX - 1. */
static relief_status parse_matches(const char *path, reader *r, relief_checkpoint *c,
                                   relief_error *err)
{
    const relief_grow_state *g = &c->state;
    const size_t nt = g->nv - g->n_samples;
    const uint32_t has = get_u32(r);
    if (r->short_read)
        return RELIEF_OK; /* reported as truncated */
    if (has > 1 || (has && nt * 4 > r->n - r->at))
        return relief_fail(err, RELIEF_E_PARSE, "%s: checkpoint matches are malformed", path);
    if (!has)
        return RELIEF_OK;
    c->matched = malloc((nt + 1) * sizeof *c->matched);
    if (!c->matched)
        return relief_fail(err, RELIEF_E_NOMEM, "%s: cannot allocate the checkpoint", path);
    get(r, c->matched, nt * sizeof *c->matched);
    for (size_t i = 0; i < nt; ++i)
        if (c->textured[i] ? c->matched[i] >= g->nv : c->matched[i] != UINT32_MAX - 1)
            return relief_fail(err, RELIEF_E_PARSE, "%s: target %zu: match %u is not a "
                               "vertex of its %s target", path, g->n_samples + i,
                               c->matched[i], c->textured[i] ? "textured" : "untextured");
    return RELIEF_OK;
}

/* A hierarchical run's place (hierarchy.h). */
static relief_status parse_hierarchy(const char *path, reader *r, relief_checkpoint *c,
                                     relief_error *err)
{
    relief_hierarchy_state *h = &c->hier;
    uint32_t has = get_u32(r), levels, level, size;
    uint64_t np;
    if (r->short_read)
        return RELIEF_OK;
    if (has > 1)
        return relief_fail(err, RELIEF_E_PARSE, "%s: checkpoint hierarchy flag %u", path, has);
    if (!has)
        return RELIEF_OK;
    levels = get_u32(r);
    level = get_u32(r);
    np = get_u64(r);
    if (r->short_read)
        return RELIEF_OK;
    if (levels < 2 || levels > RELIEF_MAX_LEVELS || level < 1 || level > levels ||
        (level == 1) != (np == 0) || np > UINT32_MAX || np * 12 > r->n - r->at)
        return relief_fail(err, RELIEF_E_PARSE, "%s: checkpoint at level %u of %u with %llu "
                           "vertices before it is malformed", path, level, levels,
                           (unsigned long long)np);
    if (!c->matched)
        return relief_fail(err, RELIEF_E_PARSE, "%s: a hierarchy's checkpoint without its "
                           "matches", path);
    c->heights_prev = malloc((np + 1) * sizeof *c->heights_prev);
    c->match_prev = malloc((np + 1) * sizeof *c->match_prev);
    if (!c->heights_prev || !c->match_prev)
        return relief_fail(err, RELIEF_E_NOMEM, "%s: cannot allocate the checkpoint", path);
    get(r, c->heights_prev, np * sizeof *c->heights_prev);
    get(r, c->match_prev, np * sizeof *c->match_prev);
    for (size_t v = 0; v < np; ++v)
        if (!isfinite(c->heights_prev[v]) ||
            (c->match_prev[v] >= np && c->match_prev[v] < UINT32_MAX - 1))
            return relief_fail(err, RELIEF_E_PARSE, "%s: level %u vertex %zu: height %g or "
                               "match %u is malformed", path, level - 1, v,
                               c->heights_prev[v], c->match_prev[v]);
    size = get_u32(r);
    if (!r->short_read && size != sizeof *h->done)
        return relief_fail(err, RELIEF_E_PARSE, "%s: checkpoint level statistics are of "
                           "another layout", path);
    get(r, c->done, (size_t)(level - 1) * sizeof *c->done);
    h->levels = (int)levels;
    h->level = (int)level;
    h->prev_nv = (size_t)np;
    h->heights_prev = c->heights_prev;
    h->match_prev = c->match_prev;
    h->done = c->done;
    return RELIEF_OK;
}

/* The record's head: magic, format, byte order, checksum (which then
 * comes off the end), the relief version, and the input's fingerprint and
 * parameters, which must be this run's. */
static relief_status parse_head(const char *path, reader *r, const relief_checkpoint_key *key,
                                relief_error *err)
{
    char magic[8], version[16], params[RELIEF_CHECKPOINT_PARAMS_MAX];
    uint32_t plen;
    uint64_t hash;
    if (!get(r, magic, 8) || memcmp(magic, MAGIC, 8) != 0)
        return relief_fail(err, RELIEF_E_PARSE, "%s: not a relief checkpoint (no '%s' magic)",
                           path, MAGIC);
    if (get_u32(r) != FORMAT)
        return relief_fail(err, RELIEF_E_PARSE, "%s: checkpoint format is not version %u",
                           path, FORMAT);
    if (get_u32(r) != ORDER)
        return relief_fail(err, RELIEF_E_PARSE,
                           "%s: checkpoint written on a machine of another byte order", path);
    /* The checksum covers everything before its own 8 bytes. */
    if (r->n >= 16)
        memcpy(&hash, r->p + r->n - 8, 8);
    if (r->n < 16 || fnv1a(FNV_START, r->p, r->n - 8) != hash)
        return relief_fail(err, RELIEF_E_PARSE,
                           "%s: checkpoint is truncated or corrupt (checksum mismatch)", path);
    r->n -= 8;
    get(r, version, sizeof version);
    version[sizeof version - 1] = '\0';
    if (strcmp(version, RELIEF_VERSION_STRING) != 0)
        return relief_fail(err, RELIEF_E_USAGE,
                           "%s: checkpoint made by relief %s; this is relief %s", path,
                           version, RELIEF_VERSION_STRING);
    hash = get_u64(r);
    plen = get_u32(r);
    if (plen >= sizeof params || !get(r, params, plen))
        return relief_fail(err, RELIEF_E_PARSE, "%s: checkpoint parameters are malformed",
                           path);
    params[plen] = '\0';
    if (hash != key->input_hash)
        return relief_fail(err, RELIEF_E_USAGE,
                           "%s: the checkpoint was made from a different input (fingerprint "
                           "%016llx, this input %016llx); resume with the same input file",
                           path, (unsigned long long)hash,
                           (unsigned long long)key->input_hash);
    if (strcmp(params, key->params) != 0) {
        char ours[128], theirs[128];
        first_difference(params, key->params, theirs, sizeof theirs, ours, sizeof ours);
        return relief_fail(err, RELIEF_E_USAGE,
                           "%s: the checkpoint was made with %s, this run has %s; resume "
                           "with the same parameters (checkpoint: %s)",
                           path, theirs, ours, params);
    }
    return RELIEF_OK;
}

/* The nt targets' state (after the ns samples): textured flags, windows,
 * displacements, colours, the mesh's colours when it has them, sources;
 * *textured counts the textured targets. */
static relief_status parse_targets(const char *path, reader *r, relief_checkpoint *c,
                                   uint64_t ns, uint64_t nt, size_t *textured,
                                   relief_error *err)
{
    const uint32_t has_col = get_u32(r);
    /* The arrays must fit in what is left before they are allocated. */
    const size_t need = (size_t)nt * (1 + 4 + 24 + 12 + (has_col ? 12 : 0) + 4);
    if (has_col > 1 || r->short_read || need > r->n - r->at)
        return relief_fail(err, RELIEF_E_PARSE,
                           "%s: checkpoint is truncated: %llu targets need %zu bytes",
                           path, (unsigned long long)nt, need);
    c->textured = malloc(nt + 1);
    c->window = malloc((nt + 1) * sizeof *c->window);
    c->disp = malloc((nt + 1) * 3 * sizeof *c->disp);
    c->colour = malloc((nt + 1) * 3 * sizeof *c->colour);
    c->mesh_colour = has_col ? malloc((nt + 1) * 3 * sizeof *c->mesh_colour) : NULL;
    c->source = malloc((nt + 1) * sizeof *c->source);
    if (!c->textured || !c->window || !c->disp || !c->colour ||
        (has_col && !c->mesh_colour) || !c->source)
        return relief_fail(err, RELIEF_E_NOMEM, "%s: cannot allocate the checkpoint",
                           path);
    get(r, c->textured, nt);
    for (size_t i = 0; i < nt; ++i) {
        const uint32_t w = get_u32(r);
        if (c->textured[i] > 1 || w < 1 || w > 16)
            return relief_fail(err, RELIEF_E_PARSE,
                               "%s: target %zu: textured flag %u or window %u out of "
                               "range",
                               path, (size_t)ns + i, c->textured[i], w);
        c->window[i] = (int)w;
        *textured += c->textured[i];
    }
    get(r, c->disp, nt * 3 * sizeof *c->disp);
    get(r, c->colour, nt * 3 * sizeof *c->colour);
    if (has_col)
        get(r, c->mesh_colour, nt * 3 * sizeof *c->mesh_colour);
    get(r, c->source, nt * sizeof *c->source);
    for (size_t i = 0; i < nt; ++i)
        if ((c->source[i] == UINT32_MAX) != !c->textured[i])
            return relief_fail(err, RELIEF_E_PARSE,
                               "%s: target %zu: source %u for a%s target", path,
                               (size_t)ns + i, c->source[i],
                               c->textured[i] ? " textured" : "n untextured");
    for (size_t i = 0; i < 3 * nt; ++i)
        if (!isfinite(c->disp[i]) || !isfinite(c->colour[i]) ||
            (has_col && !isfinite(c->mesh_colour[i])))
            return relief_fail(err, RELIEF_E_PARSE,
                               "%s: target %zu: displacement or colour is not finite",
                               path, (size_t)ns + i / 3);
    return RELIEF_OK;
}

/* The pass under way: its boundary list (of nl targets) and the position
 * of the next one in it. */
static relief_status parse_list(const char *path, reader *r, relief_checkpoint *c, uint64_t nv,
                                uint64_t ns, uint64_t nt, relief_error *err)
{
    relief_grow_state *g = &c->state;
    const uint64_t nl = get_u64(r);
    if (r->short_read || nl > nt || nl * 4 > r->n - r->at)
        return relief_fail(err, RELIEF_E_PARSE, "%s: boundary list of %llu targets is "
                           "malformed", path, (unsigned long long)nl);
    c->list = malloc((nl + 1) * sizeof *c->list);
    if (!c->list)
        return relief_fail(err, RELIEF_E_NOMEM, "%s: cannot allocate the checkpoint", path);
    get(r, c->list, nl * sizeof *c->list);
    g->n_list = (size_t)nl;
    g->next = (size_t)get_u64(r);
    /* Targets before next were done in this pass (textured or not); those
     * from next on are still to do. */
    for (size_t i = 0; i < nl && !r->short_read; ++i)
        if (c->list[i] < ns || c->list[i] >= nv || (i >= g->next && c->textured[c->list[i] - ns]))
            return relief_fail(err, RELIEF_E_PARSE,
                               "%s: boundary list entry %zu (vertex %u) is not an "
                               "untextured target",
                               path, i, c->list[i]);
    return RELIEF_OK;
}

/* What the whole record must agree on, once read: the pass's position and
 * counts, the threshold and random state, the figures against the targets
 * (nt, of which `textured` textured). */
static relief_status parse_check(const char *path, const relief_grow_state *g, uint64_t nt,
                                 size_t textured, relief_error *err)
{
    const size_t nl = g->n_list;
    if ((nl > 0 && g->next >= nl) || (nl == 0 && g->next != 0) || g->pass_any_valid > 1 ||
        g->pass_all_min_window > 1 || g->pass_accepted > textured)
        return relief_fail(err, RELIEF_E_PARSE, "%s: pass position %zu of %llu is malformed",
                           path, g->next, (unsigned long long)nl);
    if (!(g->error > 0.0) || !isfinite(g->error) || g->rng.index < 0 || g->rng.index > 624)
        return relief_fail(err, RELIEF_E_PARSE, "%s: threshold %g or random state is "
                           "malformed", path, g->error);
    if (g->stats.targets != nt || g->stats.acceptances != textured)
        return relief_fail(err, RELIEF_E_PARSE,
                           "%s: counts disagree: %zu targets and %zu acceptances, but %llu "
                           "targets of which %zu textured",
                           path, g->stats.targets, g->stats.acceptances,
                           (unsigned long long)nt, textured);
    return RELIEF_OK;
}

static relief_status parse(const char *path, reader *r, const relief_checkpoint_key *key,
                           relief_checkpoint *c, relief_error *err)
{
    relief_grow_state *g = &c->state;
    uint64_t nv, ns, nt;
    size_t textured = 0;
    relief_status st = parse_head(path, r, key, err);
    if (st != RELIEF_OK)
        return st;
    nv = get_u64(r);
    ns = get_u64(r);
    if (r->short_read || ns > nv || nv > UINT32_MAX)
        return relief_fail(err, RELIEF_E_PARSE, "%s: bad vertex counts %llu (%llu samples)",
                           path, (unsigned long long)nv, (unsigned long long)ns);
    nt = nv - ns;
    g->nv = (size_t)nv;
    g->n_samples = (size_t)ns;
    st = parse_targets(path, r, c, ns, nt, &textured, err);
    if (st == RELIEF_OK)
        st = parse_list(path, r, c, nv, ns, nt, err);
    if (st != RELIEF_OK)
        return st;
    g->pass_accepted = (size_t)get_u64(r);
    g->pass_any_valid = (int)get_u32(r);
    g->pass_all_min_window = (int)get_u32(r);
    g->error = get_f64(r);
    get(r, g->rng.mt, sizeof g->rng.mt);
    g->rng.index = (int)get_u32(r);
    if (!get_stats(r, &g->stats) && !r->short_read)
        return relief_fail(err, RELIEF_E_PARSE, "%s: checkpoint statistics are of another "
                           "layout", path);
    st = parse_matches(path, r, c, err);
    if (st == RELIEF_OK)
        st = parse_hierarchy(path, r, c, err);
    if (st != RELIEF_OK)
        return st;
    if (r->short_read || r->at != r->n)
        return relief_fail(err, RELIEF_E_PARSE, "%s: checkpoint is %s", path,
                           r->short_read ? "truncated" : "longer than its content");
    st = parse_check(path, g, nt, textured, err);
    if (st != RELIEF_OK)
        return st;
    g->textured = c->textured;
    g->window = c->window;
    g->disp = c->disp;
    g->colour = c->colour;
    g->mesh_colour = c->mesh_colour;
    g->source = c->source;
    g->list = c->list;
    g->matched = c->matched;
    g->hier = c->hier.levels ? &c->hier : NULL;
    return RELIEF_OK;
}

relief_status relief_checkpoint_read(const char *path, const relief_checkpoint_key *key,
                                     relief_checkpoint **out, relief_error *err)
{
    unsigned char *data = NULL;
    size_t n = 0;
    relief_checkpoint *c;
    reader r;
    relief_status st = slurp(path, &data, &n, err);
    if (st != RELIEF_OK)
        return st;
    c = calloc(1, sizeof *c);
    if (!c) {
        free(data);
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate a checkpoint");
    }
    r.p = data;
    r.n = n;
    r.at = 0;
    r.short_read = 0;
    st = parse(path, &r, key, c, err);
    free(data);
    if (st != RELIEF_OK) {
        relief_checkpoint_destroy(c);
        return st;
    }
    *out = c;
    return RELIEF_OK;
}
