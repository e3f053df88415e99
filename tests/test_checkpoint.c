/* Checkpoints: a growth stopped after N acceptances, saved, read back and
 * resumed gives the same surface and counts as one never stopped, whatever
 * N; saving before every target changes nothing; the cancel flag stops it
 * between two targets; a checkpoint that is truncated, corrupt or of
 * another input or parameters is refused. */
#include <signal.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "checkpoint.h"
#include "grow.h"
#include "matcher.h"
#include "mesh.h"
#include "surface.h"

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

/* A small coloured plane with a low threshold: rejections, shrunk windows
 * and threshold raises, so every part of the state matters. */
static int setup_make(setup *u, relief_error *err)
{
    relief_synth_params sp = relief_synth_params_default();
    memset(u, 0, sizeof *u);
    sp.kind = RELIEF_SYNTH_PLANE_WAVES;
    sp.vertices = 500;
    sp.colour = 1;
    u->p = relief_params_default();
    u->p.window = 2;
    u->p.error = 0.03;
    return relief_synth(&sp, &u->capture, NULL, err) == RELIEF_OK &&
           relief_smooth(u->capture, &u->p, NULL, &u->s, err) == RELIEF_OK &&
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

int main(void)
{
    relief_error err = {RELIEF_OK, ""};
    relief_grow_options go = relief_grow_options_default();
    relief_grow_stats ref_stats;
    relief_checkpoint_key key;
    setup ref;
    char path[256];
    const size_t stops[] = {1, 7, 40, 96};

    snprintf(path, sizeof path, "%s/ck", check_tmpdir());
    if (!setup_make(&ref, &err)) {
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
        if (!setup_make(&u, &err)) {
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
        if (!setup_make(&u, &err)) {
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
        if (setup_make(&u, &err)) {
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
        if (setup_make(&u, &err)) {
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
        if (!setup_make(&u, &err)) {
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
        p2.rotations = 8;
        relief_checkpoint_key_make(ref.capture, &p2, NULL, &go, &other);
        CHECK(relief_checkpoint_read(path, &other, &ck, &err) == RELIEF_E_USAGE &&
                  strstr(err.message, "rotations=4, this run has rotations=8"),
              "other parameters: %s", err.message);
        relief_checkpoint_destroy(ck);
    }
    remove(path);
    rmdir(check_tmpdir());
    setup_free(&ref);
    return check_result();
}
