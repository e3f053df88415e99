#include "report/report_dir.h"

#include <dirent.h>
#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "base/compare.h"
#include "base/error.h"
#include "base/numtext.h"
#include "base/output.h"
#include "base/vec3.h"
#include "mesh/mesh.h"
#include "report/png.h"
#include "report/render.h"

struct relief_report_dir {
    relief_staged_folder *staged; /* beside where the report goes */
};

/* What the marker file starts with (then the version and a newline). */
#define MARKER_TEXT "relief report folder; relief may replace it as a whole\nversion "

#define N_VIEWS 3
#define N_STAGES 5

static const struct {
    const char *file, *title, *note;
} stages[N_STAGES] = {
    {"captured", "Captured input", "the input as read"},
    {"smooth", "Smooth completion", "the primitive laid over the missing part, before growth"},
    {"final", "Final completion", "relief and colour grown over the missing part"},
    {"labels", "Completed vertices", "grey: captured, orange: completed"},
    {"displacement", "Displacement", "height above (red) or below (blue) the primitive"},
};

/* ------------------------------------------------------------ folders */

static int is_report_file(const char *name)
{
    size_t n = strlen(name);
    return strcmp(name, RELIEF_REPORT_DIR_MARKER) == 0 || strcmp(name, "index.html") == 0 ||
           strcmp(name, "report.json") == 0 ||
           (n > 4 && (strcmp(name + n - 4, ".png") == 0 || strcmp(name + n - 4, ".svg") == 0));
}

/* Does the folder `path` carry relief's marker? */
static int has_marker(const char *path)
{
    char full[PATH_MAX], head[sizeof MARKER_TEXT - 1];
    FILE *f;
    size_t got = 0;
    if ((size_t)snprintf(full, sizeof full, "%s/%s", path, RELIEF_REPORT_DIR_MARKER) >=
            sizeof full ||
        !(f = fopen(full, "rb")))
        return 0;
    got = fread(head, 1, sizeof head, f);
    fclose(f);
    return got == sizeof head && memcmp(head, MARKER_TEXT, sizeof head) == 0;
}

/* The first entry of the folder `path` that a report does not write, or
 * that is no plain file, into `name` (size bytes); 0 when there is none,
 * -1 when the folder cannot be read (errno). *empty: it has no entry. */
static int foreign_entry(const char *path, char *name, size_t size, int *empty)
{
    DIR *d = opendir(path);
    struct dirent *e;
    int found = 0;
    *empty = 1;
    if (!d)
        return -1;
    while (!found && (e = readdir(d)) != NULL) {
        char full[PATH_MAX];
        struct stat sb;
        if (strcmp(e->d_name, ".") == 0 || strcmp(e->d_name, "..") == 0)
            continue;
        *empty = 0;
        snprintf(full, sizeof full, "%s/%s", path, e->d_name);
        if (!is_report_file(e->d_name) || lstat(full, &sb) != 0 || !S_ISREG(sb.st_mode)) {
            snprintf(name, size, "%s", e->d_name);
            found = 1;
        }
    }
    closedir(d);
    return found;
}

/* May the report folder at `path`, which is there, be replaced: an empty
 * folder, or a report relief wrote (its marker) holding nothing else? 1,
 * or 0 with err saying why not. */
static int replaceable(const char *path, relief_error *err)
{
    struct stat sb;
    char name[256];
    int empty, foreign;
    if (lstat(path, &sb) != 0) {
        relief_fail_errno(err, errno, path, "cannot inspect");
        return 0;
    }
    if (!S_ISDIR(sb.st_mode)) {
        relief_fail_reason(err, RELIEF_E_IO, RELIEF_REASON_NOT_RELIEFS, "%s: exists and is not "
                           "a folder; a report folder needs a folder name", path);
        return 0;
    }
    if ((foreign = foreign_entry(path, name, sizeof name, &empty)) < 0) {
        relief_fail_errno(err, errno, path, "cannot read the folder");
        return 0;
    }
    if (!empty && !has_marker(path)) {
        relief_fail_reason(err, RELIEF_E_IO, RELIEF_REASON_NOT_RELIEFS, "%s: is a folder relief "
                           "did not write (no %s marker); refusing to replace it: name a new "
                           "or empty folder", path, RELIEF_REPORT_DIR_MARKER);
        return 0;
    }
    if (foreign) {
        relief_fail_reason(err, RELIEF_E_IO, RELIEF_REASON_NOT_RELIEFS, "%s: holds '%s', which "
                           "a relief report does not write; refusing to replace the folder",
                           path, name);
        return 0;
    }
    return 1;
}

relief_status relief_report_dir_check(const char *dir, relief_error *err)
{
    const char *name;
    char *parent;
    struct stat sb;
    relief_status st = RELIEF_OK;
    if (!dir || !dir[0])
        return relief_fail(err, RELIEF_E_USAGE, "report folder: empty name");
    if (!(parent = relief_output_split(dir, &name)))
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate a path");
    if (stat(parent, &sb) != 0 || !S_ISDIR(sb.st_mode))
        st = relief_fail(err, RELIEF_E_IO, "%s: the folder it goes in, '%s', does not exist",
                         dir, parent);
    else if (access(parent, W_OK | X_OK) != 0)
        st = relief_fail_errno(err, errno, dir, "cannot write in the folder it goes in");
    else if (lstat(dir, &sb) == 0 && !replaceable(dir, err))
        st = err->status;
    free(parent);
    return st;
}

void relief_report_dir_abort(relief_report_dir *r)
{
    if (!r)
        return;
    relief_staged_folder_abort(r->staged);
    free(r);
}

relief_status relief_report_dir_commit(relief_report_dir *r, relief_error *err)
{
    relief_staged_folder *s;
    if (!r)
        return relief_fail(err, RELIEF_E_USAGE, "relief_report_dir_commit: NULL report");
    s = relief_report_dir_release(r);
    return relief_staged_folder_commit(s, replaceable, err);
}

relief_staged_folder *relief_report_dir_release(relief_report_dir *r)
{
    relief_staged_folder *s = r->staged;
    free(r);
    return s;
}

int relief_report_dir_replaceable(const char *path, relief_error *err)
{
    return replaceable(path, err);
}

/* ------------------------------------------------------------ writers */

/* What text_sink writes: fn(f, ctx), 0 on success. */
typedef struct text_job {
    int (*fn)(FILE *f, void *ctx);
    void *ctx;
} text_job;

static relief_status text_sink(relief_sink *s, void *ctx, relief_error *err)
{
    const text_job *j = ctx;
    if (j->fn(s->f, j->ctx) != 0)
        return relief_fail_errno(err, errno ? errno : EIO, s->path, "cannot write");
    return RELIEF_OK;
}

/* A new file `name` in the staged folder, written by fn(f, ctx); messages
 * name it where it will stand (DIR/name). */
static relief_status write_in(const relief_report_dir *r, const char *name,
                              int (*fn)(FILE *f, void *ctx), void *ctx, relief_error *err)
{
    char path[PATH_MAX], shown[PATH_MAX];
    text_job j = {fn, ctx};
    snprintf(path, sizeof path, "%s/%s", relief_staged_folder_path(r->staged), name);
    snprintf(shown, sizeof shown, "%s/%s", relief_staged_folder_target(r->staged), name);
    errno = 0;
    return relief_output_plain(path, shown, text_sink, &j, err);
}

static int marker_text(FILE *f, void *ctx)
{
    (void)ctx;
    return fprintf(f, "%s%s\n", MARKER_TEXT, RELIEF_VERSION_STRING) < 0;
}

/* Text with &, <, > and " escaped. */
static void html_text(FILE *f, const char *s)
{
    for (; *s; ++s)
        switch (*s) {
        case '&': fputs("&amp;", f); break;
        case '<': fputs("&lt;", f); break;
        case '>': fputs("&gt;", f); break;
        case '"': fputs("&quot;", f); break;
        default: fputc(*s, f);
        }
}

/* A number for people: 4 significant digits, "n/a" for NaN. */
static const char *num(char *buf, size_t n, double v)
{
    if (isnan(v))
        snprintf(buf, n, "n/a");
    else
        snprintf(buf, n, "%.4g", v);
    return buf;
}

/* ---------------------------------------------------------- histograms */

typedef struct histogram {
    double p[2][RELIEF_MEASURE_HIST_BINS]; /* captured, completed; each sums to 1 */
    size_t n[2];
    double lo, hi;                         /* the bins span [lo, hi] */
    double tv;                             /* 0.5 sum |p0 - p1| */
} histogram;

/* Bin x[v] over [lo, hi] by the vertices' labels (the measures' binning:
 * the maximum goes in the last bin). */
static void histogram_fill(histogram *h, const double *x, const uint8_t *label,
                           size_t nv, double lo, double hi)
{
    const int bins = RELIEF_MEASURE_HIST_BINS;
    memset(h, 0, sizeof *h);
    h->lo = lo;
    h->hi = hi;
    for (size_t v = 0; v < nv; ++v) {
        int part = label[v] == RELIEF_LABEL_COMPLETED, b = 0;
        double t = x[v];
        if (hi > lo)
            b = (int)floor((fmin(hi, fmax(lo, t)) - lo) / (hi - lo) * bins);
        b = b < 0 ? 0 : b >= bins ? bins - 1 : b;
        h->p[part][b] += 1.0;
        h->n[part]++;
    }
    for (int part = 0; part < 2; ++part)
        for (int b = 0; b < bins; ++b)
            h->p[part][b] /= h->n[part] ? (double)h->n[part] : 1.0;
    for (int b = 0; b < bins; ++b)
        h->tv += 0.5 * fabs(h->p[0][b] - h->p[1][b]);
}

static const char *part_fill[2] = {"rgba(74,111,165,0.45)", "rgba(240,133,25,0.45)"};
static const char *part_line[2] = {"#35557f", "#c0640a"};

static int svg_histogram(FILE *f, const histogram *h, const char *title, const char *xlabel)
{
    const int bins = RELIEF_MEASURE_HIST_BINS, W = 440, H = 280, L = 56, R = 30, T = 52,
              B = 48;
    const double pw = W - L - R, ph = H - T - B;
    double top = 0.0;
    char a[32], b[32], c[32];
    for (int part = 0; part < 2; ++part)
        for (int i = 0; i < bins; ++i)
            top = fmax(top, h->p[part][i]);
    top = top > 0.0 ? top * 1.08 : 1.0; /* headroom above the highest bar */
    fprintf(f, "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"%d\" height=\"%d\" "
               "viewBox=\"0 0 %d %d\" font-family=\"sans-serif\" font-size=\"12\">\n",
            W, H, W, H);
    fprintf(f, "<rect width=\"%d\" height=\"%d\" fill=\"white\"/>\n", W, H);
    fprintf(f, "<text x=\"%d\" y=\"18\" font-size=\"14\" font-weight=\"bold\">", L);
    html_text(f, title);
    fprintf(f, "</text>\n<text x=\"%d\" y=\"18\" text-anchor=\"end\" fill=\"#444\">"
               "TV distance %.3f</text>\n", W - R, h->tv);
    for (int part = 0; part < 2; ++part) {
        fprintf(f, "<path fill=\"%s\" stroke=\"%s\" stroke-width=\"1.2\" d=\"M%.1f %.1f",
                part_fill[part], part_line[part], (double)L, (double)(T + ph));
        for (int i = 0; i < bins; ++i) {
            double y = T + ph - ph * h->p[part][i] / top;
            fprintf(f, " L%.1f %.1f L%.1f %.1f", L + pw * i / bins, y, L + pw * (i + 1) / bins,
                    y);
        }
        fprintf(f, " L%.1f %.1f Z\"/>\n", L + pw, (double)(T + ph));
    }
    /* axes, ticks at both ends and the middle */
    fprintf(f, "<path stroke=\"#222\" fill=\"none\" d=\"M%d %d V%.1f H%.1f\"/>\n", L, T,
            T + ph, L + pw);
    for (int i = 0; i <= 2; ++i) {
        double x = L + pw * i / 2.0, y = T + ph - ph * i / 2.0;
        fprintf(f, "<path stroke=\"#222\" d=\"M%.1f %.1f v5 M%d %.1f h-5\"/>\n", x, T + ph, L,
                y);
        fprintf(f, "<text x=\"%.1f\" y=\"%.1f\" text-anchor=\"middle\">%s</text>\n", x,
                T + ph + 18, num(a, sizeof a, h->lo + (h->hi - h->lo) * i / 2.0));
        fprintf(f, "<text x=\"%d\" y=\"%.1f\" text-anchor=\"end\">%.1f%%</text>\n", L - 8,
                y + 4, 100.0 * top * i / 2.0);
    }
    fprintf(f, "<text x=\"%.1f\" y=\"%d\" text-anchor=\"middle\" fill=\"#444\">", L + pw / 2,
            H - 8);
    html_text(f, xlabel);
    fputs("</text>\n", f);
    snprintf(b, sizeof b, "%zu", h->n[0]);
    snprintf(c, sizeof c, "%zu", h->n[1]);
    for (int part = 0; part < 2; ++part) { /* legend: one row under the title */
        double x = L + 190.0 * part;
        fprintf(f, "<rect x=\"%.1f\" y=\"29\" width=\"14\" height=\"10\" fill=\"%s\" "
                   "stroke=\"%s\"/>\n<text x=\"%.1f\" y=\"38\">%s (%s vertices)</text>\n",
                x, part_fill[part], part_line[part], x + 20, part ? "completed" : "captured",
                part ? c : b);
    }
    fputs("</svg>\n", f);
    return 0;
}

/* What svg_job writes. */
typedef struct svg_job {
    const histogram *h;
    const char *title, *xlabel;
} svg_job;

static int svg_text(FILE *f, void *ctx)
{
    const svg_job *j = ctx;
    return svg_histogram(f, j->h, j->title, j->xlabel);
}

static relief_status write_svg(const relief_report_dir *r, const char *name,
                               const histogram *h, const char *title, const char *xlabel,
                               relief_error *err)
{
    svg_job j = {h, title, xlabel};
    return write_in(r, name, svg_text, &j, err);
}

/* --------------------------------------------------------------- html */

static void row(FILE *f, const char *name, const char *fmt, ...) RELIEF_PRINTF(3, 4);
static void row(FILE *f, const char *name, const char *fmt, ...)
{
    char buf[1024];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(buf, sizeof buf, fmt, ap);
    va_end(ap);
    fputs("<tr><th>", f);
    html_text(f, name);
    fputs("</th><td>", f);
    html_text(f, buf);
    fputs("</td></tr>\n", f);
}

static const char css[] =
    "body{font-family:sans-serif;margin:24px;color:#222;max-width:1400px}"
    "h1{font-size:22px}h2{font-size:18px;margin-top:28px;border-bottom:1px solid #ccc}"
    ".figs{display:flex;flex-wrap:wrap;gap:24px;align-items:flex-start}"
    "table.kv{border-collapse:collapse;font-size:13px}"
    "table.kv th{text-align:left;font-weight:normal;color:#555;padding:2px 14px 2px 0}"
    "table.kv td{font-family:monospace;padding:2px 0;max-width:460px;overflow-wrap:anywhere}"
    "table.kv caption{text-align:left;font-weight:bold;padding-bottom:4px}"
    "table.renders{border-collapse:collapse}"
    "table.renders td,table.renders th{padding:4px;vertical-align:top;font-size:13px}"
    "table.renders th{text-align:left;font-weight:normal}"
    "table.renders img{width:100%;max-width:420px;border:1px solid #ddd}"
    ".note{color:#666;font-size:12px}"
    ".swatch{display:inline-block;width:12px;height:12px;border:1px solid #888;"
    "vertical-align:middle;margin:0 4px}"
    ".bar{display:inline-block;width:160px;height:12px;vertical-align:middle;margin:0 6px;"
    "background:linear-gradient(to right,rgb(59,77,191),rgb(222,222,222),rgb(181,5,38))}";

static void write_figures(FILE *f, const relief_report_content *c)
{
    const relief_surface *s = c->surface;
    const relief_grow_stats *g = c->stats;
    const relief_measures *m = c->measures;
    char a[32], b[32];

    fputs("<div class=\"figs\">\n<table class=\"kv\"><caption>Input and fit</caption>\n", f);
    row(f, "input", "%s", c->input);
    row(f, "output", "%s", c->output);
    row(f, "primitive", "%s", relief_fit_model_name(s->fit.prim.model));
    row(f, "fit rms", "%s (%s)", num(a, sizeof a, s->fit.rms), s->fit.reason);
    row(f, "spacing", "%s (%s)", num(b, sizeof b, s->spacing),
        s->spacing_from_capture ? "from the capture" : "given");
    fputs("</table>\n<table class=\"kv\"><caption>Counts</caption>\n", f);
    row(f, "captured vertices", "%zu", s->n_captured);
    row(f, "samples (oversampled)", "%zu", s->n_samples);
    row(f, "targets", "%zu", s->n_targets);
    row(f, "region completed", "%s: %zu holes (%zu points); %zu points outside the outline; "
        "the capture covers %.1f%%", relief_fill_region_name(s->fill.region), s->fill.holes,
        s->fill.hole_points, s->fill.outside_points, 100.0 * s->fill.cover);
    row(f, "triangles", "%zu", s->mesh->nt);
    row(f, "left out (duplicates)", "%zu", s->n_dropped);
    row(f, "folded triangles (dropped with their vertices)", "%zu (%zu vertices)",
        s->folds.triangles, s->folds.vertices_dropped);
    row(f, "scanner spikes left out", "%zu", s->spikes.vertices);
    fputs("</table>\n<table class=\"kv\"><caption>Growth</caption>\n", f);
    row(f, "levels, window, rotations", "%d, %d, %d", c->params->levels, c->params->window,
        c->params->rotations);
    row(f, "mu, seed, coherence", "%s, %lu, %s", num(a, sizeof a, g->mu),
        (unsigned long)c->params->seed, num(b, sizeof b, c->params->coherence));
    row(f, "passes", "%zu", g->passes);
    row(f, "acceptances", "%zu (%zu coherent)", g->acceptances, g->coherent);
    row(f, "rejections", "%zu", g->rejections);
    row(f, "threshold raises", "%zu (e %s to %s)", g->threshold_raises,
        num(a, sizeof a, c->params->error), num(b, sizeof b, g->error_final));
    row(f, "candidates scored", "%zu (%zu pruned)", g->candidates, g->pruned);
    if (g->search == RELIEF_SEARCH_COHERENT)
        row(f, "search", "coherent, k %d: %zu accepted from the continuations, %zu fell back "
            "to every sample (%zu with none); built in %.2f s", c->params->search_k,
            g->search_hits, g->search_misses + g->search_empty, g->search_empty,
            g->search_seconds);
    else
        row(f, "search", "exhaustive");
    row(f, "backend", "%s: %s", c->backend, c->device);
    fputs("</table>\n<table class=\"kv\"><caption>Timings (s)</caption>\n", f);
    row(f, "fit", "%.3f", s->seconds[RELIEF_STAGE_FIT]);
    row(f, "targets", "%.3f", s->seconds[RELIEF_STAGE_TARGETS]);
    row(f, "oversample", "%.3f", s->seconds[RELIEF_STAGE_OVERSAMPLE]);
    row(f, "triangulate", "%.3f", s->seconds[RELIEF_STAGE_TRIANGULATE]);
    row(f, "growth", "%.3f", g->seconds);
    row(f, "of which matching", "%.3f", g->match_seconds);
    row(f, "total", "%.3f", c->seconds_total);
    fputs("</table>\n", f);
    if (m) {
        fputs("<table class=\"kv\"><caption>Measures</caption>\n", f);
        row(f, "MSI captured", "%s", num(a, sizeof a, m->msi_captured));
        row(f, "MSI completed", "%s", num(a, sizeof a, m->msi_completed));
        row(f, "MSI difference", "%s %%", num(a, sizeof a, m->msi_diff_percent));
        row(f, "displacement histogram distance", "%s",
            num(a, sizeof a, m->hist_distance_displacement));
        if (m->has_colour)
            row(f, "colour histogram distance", "%s",
                num(a, sizeof a, m->hist_distance_colour));
        row(f, "seam ratio", "%s", num(a, sizeof a, m->seam_ratio));
        row(f, "frequency captured, completed", "%s, %s",
            num(a, sizeof a, m->freq_captured.freq), num(b, sizeof b, m->freq_completed.freq));
        fputs("</table>\n", f);
    }
    fputs("</div>\n", f);
}

static int write_html(FILE *f, const relief_report_content *c, const double view[N_VIEWS][2],
                      double range, int has_colour)
{
    char a[32];
    fputs("<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\n<title>relief: ",
          f);
    html_text(f, c->input);
    fprintf(f, "</title>\n<style>%s</style></head><body>\n<h1>relief complete: ", css);
    html_text(f, c->input);
    fputs("</h1>\n<p class=\"note\">relief " RELIEF_VERSION_STRING
          "; every figure is also in <a href=\"report.json\">report.json</a>.</p>\n",
          f);
    write_figures(f, c);
    fputs("<h2>Renders</h2>\n<p class=\"note\">Orthographic, framed on the final surface. "
          "Labels: <span class=\"swatch\" style=\"background:rgb(184,184,184)\"></span>"
          "captured <span class=\"swatch\" style=\"background:rgb(245,133,26)\"></span>"
          "completed. Displacement: ",
          f);
    fprintf(f, "&minus;%s<span class=\"bar\"></span>+%s (input units).</p>\n",
            num(a, sizeof a, range), num(a, sizeof a, range));
    fputs("<table class=\"renders\">\n<tr><th></th>", f);
    for (int v = 0; v < N_VIEWS; ++v)
        fprintf(f, "<th>azimuth %.0f&deg;, elevation %.0f&deg;</th>", view[v][0], view[v][1]);
    fputs("</tr>\n", f);
    for (int s = 0; s < N_STAGES; ++s) {
        fprintf(f, "<tr><th>%s<br><span class=\"note\">%s</span></th>", stages[s].title,
                stages[s].note);
        for (int v = 0; v < N_VIEWS; ++v)
            fprintf(f, "<td><a href=\"%s-view%d.png\"><img src=\"%s-view%d.png\" alt=\"%s, "
                       "view %d\"></a></td>",
                    stages[s].file, v + 1, stages[s].file, v + 1, stages[s].title, v + 1);
        fputs("</tr>\n", f);
    }
    fputs("</table>\n<h2>Histograms of the captured and completed parts</h2>\n"
          "<p class=\"note\">As paper 000's figure 13: each part's distribution, "
          "normalised to sum 1, and their total-variation distance (0 same, 1 disjoint)."
          "</p>\n<div class=\"figs\">\n<img src=\"hist-displacement.svg\" "
          "alt=\"displacement histogram\">\n",
          f);
    if (has_colour)
        fputs("<img src=\"hist-red.svg\" alt=\"red histogram\">\n"
              "<img src=\"hist-green.svg\" alt=\"green histogram\">\n"
              "<img src=\"hist-blue.svg\" alt=\"blue histogram\">\n",
              f);
    fputs("</div>\n</body></html>\n", f);
    return 0;
}

/* What html_text_of writes. */
typedef struct html_job {
    const relief_report_content *c;
    const double (*view)[2];
    double range;
    int colour;
} html_job;

static int html_text_of(FILE *f, void *ctx)
{
    const html_job *j = ctx;
    return write_html(f, j->c, j->view, j->range, j->colour);
}

/* ------------------------------------------------------------- stage */

static relief_status render_to(const relief_report_dir *r, const relief_mesh *mesh,
                               const relief_render_options *o, const char *name,
                               relief_error *err)
{
    relief_rgb_image img = {0, 0, NULL};
    char path[4096];
    char shown[4096];
    relief_status st = relief_render(mesh, o, &img, NULL, err);
    if (st == RELIEF_OK) {
        snprintf(path, sizeof path, "%s/%s", relief_staged_folder_path(r->staged), name);
        snprintf(shown, sizeof shown, "%s/%s", relief_staged_folder_target(r->staged), name);
        st = relief_png_write_plain(path, shown, img.rgb, img.width, img.height, err);
    }
    relief_rgb_image_free(&img);
    return st;
}

static void direction(const double *view, double *d)
{
    const double deg = RELIEF_PI / 180.0;
    d[0] = cos(view[1] * deg) * cos(view[0] * deg);
    d[1] = cos(view[1] * deg) * sin(view[0] * deg);
    d[2] = sin(view[1] * deg);
}

/* Three views that between them show the captured side, the completed
 * side and the seam: the capture's default view; the completed part's,
 * or, when that part faces the same way (a hole in a plane), the first
 * view lowered 45 degrees towards grazing, where relief shows in profile;
 * and the first turned 90 degrees in azimuth. */
static void choose_views(const relief_mesh *capture, const relief_mesh *fin,
                         double view[N_VIEWS][2])
{
    double a[3], b[3];
    relief_render_default_view(capture, &view[0][0], &view[0][1]);
    relief_render_part_view(fin, RELIEF_LABEL_COMPLETED, &view[1][0], &view[1][1]);
    direction(view[0], a);
    direction(view[1], b);
    if (a[0] * b[0] + a[1] * b[1] + a[2] * b[2] > 0.5) { /* within 60 degrees */
        view[1][0] = view[0][0];
        view[1][1] = view[0][1] > 0.0 ? view[0][1] - 45.0 : view[0][1] + 45.0;
    }
    view[2][0] = fmod(view[0][0] + 90.0 + 540.0, 360.0) - 180.0;
    view[2][1] = view[0][1];
}

/* A new report folder's record for `dir` with its staging folder made
 * beside it (base/output.h) and relief's marker in it. */
static relief_status make_staging(const char *dir, relief_report_dir **out, relief_error *err)
{
    relief_report_dir *r = calloc(1, sizeof *r);
    relief_status st;
    if (!r)
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate a report folder");
    st = relief_staged_folder_create(dir, &r->staged, err);
    if (st == RELIEF_OK)
        st = write_in(r, RELIEF_REPORT_DIR_MARKER, marker_text, NULL, err);
    if (st != RELIEF_OK) {
        relief_report_dir_abort(r);
        return st;
    }
    *out = r;
    return RELIEF_OK;
}

/* Heights of the final surface fin above the primitive: *h (malloc'd, 2 x
 * nv: the heights, then their sorted magnitudes), their range [*lo, *hi]
 * and *range, the 99th percentile of the magnitudes (1 when that is 0),
 * one colour range for every displacement render. */
static relief_status heights(const relief_mesh *fin, const relief_fit_primitive *prim,
                             double **h, double *lo, double *hi, double *range,
                             relief_error *err)
{
    size_t n = fin->nv;
    double *x = malloc(2 * n * sizeof *x);
    if (!x)
        return relief_fail(err, RELIEF_E_NOMEM, "cannot allocate %zu heights", n);
    *lo = INFINITY;
    *hi = -INFINITY;
    for (size_t v = 0; v < n; ++v) {
        x[v] = relief_fit_distance(prim, fin->pos + 3 * v);
        x[n + v] = fabs(x[v]);
        *lo = fmin(*lo, x[v]);
        *hi = fmax(*hi, x[v]);
    }
    qsort(x + n, n, sizeof *x, relief_cmp_double);
    *range = x[n + (size_t)(0.99 * (double)(n - 1))];
    if (!(*range > 0.0))
        *range = 1.0;
    *h = x;
    return RELIEF_OK;
}

/* Every stage's render from every view into the staging folder. */
static relief_status render_views(relief_report_dir *r, const relief_report_content *c,
                                  const double view[N_VIEWS][2], double range,
                                  relief_error *err)
{
    const relief_mesh *fin = c->surface->mesh;
    relief_status st = RELIEF_OK;
    for (int v = 0; v < N_VIEWS && st == RELIEF_OK; ++v)
        for (int s = 0; s < N_STAGES && st == RELIEF_OK; ++s) {
            relief_render_options o = relief_render_options_default();
            const relief_mesh *mesh = s == 0 ? c->capture : s == 1 ? c->smooth : fin;
            char name[64];
            o.width = RELIEF_REPORT_DIR_WIDTH;
            o.height = RELIEF_REPORT_DIR_HEIGHT;
            o.has_view = 1;
            o.azimuth = view[v][0];
            o.elevation = view[v][1];
            o.frame = fin;
            o.prim = &c->surface->fit.prim;
            o.displacement_range = range;
            o.colour_by = s == 0 ? RELIEF_COLOUR_BY_AUTO
                          : s == 3 ? RELIEF_COLOUR_BY_LABEL
                          : s == 4 ? RELIEF_COLOUR_BY_DISPLACEMENT
                          : mesh->col ? RELIEF_COLOUR_BY_COLOUR : RELIEF_COLOUR_BY_NONE;
            snprintf(name, sizeof name, "%s-view%d.png", stages[s].file, v + 1);
            st = render_to(r, mesh, &o, name, err);
        }
    return st;
}

/* The histograms of fin's heights h (nv of them, in [lo, hi]) and, with
 * colours, of each channel (h's room reused). */
static relief_status write_histograms(relief_report_dir *r, const relief_mesh *fin, double *h,
                                      double lo, double hi, relief_error *err)
{
    static const char *names[3] = {"red", "green", "blue"},
                      *titles[3] = {"Red", "Green", "Blue"};
    size_t n = fin->nv;
    histogram hist;
    relief_status st;
    histogram_fill(&hist, h, fin->label, n, lo, hi);
    st = write_svg(r, "hist-displacement.svg", &hist, "Displacement",
                   "height above the primitive (input units)", err);
    for (int k = 0; fin->col && k < 3 && st == RELIEF_OK; ++k) {
        char file[32];
        for (size_t v = 0; v < n; ++v) /* float colours into the heights' room */
            h[v] = fin->col[3 * v + k];
        histogram_fill(&hist, h, fin->label, n, 0.0, 1.0);
        snprintf(file, sizeof file, "hist-%s.svg", names[k]);
        st = write_svg(r, file, &hist, titles[k], "channel value", err);
    }
    return st;
}

static relief_status stage(const char *dir, const relief_report_content *c,
                           relief_report_dir **out, relief_error *err)
{
    const relief_mesh *fin;
    relief_report_dir *r = NULL;
    double view[N_VIEWS][2], *h = NULL, range = 1.0, lo = 0.0, hi = 0.0;
    relief_status st;

    if (!dir || !c || !out || !c->capture || !c->smooth || !c->surface || !c->params ||
        !c->stats || !c->write_json)
        return relief_fail(err, RELIEF_E_USAGE, "relief_report_dir_stage: NULL argument");
    fin = c->surface->mesh;
    if (!fin->label)
        return relief_fail(err, RELIEF_E_MESH, "the completed surface has no labels");
    if ((st = relief_report_dir_check(dir, err)) != RELIEF_OK)
        return st;
    if ((st = make_staging(dir, &r, err)) != RELIEF_OK)
        return st;
    st = write_in(r, "report.json", c->write_json, c->json_ctx, err);
    if (st == RELIEF_OK)
        st = heights(fin, &c->surface->fit.prim, &h, &lo, &hi, &range, err);
    choose_views(c->capture, fin, view);
    if (st == RELIEF_OK)
        st = render_views(r, c, (const double(*)[2])view, range, err);
    if (st == RELIEF_OK)
        st = write_histograms(r, fin, h, lo, hi, err);
    if (st == RELIEF_OK) {
        html_job j = {c, (const double(*)[2])view, range, fin->col != NULL};
        st = write_in(r, "index.html", html_text_of, &j, err);
    }
    free(h);
    if (st != RELIEF_OK) {
        relief_report_dir_abort(r);
        return st;
    }
    *out = r;
    return RELIEF_OK;
}

/* The numbers in the figures and the page in the C locale (numtext.h),
 * "0.5" whatever the caller's: one scope for the whole folder. */
relief_status relief_report_dir_stage(const char *dir, const relief_report_content *c,
                                      relief_report_dir **out, relief_error *err)
{
    relief_numtext_scope scope;
    relief_status st;
    relief_numtext_begin(&scope);
    st = stage(dir, c, out, err);
    relief_numtext_end(&scope);
    return st;
}
