/* relief_eval (relief/eval.h): the measures of a completion (measures.h),
 * its pattern distances (pattern.h) and its closure where it completed
 * (mesh/mesh_check.h), as the figures a caller reads and as the JSON and
 * the lines `relief eval` prints. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "relief/relief.h"
#include "base/error.h"
#include "base/json.h"
#include "base/numtext.h"
#include "mesh/mesh.h"
#include "mesh/mesh_check.h"
#include "report/measures.h"
#include "report/pattern.h"

/* What relief_eval measured, for its renderings. */
typedef struct eval_measures {
    const relief_measures *m;
    const relief_pattern *pat;
    relief_closure closure;
} eval_measures;

static void print_measures_text(FILE *f, const relief_measures *m)
{
    fprintf(f, "primitive: %s\n", relief_fit_model_name(m->prim.model));
    fprintf(f, "vertices: %zu captured, %zu completed\n", m->n_captured, m->n_completed);
    fprintf(f, "msi_captured: %.6g\nmsi_completed: %.6g\nmsi_diff_percent: %.3f\n",
            m->msi_captured, m->msi_completed, m->msi_diff_percent);
    fprintf(f, "hist_distance_displacement: %.4f\n", m->hist_distance_displacement);
    if (m->has_colour)
        fprintf(f, "hist_distance_colour: %.4f\n", m->hist_distance_colour);
    fprintf(f, "seam: %.6g (over %zu edges), inside: %.6g (%zu edges), seam_ratio: %.3f\n",
            m->seam, m->n_seam_edges, m->inside, m->n_inside_edges, m->seam_ratio);
    fprintf(f, "freq_captured: %.4g\nfreq_completed: %.4g\n", m->freq_captured.freq,
            m->freq_completed.freq);
    if (m->has_truth) {
        fprintf(f, "truth_rms: %.6g (over %zu completed vertices on the truth)\n", m->truth_rms,
                m->n_completed - m->n_truth_outside);
        fprintf(f, "truth_outside: %zu", m->n_truth_outside);
        if (m->n_truth_outside)
            fprintf(f, " (rms %.6g against the nearest truth vertex)", m->truth_rms_outside);
        fprintf(f, "\nfreq_truth: %.4g\n", m->freq_truth.freq);
    }
}

/* One line per pattern distance, the truth's own floor beside it; then
 * the parts' lean-across shares, the truth's parts beside them. */
static void print_pattern_text(FILE *f, const char *what, const relief_pattern_distance *d,
                               const relief_pattern_distance *floor,
                               const relief_pattern_part *part,
                               const relief_pattern_part *truth)
{
    static const char *const names[] = {"spectrum", "orientation", "radial", "tensor", "lean"};
    const double v[] = {d->spectrum, d->orientation, d->radial, d->tensor, d->lean};
    const double fl[] = {floor ? floor->spectrum : NAN, floor ? floor->orientation : NAN,
                         floor ? floor->radial : NAN, floor ? floor->tensor : NAN,
                         floor ? floor->lean : NAN};
    for (int i = 0; i < 5; ++i) {
        fprintf(f, "pattern_%s_distance%s: %.4f", names[i], what, v[i]);
        if (floor)
            fprintf(f, " (truth's own: %.4f)", fl[i]);
        fputc('\n', f);
    }
    fprintf(f, "pattern_lean_across%s: captured %.4f, completed %.4f", what, part[0].lean_across,
            part[1].lean_across);
    if (truth)
        fprintf(f, " (truth's own: captured %.4f, missing %.4f)", truth[0].lean_across,
                truth[1].lean_across);
    fputc('\n', f);
}

static void write_text(FILE *f, const eval_measures *e)
{
    const relief_pattern *pat = e->pat;
    print_measures_text(f, e->m);
    print_pattern_text(f, "", &pat->d_height, pat->has_truth ? &pat->d_truth_height : NULL,
                       pat->height, pat->has_truth ? pat->truth_height : NULL);
    if (pat->has_colour)
        print_pattern_text(f, "_colour", &pat->d_colour,
                           pat->has_truth_colour ? &pat->d_truth_colour : NULL, pat->colour,
                           pat->has_truth_colour ? pat->truth_colour : NULL);
    fprintf(f, "open_loops_completed: %zu\nopen_edges_completed: %zu\n",
            e->closure.open_loops, e->closure.open_edges);
    fprintf(f, "nonmanifold_edges_completed: %zu\nself_intersections_completed: %zu\n",
            e->closure.nonmanifold_edges, e->closure.self_intersections);
}

static void write_json(FILE *f, const eval_measures *e)
{
    relief_json j;
    rj_init(&j, f);
    rj_begin_object(&j, NULL);
    relief_report_measures_fields(&j, e->m);
    relief_pattern_json_fields(&j, e->pat);
    rj_int(&j, "open_loops_completed", (long long)e->closure.open_loops);
    rj_int(&j, "open_edges_completed", (long long)e->closure.open_edges);
    rj_int(&j, "nonmanifold_edges_completed", (long long)e->closure.nonmanifold_edges);
    rj_int(&j, "self_intersections_completed", (long long)e->closure.self_intersections);
    rj_end_object(&j);
}

/* What write(f, e) writes, as a string, its numbers in the C locale
 * ("0.5" whatever the caller's); NULL when out of memory. */
static char *render(void (*write)(FILE *, const eval_measures *), const eval_measures *e)
{
    char *buf = NULL;
    size_t len = 0;
    FILE *f = open_memstream(&buf, &len);
    relief_numtext_scope c;
    if (!f)
        return NULL;
    relief_numtext_begin(&c);
    write(f, e);
    relief_numtext_end(&c);
    if (fclose(f) != 0) {
        free(buf);
        return NULL;
    }
    return buf;
}

static void fill(relief_eval_result *out, const eval_measures *e)
{
    const relief_measures *m = e->m;
    out->prim = m->prim;
    out->captured = m->n_captured;
    out->completed = m->n_completed;
    out->msi_captured = m->msi_captured;
    out->msi_completed = m->msi_completed;
    out->msi_diff_percent = m->msi_diff_percent;
    out->hist_distance_displacement = m->hist_distance_displacement;
    out->hist_distance_colour = m->has_colour ? m->hist_distance_colour : NAN;
    out->seam_ratio = m->seam_ratio;
    out->pattern_spectrum_distance = e->pat->d_height.spectrum;
    out->has_truth = m->has_truth;
    out->truth_rms = m->has_truth ? m->truth_rms : NAN;
    out->open_loops_completed = e->closure.open_loops;
    out->open_edges_completed = e->closure.open_edges;
    out->nonmanifold_edges_completed = e->closure.nonmanifold_edges;
    out->self_intersections_completed = e->closure.self_intersections;
}

relief_status relief_eval(const relief_mesh *completed, const relief_mesh *truth,
                          relief_eval_result *out, relief_error *err)
{
    RELIEF_ENTRY_ERR(err);
    relief_measures *m;
    relief_pattern *pat;
    relief_eval_result r;
    eval_measures e;
    relief_status st;
    if (!completed || !out)
        return relief_fail(err, RELIEF_E_USAGE, "%s is NULL", !completed ? "completed" : "out");
    m = malloc(sizeof *m);
    pat = malloc(sizeof *pat);
    memset(&r, 0, sizeof r);
    st = m && pat ? relief_measure(completed, truth, NULL, m, err)
                  : relief_fail(err, RELIEF_E_NOMEM, "cannot allocate the measures");
    if (st == RELIEF_OK)
        st = relief_pattern_measure(completed, &m->prim, truth, pat, err);
    e.m = m, e.pat = pat;
    if (st == RELIEF_OK) /* relief_measure has checked the labels are there */
        st = relief_closure_check(completed->pos, completed->nv, completed->tri, completed->nt,
                                  completed->label, &e.closure, err);
    if (st == RELIEF_OK) {
        fill(&r, &e);
        r.json = render(write_json, &e);
        r.text = render(write_text, &e);
        if (!r.json || !r.text) {
            relief_eval_result_free(&r);
            st = relief_fail(err, RELIEF_E_NOMEM, "cannot write the measures");
        }
    }
    if (st == RELIEF_OK)
        *out = r;
    free(m);
    free(pat);
    return st;
}

void relief_eval_result_free(relief_eval_result *r)
{
    if (!r)
        return;
    free(r->json);
    free(r->text);
    memset(r, 0, sizeof *r);
}
