/* The image filler's scorers side by side in one process (issue 19:
 * OpenCL at least as fast as scalar on PoCL; issue 42: only the winners
 * read back): each image of IMAGES_DIR with a 64 x 64 hole at its centre
 * (and, with --atlas FILE --atlas-mask M, a paper-sized atlas with --atlas
 * windows; with --fill FILE MASK, any image and mask with the defaults),
 * filled REPEAT times by each in turn, the scorers made once:
 * scalar, OpenCL reading every score back ("all") and OpenCL ranking
 * large batches' blocks on the device and reading back only those that
 * may hold the best ("sel", the default); wall time of relief_fill, median
 * over the repetitions, the ratios, and the share of the scores "sel" read
 * back. The scorers' one-time set-up (an OpenCL context and program) is
 * timed apart. Every OpenCL fill is checked byte for byte against the
 * scalar one.
 *   bench_image_fill IMAGES_DIR [--repeat N] [--csv OUT.csv]
 *                    [--atlas IMAGE --atlas-mask MASK] [--fill IMAGE MASK]... */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "bench_util.h"
#include "base/clock.h"
#include "image/fill.h"
#include "image/image_io.h"

typedef struct job {
    const char *name;
    relief_raster img;
    uint8_t *hole;
    relief_fill_params p;
} job;

/* One fill of a copy of j's image; its seconds, the copy kept in *out,
 * the report in *rep. */
static double fill_once(const job *j, relief_patch_scorer *s, relief_raster *out,
                        relief_fill_report *rep)
{
    relief_error err = {0};
    size_t n = (size_t)j->img.width * j->img.height * j->img.channels;
    double t0;
    relief_raster_create(j->img.width, j->img.height, j->img.channels, j->img.bit_depth, out,
                         &err);
    memcpy(out->v, j->img.v, n * sizeof(float));
    t0 = relief_seconds();
    if (relief_fill(out, j->hole, &j->p, s, rep, &err) != RELIEF_OK) {
        fprintf(stderr, "bench_image_fill: %s: %s\n", j->name, err.message);
        exit(2);
    }
    return relief_seconds() - t0;
}

int main(int argc, char **argv)
{
    const char *images = NULL, *csv = NULL, *atlas = NULL, *atlas_mask = NULL;
    const char *fills[2][2];
    int n_fills = 0;
    static const char *names[] = {"brick.png", "grass.png", "gravel.png", "coffee.png",
                                  "chelsea.png", "astronaut.png", "rocket.jpg"};
    relief_patch_scorer *sc = NULL, *cl = NULL;
    relief_error err = {0};
    double t0, setup_scalar, setup_cl;
    int repeat = 5, n_jobs = 0;
    job jobs[10];
    bench_machine m;
    FILE *f = NULL;

    for (int i = 1; i < argc; ++i) {
        if (strcmp(argv[i], "--repeat") == 0 && i + 1 < argc)
            repeat = atoi(argv[++i]);
        else if (strcmp(argv[i], "--csv") == 0 && i + 1 < argc)
            csv = argv[++i];
        else if (strcmp(argv[i], "--atlas") == 0 && i + 1 < argc)
            atlas = argv[++i];
        else if (strcmp(argv[i], "--atlas-mask") == 0 && i + 1 < argc)
            atlas_mask = argv[++i];
        else if (strcmp(argv[i], "--fill") == 0 && i + 2 < argc && n_fills < 2) {
            fills[n_fills][0] = argv[++i];
            fills[n_fills++][1] = argv[++i];
        }
        else if (!images)
            images = argv[i];
        else {
            fprintf(stderr, "usage: bench_image_fill IMAGES_DIR [--repeat N] [--csv OUT] "
                    "[--atlas IMAGE --atlas-mask MASK] [--fill IMAGE MASK] (twice at most)\n");
            return 1;
        }
    }
    if (!images || repeat < 1 || repeat > 64) {
        fprintf(stderr, "usage: bench_image_fill IMAGES_DIR [--repeat N (1..64)] ...\n");
        return 1;
    }
    for (size_t k = 0; k < sizeof names / sizeof names[0]; ++k) {
        char path[1024];
        job *j = &jobs[n_jobs];
        snprintf(path, sizeof path, "%s/%s", images, names[k]);
        if (relief_raster_read(path, NULL, &j->img, &err) != RELIEF_OK) {
            fprintf(stderr, "bench_image_fill: %s\n", err.message);
            return 1;
        }
        j->name = names[k];
        j->p = relief_fill_params_default();
        j->hole = calloc((size_t)j->img.width * j->img.height, 1);
        for (int y = j->img.height / 2 - 32; y < j->img.height / 2 + 32; ++y)
            for (int x = j->img.width / 2 - 32; x < j->img.width / 2 + 32; ++x)
                j->hole[(size_t)y * j->img.width + x] = 1;
        ++n_jobs;
    }
    for (int k = 0; k < n_fills + (atlas && atlas_mask); ++k) {
        int is_atlas = k == n_fills;
        const char *image = is_atlas ? atlas : fills[k][0];
        const char *mask_path = is_atlas ? atlas_mask : fills[k][1];
        job *j = &jobs[n_jobs];
        relief_raster mask;
        if (relief_raster_read(image, NULL, &j->img, &err) != RELIEF_OK ||
            relief_raster_read(mask_path, NULL, &mask, &err) != RELIEF_OK) {
            fprintf(stderr, "bench_image_fill: %s\n", err.message);
            return 1;
        }
        j->name = is_atlas ? "atlas" : strrchr(image, '/') ? strrchr(image, '/') + 1 : image;
        j->p = relief_fill_params_default();
        if (is_atlas) {
            j->p.window = 129;
            j->p.min_window = 9;
        }
        j->hole = malloc((size_t)j->img.width * j->img.height);
        for (size_t i = 0; i < (size_t)j->img.width * j->img.height; ++i)
            j->hole[i] = mask.v[i * mask.channels] != 0.0f;
        relief_raster_free(&mask);
        ++n_jobs;
    }

    t0 = relief_seconds();
    relief_patch_scalar_create(&sc, &err);
    setup_scalar = relief_seconds() - t0;
    t0 = relief_seconds();
    if (relief_patch_opencl_create(-1, &cl, &err) != RELIEF_OK) {
        fprintf(stderr, "bench_image_fill: no OpenCL scorer: %s\n", err.message);
        return 1;
    }
    setup_cl = relief_seconds() - t0;
    bench_read_machine(&m);
    printf("scalar: %s\nOpenCL: %s (set-up %.3f s, scalar %.6f s)\n", sc->device, cl->device,
           setup_cl, setup_scalar);
    if (csv && !(f = fopen(csv, "w"))) {
        perror(csv);
        return 1;
    }
    if (f)
        fprintf(f, "image,width,height,holes,scalar_s,opencl_s,scalar_over_opencl,"
                "opencl_all_s,all_over_sel,read_back,opencl_setup_s,identical\n");
    printf("%-14s %11s %9s %9s %9s %8s %8s %8s  %s\n", "image", "size", "scalar s",
           "all s", "sel s", "sc/sel", "all/sel", "read", "identical");
    for (int k = 0; k < n_jobs; ++k) {
        const job *j = &jobs[k];
        double ts[64], ta[64], tc[64], ms, ma, mc, lo, hi, read = 0.0;
        size_t holes = 0;
        int same = 1;
        for (size_t i = 0; i < (size_t)j->img.width * j->img.height; ++i)
            holes += j->hole[i];
        /* Alternate them, so that a busy spell of a shared machine falls
         * on each. */
        for (int r = 0; r < repeat; ++r) {
            relief_fill_report rs, ra, rc;
            relief_raster a, b, c;
            size_t bytes;
            ts[r] = fill_once(j, sc, &a, &rs);
            relief_patch_opencl_select_from(cl, (size_t)-1);
            ta[r] = fill_once(j, cl, &b, &ra);
            relief_patch_opencl_select_from(cl, RELIEF_PATCH_SELECT_FROM);
            tc[r] = fill_once(j, cl, &c, &rc);
            bytes = sizeof(float) * (size_t)a.width * a.height * a.channels;
            same &= memcmp(a.v, b.v, bytes) == 0 && memcmp(a.v, c.v, bytes) == 0 &&
                    ra.scores_read == ra.candidates;
            read = rc.candidates ? (double)rc.scores_read / (double)rc.candidates : 1.0;
            relief_raster_free(&a);
            relief_raster_free(&b);
            relief_raster_free(&c);
        }
        bench_stats3(ts, repeat, &ms, &lo, &hi);
        bench_stats3(ta, repeat, &ma, &lo, &hi);
        bench_stats3(tc, repeat, &mc, &lo, &hi);
        printf("%-14s %5dx%-5d %9.3f %9.3f %9.3f %8.2f %8.2f %7.1f%%  %s\n", j->name,
               j->img.width, j->img.height, ms, ma, mc, ms / mc, ma / mc, 100.0 * read,
               same ? "yes" : "NO");
        if (f)
            fprintf(f, "%s,%d,%d,%zu,%.4f,%.4f,%.3f,%.4f,%.3f,%.4f,%.4f,%d\n", j->name,
                    j->img.width, j->img.height, holes, ms, mc, ms / mc, ma, ma / mc, read,
                    setup_cl, same);
        if (!same) {
            fprintf(stderr, "bench_image_fill: %s: the scorers filled differently\n", j->name);
            return 2;
        }
    }
    printf("machine: %s, %ld cores\n", m.cpu, m.cores);
    if (f)
        fclose(f);
    for (int k = 0; k < n_jobs; ++k) {
        relief_raster_free(&jobs[k].img);
        free(jobs[k].hole);
    }
    relief_patch_scorer_destroy(sc);
    relief_patch_scorer_destroy(cl);
    return 0;
}
