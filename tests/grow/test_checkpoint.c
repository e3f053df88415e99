/* Checkpoints: a growth stopped after N acceptances, saved, read back and
 * resumed gives the same surface and counts as one never stopped, whatever
 * N; saving before every target changes nothing; the cancel flag stops it
 * between two targets; a checkpoint that is truncated, corrupt or of
 * another input or parameters is refused. The same for a hierarchical run
 * (M = 3), stopped in each level and at a level's end. */
#include <signal.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "base/params.h"
#include "grow/checkpoint.h"
#include "grow/grow.h"
#include "grow/hierarchy.h"
#include "match/matcher.h"
#include "match/matcher_scalar.h"
#include "mesh/mesh.h"
#include "smooth/surface.h"

typedef struct setup {
    relief_mesh *capture;
    relief_surface *s;
    relief_match_data *d;
    relief_matcher *m;
    relief_params p;
} setup;

static void setup_free(setup *u)
{
    relief_matcher_destroy(u->m);
    relief_match_data_destroy(u->d);
    relief_surface_destroy(u->s);
    relief_mesh_destroy(u->capture);
}

/* A small coloured plane with a low threshold and coherence: rejections,
 * shrunk windows, threshold raises and coherent picks, so every part of the
 * state matters. */
static int setup_make(setup *u, relief_search_mode search, relief_error *err)
{
    relief_synth_params sp = relief_synth_params_default();
    memset(u, 0, sizeof *u);
    sp.kind = RELIEF_SYNTH_PLANE_WAVES;
    sp.vertices = 500;
    sp.colour = 1;
    u->p = relief_params_default();
    u->p.window = 2;
    u->p.error = 0.03;
    /* Coherent candidates come from the targets' sources, which a resumed
     * run must read back: without them it continues other patches. */
    u->p.coherence = 2.0;
    u->p.search = search;
    return relief_synth(&sp, &u->capture, NULL, err) == RELIEF_OK &&
           relief_surface_build(u->capture, &u->p, NULL, &u->s, err) == RELIEF_OK &&
           relief_match_data_build(u->s, u->p.rotations, relief_grow_mu(&u->p, 1), &u->d,
                                   err) == RELIEF_OK &&
           relief_matcher_scalar_create(u->d, &u->m, err) == RELIEF_OK;
}

typedef struct saver {
    const char *path;
    const relief_checkpoint_key *key;
    int calls;
} saver;

static relief_status save(void *ctx, const relief_grow_state *g, relief_error *err)
{
    saver *sv = ctx;
    ++sv->calls;
    return relief_checkpoint_write(sv->path, sv->key, g, err);
}

static int same_counts(const relief_grow_stats *a, const relief_grow_stats *b)
{
    return a->targets == b->targets && a->passes == b->passes &&
           a->candidates == b->candidates && a->pruned == b->pruned &&
           a->invalid == b->invalid && a->acceptances == b->acceptances &&
           a->rejections == b->rejections && a->no_candidate == b->no_candidate &&
           a->threshold_raises == b->threshold_raises &&
           a->window_shrinks == b->window_shrinks && a->error_final == b->error_final;
}

static size_t file_size(const char *path)
{
    FILE *f = fopen(path, "rb");
    long n = -1;
    if (f && fseek(f, 0, SEEK_END) == 0)
        n = ftell(f);
    if (f)
        fclose(f);
    return n < 0 ? 0 : (size_t)n;
}

/* Cancel once `after` targets have been accepted in all (the levels
 * included), as the CLI's SIGINT hook does. */
typedef struct stopper {
    size_t after, seen, done;
    int level;
    volatile sig_atomic_t flag;
} stopper;

/* Progress comes after every target; an acceptance is a step of done
 * (counted afresh on each level). */
static void count_progress(void *ctx, const relief_grow_progress *p)
{
    stopper *s = ctx;
    int moved;
    if (p->level != s->level)
        s->done = 0;
    moved = p->done > s->done;
    s->level = p->level;
    s->done = p->done;
    if (moved && ++s->seen == s->after)
        s->flag = 1;
}

/* A hierarchical run of u's surface, from `resume` when not NULL. */
static relief_status grow_levels(setup *u, const relief_grow_options *go,
                                 relief_hierarchy_stats *hs, relief_grow_stats *total,
                                 relief_error *err)
{
    relief_hierarchy *h = NULL;
    relief_hierarchy_options ho = relief_hierarchy_options_default();
    relief_backend used;
    char dev[256];
    relief_status st = relief_hierarchy_build(u->s, u->p.levels, &h, err);
    ho.backend = RELIEF_BACKEND_SCALAR;
    if (st == RELIEF_OK)
        st = relief_hierarchy_grow(h, u->s, &u->p, go, &ho, hs, total, &used, dev, sizeof dev,
                                   NULL, 0, err);
    relief_hierarchy_destroy(h);
    return st;
}

static void check_hierarchy(const char *path)
{
    relief_error err = {0};
    relief_grow_options go = relief_grow_options_default();
    relief_hierarchy_stats ref_hs;
    relief_grow_stats ref_total;
    relief_checkpoint_key key;
    setup ref;
    size_t stops[] = {5, 0, 120, 0};

    if (!setup_make(&ref, RELIEF_SEARCH_EXHAUSTIVE, &err)) {
        CHECK(0, "set-up: %s", err.message);
        return;
    }
    ref.p.levels = 3;
    relief_checkpoint_key_make(ref.capture, &ref.p, NULL, &go, &key);
    CHECK(grow_levels(&ref, &go, &ref_hs, &ref_total, &err) == RELIEF_OK, "levels: %s",
          err.message);
    stops[1] = ref_hs.level[0].targets;      /* level 1's end */
    stops[3] = ref_total.acceptances - 3;    /* late in level 3 */
    for (size_t i = 0; i < sizeof stops / sizeof stops[0]; ++i) {
        setup u, v;
        saver sv = {path, &key, 0};
        stopper stop = {stops[i], 0, 0, 0, 0};
        relief_grow_options g1 = relief_grow_options_default(), g2 = g1;
        relief_hierarchy_stats hs1, hs2;
        relief_grow_stats t1, t2;
        relief_checkpoint *ck = NULL;
        relief_status st;
        const relief_grow_state *g;
        if (!setup_make(&u, RELIEF_SEARCH_EXHAUSTIVE, &err) || !setup_make(&v, RELIEF_SEARCH_EXHAUSTIVE, &err)) {
            CHECK(0, "set-up: %s", err.message);
            return;
        }
        u.p.levels = v.p.levels = 3;
        g1.save = save;
        g1.save_ctx = &sv;
        g1.progress = count_progress;
        g1.progress_ctx = &stop;
        g1.cancel = &stop.flag;
        st = grow_levels(&u, &g1, &hs1, &t1, &err);
        CHECK(st == RELIEF_E_CANCELLED && sv.calls == 1, "levels, stop after %zu: %s, %d saves",
              stops[i], relief_status_name(st), sv.calls);
        CHECK(t1.acceptances == stops[i], "levels, stopped after %zu: %zu counted", stops[i],
              t1.acceptances);
        st = relief_checkpoint_read(path, &key, &ck, &err);
        CHECK(st == RELIEF_OK, "levels, read after %zu: %s", stops[i], err.message);
        if (st != RELIEF_OK) {
            setup_free(&u), setup_free(&v);
            continue;
        }
        g = relief_checkpoint_state(ck);
        CHECK(g->hier && g->hier->levels == 3 && g->matched, "levels: no hierarchy state");
        if (g->hier)
            printf("levels: stopped after %zu, saved at level %d with %zu of %zu done\n",
                   stops[i], g->hier->level, g->stats.acceptances, g->stats.targets);
        if (i == 1)
            CHECK(g->hier && g->hier->level == 2 && g->stats.acceptances == 0,
                  "stopped at level 1's end: saved at level %d with %zu done",
                  g->hier ? g->hier->level : 0, g->stats.acceptances);
        /* Resumed on a surface built afresh: the uninterrupted result. */
        g2.resume = g;
        st = grow_levels(&v, &g2, &hs2, &t2, &err);
        CHECK(st == RELIEF_OK, "levels, resume after %zu: %s", stops[i], err.message);
        CHECK(memcmp(v.s->mesh->pos, ref.s->mesh->pos,
                     ref.s->mesh->nv * 3 * sizeof *ref.s->mesh->pos) == 0 &&
                  memcmp(v.s->mesh->col, ref.s->mesh->col,
                         ref.s->mesh->nv * 3 * sizeof *ref.s->mesh->col) == 0,
              "levels, resumed after %zu: the surface differs", stops[i]);
        CHECK(same_counts(&t2, &ref_total), "levels, resumed after %zu: the counts differ",
              stops[i]);
        for (int k = 0; k < 3; ++k)
            CHECK(same_counts(&hs2.level[k].grow, &ref_hs.level[k].grow) &&
                      hs2.level[k].boxes == ref_hs.level[k].boxes,
                  "levels, resumed after %zu: level %d's counts differ", stops[i], k + 1);
        /* A place that does not fit this hierarchy is refused. */
        if (g->hier && i == 2) {
            relief_hierarchy_state bad = *g->hier;
            relief_grow_state gb = *g;
            relief_checkpoint *ck2 = NULL;
            gb.hier = &bad;
            bad.level = 4;
            CHECK(relief_checkpoint_write(path, &key, &gb, &err) == RELIEF_OK, "%s",
                  err.message);
            CHECK(relief_checkpoint_read(path, &key, &ck2, &err) == RELIEF_E_PARSE &&
                      strstr(err.message, "level 4 of 3"),
                  "level 4 of 3 read back: %s", err.message);
            relief_checkpoint_destroy(ck2);
            bad = *g->hier;
            gb.matched = NULL;
            CHECK(relief_checkpoint_write(path, &key, &gb, &err) == RELIEF_OK, "%s",
                  err.message);
            CHECK(relief_checkpoint_read(path, &key, &ck2, &err) == RELIEF_E_PARSE &&
                      strstr(err.message, "without its matches"),
                  "a hierarchy's checkpoint without matches read back: %s", err.message);
            relief_checkpoint_destroy(ck2);
        }
        relief_checkpoint_destroy(ck);
        setup_free(&u), setup_free(&v);
    }
    /* A mono-scale state given to a hierarchy is refused. */
    {
        setup u;
        saver sv = {path, &key, 0};
        relief_grow_options g1 = relief_grow_options_default(), g2 = g1;
        relief_grow_stats st1, t2;
        relief_hierarchy_stats hs2;
        relief_checkpoint *ck = NULL;
        if (setup_make(&u, RELIEF_SEARCH_EXHAUSTIVE, &err)) {
            g1.save = save;
            g1.save_ctx = &sv;
            g1.cancel_after = 10;
            relief_grow(u.s, u.d, u.m, &u.p, &g1, &st1, &err);
            if (relief_checkpoint_read(path, &key, &ck, &err) == RELIEF_OK) {
                u.p.levels = 3;
                g2.resume = relief_checkpoint_state(ck);
                CHECK(grow_levels(&u, &g2, &hs2, &t2, &err) == RELIEF_E_USAGE &&
                          strstr(err.message, "mono-scale"),
                      "a mono-scale state resumed by a hierarchy: %s", err.message);
            } else {
                CHECK(0, "mono-scale checkpoint: %s", err.message);
            }
            relief_checkpoint_destroy(ck);
            setup_free(&u);
        }
    }
    remove(path);
    setup_free(&ref);
}

/* The k-coherence search reads the targets' sources too (and rebuilds its
 * similar pairs on resume): stopped and resumed, the same surface. */
static void check_resume_coherent(const char *path)
{
    relief_error err = {0};
    relief_grow_options go = relief_grow_options_default(), g1 = go, g2 = go;
    relief_grow_stats ref_stats, st1, st2;
    relief_checkpoint_key key;
    relief_checkpoint *ck = NULL;
    saver sv = {path, &key, 0};
    setup ref, u;
    if (!setup_make(&ref, RELIEF_SEARCH_COHERENT, &err)) {
        CHECK(0, "coherent set-up: %s", err.message);
        return;
    }
    relief_checkpoint_key_make(ref.capture, &ref.p, NULL, &go, &key);
    CHECK(relief_grow(ref.s, ref.d, ref.m, &ref.p, &go, &ref_stats, &err) == RELIEF_OK &&
              ref_stats.search == RELIEF_SEARCH_COHERENT,
          "coherent, uninterrupted: %s", err.message);
    g1.save = save;
    g1.save_ctx = &sv;
    g1.cancel_after = 40;
    if (setup_make(&u, RELIEF_SEARCH_COHERENT, &err)) {
        CHECK(relief_grow(u.s, u.d, u.m, &u.p, &g1, &st1, &err) == RELIEF_E_CANCELLED,
              "coherent, stop after 40: %s", err.message);
    }
    setup_free(&u);
    if (setup_make(&u, RELIEF_SEARCH_COHERENT, &err) &&
        relief_checkpoint_read(path, &key, &ck, &err) == RELIEF_OK) {
        g2.resume = relief_checkpoint_state(ck);
        CHECK(relief_grow(u.s, u.d, u.m, &u.p, &g2, &st2, &err) == RELIEF_OK,
              "coherent, resume: %s", err.message);
        CHECK(memcmp(u.s->mesh->pos, ref.s->mesh->pos, u.s->mesh->nv * 3 * sizeof(double)) ==
                      0 && same_counts(&st2, &ref_stats) &&
                  st2.search_hits == ref_stats.search_hits,
              "coherent, resumed after 40: the surface or counts differ from the "
              "uninterrupted run's");
    } else {
        CHECK(0, "coherent, read back: %s", err.message);
    }
    relief_checkpoint_destroy(ck);
    setup_free(&u);
    setup_free(&ref);
}

int main(void)
{
    relief_error err = {0};
    relief_grow_options go = relief_grow_options_default();
    relief_grow_stats ref_stats;
    relief_checkpoint_key key;
    setup ref;
    char path[256];
    const size_t stops[] = {1, 7, 40, 96};

    snprintf(path, sizeof path, "%s/ck", check_tmpdir());
    if (!setup_make(&ref, RELIEF_SEARCH_EXHAUSTIVE, &err)) {
        CHECK(0, "set-up: %s", err.message);
        return check_result();
    }
    relief_checkpoint_key_make(ref.capture, &ref.p, NULL, &go, &key);
    CHECK(relief_grow(ref.s, ref.d, ref.m, &ref.p, &go, &ref_stats, &err) == RELIEF_OK,
          "uninterrupted: %s", err.message);
    CHECK(ref_stats.rejections > 0 && ref_stats.threshold_raises > 0 &&
              ref_stats.window_shrinks > 0,
          "the reference run should reject (%zu), raise e (%zu) and shrink windows (%zu)",
          ref_stats.rejections, ref_stats.threshold_raises, ref_stats.window_shrinks);

    /* Stop after n acceptances, save, read back, resume: same result. */
    for (size_t i = 0; i < sizeof stops / sizeof stops[0]; ++i) {
        setup u;
        saver sv = {path, &key, 0};
        relief_grow_options g1 = relief_grow_options_default(), g2 = g1;
        relief_grow_stats st1, st2;
        relief_checkpoint *ck = NULL;
        relief_status st;
        if (!setup_make(&u, RELIEF_SEARCH_EXHAUSTIVE, &err)) {
            CHECK(0, "set-up: %s", err.message);
            break;
        }
        g1.save = save;
        g1.save_ctx = &sv;
        g1.cancel_after = stops[i];
        st = relief_grow(u.s, u.d, u.m, &u.p, &g1, &st1, &err);
        CHECK(st == RELIEF_E_CANCELLED && sv.calls == 1 && st1.acceptances == stops[i],
              "stop after %zu: status %s, %d saves, %zu acceptances", stops[i],
              relief_status_name(st), sv.calls, st1.acceptances);
        setup_free(&u);
        /* A fresh surface, as a new process would build. */
        if (!setup_make(&u, RELIEF_SEARCH_EXHAUSTIVE, &err)) {
            CHECK(0, "set-up: %s", err.message);
            break;
        }
        st = relief_checkpoint_read(path, &key, &ck, &err);
        CHECK(st == RELIEF_OK, "read back: %s", err.message);
        if (st == RELIEF_OK) {
            g2.resume = relief_checkpoint_state(ck);
            st = relief_grow(u.s, u.d, u.m, &u.p, &g2, &st2, &err);
            CHECK(st == RELIEF_OK, "resume after %zu: %s", stops[i], err.message);
            CHECK(memcmp(u.s->mesh->pos, ref.s->mesh->pos,
                         u.s->mesh->nv * 3 * sizeof(double)) == 0 &&
                      memcmp(u.s->mesh->col, ref.s->mesh->col,
                             u.s->mesh->nv * 3 * sizeof(float)) == 0,
                  "resumed after %zu: the surface differs from the uninterrupted one",
                  stops[i]);
            CHECK(same_counts(&st2, &ref_stats),
                  "resumed after %zu: %zu passes, %zu candidates, %zu rejections; "
                  "uninterrupted %zu, %zu, %zu",
                  stops[i], st2.passes, st2.candidates, st2.rejections, ref_stats.passes,
                  ref_stats.candidates, ref_stats.rejections);
        }
        relief_checkpoint_destroy(ck);
        setup_free(&u);
    }

    /* Saving every moment (before each target) changes nothing. */
    {
        setup u;
        saver sv = {path, &key, 0};
        relief_grow_options g = relief_grow_options_default();
        relief_grow_stats st1;
        if (setup_make(&u, RELIEF_SEARCH_EXHAUSTIVE, &err)) {
            g.save = save;
            g.save_ctx = &sv;
            g.save_every = 1e-12;
            CHECK(relief_grow(u.s, u.d, u.m, &u.p, &g, &st1, &err) == RELIEF_OK,
                  "saving all the time: %s", err.message);
            CHECK((size_t)sv.calls == st1.acceptances + st1.rejections,
                  "%d periodic saves for %zu targets scored", sv.calls,
                  st1.acceptances + st1.rejections);
            CHECK(memcmp(u.s->mesh->pos, ref.s->mesh->pos,
                         u.s->mesh->nv * 3 * sizeof(double)) == 0 &&
                      same_counts(&st1, &ref_stats),
                  "periodic saves changed the result");
        }
        setup_free(&u);
    }

    /* The cancel flag (what SIGINT sets) stops before the next target. */
    {
        setup u;
        volatile sig_atomic_t flag = 1;
        relief_grow_options g = relief_grow_options_default();
        relief_grow_stats st1;
        if (setup_make(&u, RELIEF_SEARCH_EXHAUSTIVE, &err)) {
            g.cancel = &flag;
            CHECK(relief_grow(u.s, u.d, u.m, &u.p, &g, &st1, &err) == RELIEF_E_CANCELLED &&
                      st1.acceptances == 0 && strstr(err.message, "interrupted after 0 of"),
                  "a set cancel flag: %s, %zu acceptances", err.message, st1.acceptances);
        }
        setup_free(&u);
    }

    /* Every truncation, and a flipped byte anywhere, is refused cleanly. */
    {
        setup u;
        saver sv = {path, &key, 0};
        relief_grow_options g = relief_grow_options_default();
        relief_grow_stats st1;
        size_t n;
        unsigned char *bytes;
        FILE *f;
        char cut[256];
        snprintf(cut, sizeof cut, "%s/cut", check_tmpdir());
        if (!setup_make(&u, RELIEF_SEARCH_EXHAUSTIVE, &err)) {
            CHECK(0, "set-up: %s", err.message);
            return check_result();
        }
        g.save = save;
        g.save_ctx = &sv;
        g.cancel_after = 30;
        relief_grow(u.s, u.d, u.m, &u.p, &g, &st1, &err);
        setup_free(&u);
        n = file_size(path);
        bytes = malloc(n + 1);
        f = fopen(path, "rb");
        CHECK(f && bytes && fread(bytes, 1, n, f) == n, "cannot read %s back", path);
        if (f)
            fclose(f);
        for (size_t len = 0; bytes && len < n; len += 1 + len / 8) {
            relief_checkpoint *ck = NULL;
            relief_status st;
            check_write_file(cut, bytes, len);
            st = relief_checkpoint_read(cut, &key, &ck, &err);
            CHECK(st == RELIEF_E_PARSE, "a checkpoint cut to %zu of %zu bytes: %s", len, n,
                  relief_status_name(st));
            relief_checkpoint_destroy(ck);
        }
        for (size_t at = 0; bytes && at < n; at += 1 + at / 4) {
            relief_checkpoint *ck = NULL;
            relief_status st;
            bytes[at] ^= 0x10;
            check_write_file(cut, bytes, n);
            bytes[at] ^= 0x10;
            st = relief_checkpoint_read(cut, &key, &ck, &err);
            CHECK(st == RELIEF_E_PARSE || st == RELIEF_E_USAGE,
                  "byte %zu of %zu flipped: %s", at, n, relief_status_name(st));
            relief_checkpoint_destroy(ck);
        }
        free(bytes);
        remove(cut);
    }

    /* Another input or other parameters: refused, naming what differs. */
    {
        relief_checkpoint_key other = key;
        relief_checkpoint *ck = NULL;
        relief_params p2 = ref.p;
        other.input_hash ^= 1;
        CHECK(relief_checkpoint_read(path, &other, &ck, &err) == RELIEF_E_USAGE &&
                  strstr(err.message, "different input"),
              "another input: %s", err.message);
        /* Labels choose holes (hole_labels): another labelling is another input. */
        {
            relief_mesh *lab = NULL;
            relief_checkpoint_key relabelled;
            CHECK(relief_mesh_copy(ref.capture, &lab, &err) == RELIEF_OK && lab->label,
                  "a labelled copy of the capture");
            if (lab && lab->label) {
                lab->label[0] ^= 1;
                relief_checkpoint_key_make(lab, &ref.p, NULL, &go, &relabelled);
                CHECK(relabelled.input_hash != key.input_hash, "a label changed, the same input");
            }
            relief_mesh_destroy(lab);
        }
        p2.rotations = 8;
        relief_checkpoint_key_make(ref.capture, &p2, NULL, &go, &other);
        CHECK(relief_checkpoint_read(path, &other, &ck, &err) == RELIEF_E_USAGE &&
                  strstr(err.message, "rotations=0, this run has rotations=8"),
              "other parameters: %s", err.message);
        relief_checkpoint_destroy(ck);
    }
    remove(path);
    check_hierarchy(path);
    check_resume_coherent(path);
    remove(path);
    rmdir(check_tmpdir());
    setup_free(&ref);
    return check_result();
}
