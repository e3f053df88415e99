/* Synthetic partial surfaces with known relief (`relief synth`).
 *
 * Every kind is a base primitive meshed regularly (a grid on the plane and
 * the cylinder, a geodesic icosphere on the sphere), displaced along the
 * primitive's normal by a relief height field h, optionally coloured by a
 * palette driven by h. The truth is the whole surface; the capture keeps
 * what a scanner looking down +x sees (cylinder, sphere) or the plane with
 * a central disc removed. Truth labels say which vertices the capture has
 * (0) and which a completion must produce (1). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "base/error.h"
#include "base/rng.h"
#include "base/vec3.h"
#include "mesh/mesh.h"

#define N_WAVES 24
#define N_DIMPLES_MAX 4096

static const struct {
    const char *name;
    const char *description;
} kinds[] = {
#define RELIEF_X_ROW(code, name, desc) {name, desc},
    RELIEF_SYNTH_KIND_LIST(RELIEF_X_ROW)
#undef RELIEF_X_ROW
};

const char *relief_synth_kind_name(relief_synth_kind kind)
{
    return (unsigned)kind < RELIEF_SYNTH_KIND_COUNT ? kinds[kind].name : NULL;
}

const char *relief_synth_kind_description(relief_synth_kind kind)
{
    return (unsigned)kind < RELIEF_SYNTH_KIND_COUNT ? kinds[kind].description : NULL;
}

relief_status relief_synth_kind_parse(const char *name, relief_synth_kind *out,
                                      relief_error *err)
{
    RELIEF_ENTRY_ERR(err);
    if (!out)
        return relief_fail(err, RELIEF_E_USAGE, "relief_synth_kind_parse: out is NULL");
    for (int k = 0; k < RELIEF_SYNTH_KIND_COUNT; ++k)
        if (name && strcmp(name, kinds[k].name) == 0) {
            *out = (relief_synth_kind)k;
            return RELIEF_OK;
        }
    return relief_fail_param(err, RELIEF_E_USAGE, "kind",
                             "unknown surface kind '%s'; expected one of plane-waves, "
                             "plane-noise, cylinder-bands, cylinder-bark, sphere-dimples",
                             name ? name : "(null)");
}

relief_synth_params relief_synth_params_default(void)
{
    relief_synth_params p;
    p.kind = RELIEF_SYNTH_PLANE_WAVES;
    p.seed = 1;
    p.vertices = 2000;
    p.colour = 0;
    p.noise = 0.0;
    return p;
}

/* ------------------------------------------------------------ relief */

/* Shape constants, in units of the primitive (plane side, radius). */
enum { PLANE_SIDE = 1 };
static const double CYL_HEIGHT = 2.0;      /* axis from z = 0 to z = 2 */
static const double VIEW_HALF_ANGLE = 80.0; /* degrees seen around +x */
static const double HOLE_RADIUS = 0.25;    /* plane: disc removed */
/* cylinder-bark: the unfolded ridges' cycles around the circumference
 * (wavelength 2 pi / 12 = 0.52, so 24 crests 0.26 apart after folding,
 * three vertex spacings at the default 2000), and the standard deviation of
 * their phase field in radians. */
static const double BARK_RIDGES = 12.0;
static const double BARK_MEANDER = 1.5;
/* plane-noise's grid cell: 5.3 vertex spacings at the default 2000. */
static const double PEBBLE_CELL = 0.12;

typedef struct wave {
    double k[2];  /* wave vector, radians per unit (plane) or per (rad, unit) */
    double phase;
} wave;

typedef struct relief_field {
    relief_synth_kind kind;
    wave w[N_WAVES];     /* cylinder-bark's meander */
    wave cw[N_WAVES];    /* an independent field for colour variation */
    double norm;         /* scales the wave sums to unit standard deviation */
    double (*dimple)[3]; /* sphere-dimples: unit centres */
    int n_dimples;
    double (*pebble)[4]; /* plane-noise: per cell x, y, height, radius */
    int pebble_side;     /* cells per side, row-major from pebble_lo */
    double pebble_lo, pebble_cell;
    double pebble_mean;  /* the bumps' mean height over the plane */
    double colour_var;   /* amplitude of the colour's variation that is
                          * not a function of height (cw, unit deviation) */
} relief_field;

/* A band-limited random field: N_WAVES plane waves with random directions
 * and wavelengths in [lmin, lmax]. For the cylinder (`angular`), the first
 * coordinate is the angle and its frequency an integer (the field wraps),
 * and directions lie within 15 degrees of the circumference. */
static void make_waves(wave *w, relief_rng *rng, double lmin, double lmax, int angular)
{
    for (int i = 0; i < N_WAVES; ++i) {
        double len = lmin + (lmax - lmin) * relief_rng_uniform(rng);
        double kmag = 2.0 * RELIEF_PI / len;
        double dir = angular ? (relief_rng_uniform(rng) - 0.5) * (RELIEF_PI / 6.0)
                             : relief_rng_uniform(rng) * 2.0 * RELIEF_PI;
        w[i].k[0] = kmag * cos(dir);
        w[i].k[1] = kmag * sin(dir) * (angular ? 0.15 : 1.0);
        if (angular) /* cycles around the circumference (radius 1) */
            w[i].k[0] = floor(w[i].k[0] + 0.5);
        w[i].phase = 2.0 * RELIEF_PI * relief_rng_uniform(rng);
    }
}

/* cylinder-bark's phase field: slow waves, -3 to 3 cycles around the
 * circumference and wavelengths 1 to 3 along the axis, so crests drift
 * sideways, and merge or split, over half a trunk's height. */
static void make_meander(wave *w, relief_rng *rng)
{
    for (int i = 0; i < N_WAVES; ++i) {
        double len = 1.0 + 2.0 * relief_rng_uniform(rng);
        w[i].k[0] = floor(7.0 * relief_rng_uniform(rng)) - 3.0;
        w[i].k[1] = 2.0 * RELIEF_PI / len * (relief_rng_uniform(rng) < 0.5 ? -1.0 : 1.0);
        w[i].phase = 2.0 * RELIEF_PI * relief_rng_uniform(rng);
    }
}

static double wave_sum(const wave *w, double u, double v)
{
    double s = 0.0;
    for (int i = 0; i < N_WAVES; ++i)
        s += sin(w[i].k[0] * u + w[i].k[1] * v + w[i].phase);
    return s;
}

/* Relief height h at base point `b` with parameters (u, v): plane (x, y),
 * cylinder (angle, z), sphere unused. */
static double relief_height(const relief_field *f, const double b[3], double u, double v)
{
    switch (f->kind) {
    case RELIEF_SYNTH_PLANE_WAVES: {
        /* Waves of wavelength 1/8 travelling at 30 degrees to x. */
        const double k = 2.0 * RELIEF_PI * 8.0;
        return 0.02 * sin(k * (u * 0.8660254037844386 + v * 0.5));
    }
    case RELIEF_SYNTH_PLANE_NOISE: {
        /* The bumps of this cell and its 8 neighbours (radii < 1 cell). */
        const int n = f->pebble_side;
        const int ci = (int)floor((u - f->pebble_lo) / f->pebble_cell);
        const int cj = (int)floor((v - f->pebble_lo) / f->pebble_cell);
        double h = -f->pebble_mean; /* relief about 0 */
        for (int j = cj - 1; j <= cj + 1; ++j)
            for (int i = ci - 1; i <= ci + 1; ++i) {
                const double *pb;
                double dx, dy, q;
                if (i < 0 || j < 0 || i >= n || j >= n)
                    continue;
                pb = f->pebble[(size_t)j * (size_t)n + (size_t)i];
                dx = u - pb[0], dy = v - pb[1];
                q = (dx * dx + dy * dy) / (pb[3] * pb[3]);
                if (q < 1.0)
                    h += pb[2] * (1.0 - q) * (1.0 - q);
            }
        return h;
    }
    case RELIEF_SYNTH_CYLINDER_BANDS: {
        /* Raised rings of period 0.5 along the axis: about 6 vertices per
         * period at the default 2000, so the capture resolves them. */
        double c = cos(2.0 * RELIEF_PI * v / 0.5);
        return c > 0.0 ? 0.05 * c * c : 0.0;
    }
    case RELIEF_SYNTH_CYLINDER_BARK: {
        /* Furrowed ridges along the axis: BARK_RIDGES crests around the
         * circumference whose phase meanders with a smooth random field,
         * folded so furrows are sharp and crests round. Only the phase is
         * random, so sin(.) keeps its arcsine distribution everywhere and
         * the relief is stationary: every part of the trunk has the same
         * height statistics (a completion can only copy the capture's).
         * E|sin| = 2 / pi: subtracting half of it keeps the relief's mean
         * at zero, so a fit to one side is not pulled off the axis. */
        double s = sin(BARK_RIDGES * u + BARK_MEANDER * f->norm * wave_sum(f->w, u, v));
        return 0.03 * (0.3183098861837907 - fabs(s) / 2.0);
    }
    case RELIEF_SYNTH_SPHERE_DIMPLES: {
        const double rd = 0.16; /* dimple radius, radians */
        double h = 0.0;
        for (int i = 0; i < f->n_dimples; ++i) {
            const double *c = f->dimple[i];
            double d = b[0] * c[0] + b[1] * c[1] + b[2] * c[2];
            if (d > cos(rd)) {
                double a = acos(d > 1.0 ? 1.0 : d) / rd;
                h -= 0.03 * (1.0 - a * a) * (1.0 - a * a);
            }
        }
        return h;
    }
    default:
        return 0.0;
    }
}

/* Colour from the relief height normalised to t in [0, 1] and a second,
 * independent field for variation that is not a function of height. */
static void relief_colour(const relief_field *f, double t, double var, float out[3])
{
    static const float pal[RELIEF_SYNTH_KIND_COUNT][2][3] = {
        {{0.10f, 0.20f, 0.55f}, {0.95f, 0.85f, 0.35f}}, /* waves: blue to yellow */
        {{0.25f, 0.30f, 0.20f}, {0.65f, 0.70f, 0.45f}}, /* noise: moss */
        {{0.90f, 0.90f, 0.88f}, {0.80f, 0.10f, 0.10f}}, /* bands: white, red rings */
        {{0.20f, 0.12f, 0.06f}, {0.62f, 0.48f, 0.33f}}, /* bark: furrow to crest */
        {{0.55f, 0.55f, 0.58f}, {0.97f, 0.97f, 0.95f}}, /* golf ball */
    };
    for (int k = 0; k < 3; ++k) {
        double c = pal[f->kind][0][k] + (pal[f->kind][1][k] - pal[f->kind][0][k]) * t +
                   f->colour_var * var;
        out[k] = (float)(c < 0.0 ? 0.0 : c > 1.0 ? 1.0 : c);
    }
}

/* ------------------------------------------------------------ meshes */

/* Base meshes: positions on the primitive, unit normals and the (u, v) the
 * relief is a function of. */
typedef struct base_mesh {
    size_t nv, nt;
    double *p, *n, *uv; /* nv x 3, nv x 3, nv x 2 */
    uint32_t *tri;      /* nt x 3 */
} base_mesh;

static void base_free(base_mesh *b)
{
    free(b->p);
    free(b->n);
    free(b->uv);
    free(b->tri);
}

static int base_alloc(base_mesh *b, size_t nv, size_t nt)
{
    b->nv = nv;
    b->nt = nt;
    b->p = malloc(nv * 3 * sizeof *b->p);
    b->n = malloc(nv * 3 * sizeof *b->n);
    b->uv = malloc(nv * 2 * sizeof *b->uv);
    b->tri = malloc(nt * 3 * sizeof *b->tri);
    return b->p && b->n && b->uv && b->tri;
}

/* Quads of an nu x nv grid (u fastest), two triangles each, counter-clockwise
 * seen along +n when u x v points along n; `wrap_u` joins the last column to
 * the first. Returns the triangle count written. */
static size_t grid_triangles(uint32_t *tri, size_t nu, size_t nvv, int wrap_u)
{
    size_t t = 0, cols = wrap_u ? nu : nu - 1;
    for (size_t j = 0; j + 1 < nvv; ++j)
        for (size_t i = 0; i < cols; ++i) {
            uint32_t a = (uint32_t)(j * nu + i), b = (uint32_t)(j * nu + (i + 1) % nu);
            uint32_t c = (uint32_t)((j + 1) * nu + (i + 1) % nu),
                     d = (uint32_t)((j + 1) * nu + i);
            /* Alternate diagonals so the mesh has no preferred direction. */
            if ((i + j) % 2 == 0) {
                tri[3 * t] = a, tri[3 * t + 1] = b, tri[3 * t + 2] = c, ++t;
                tri[3 * t] = a, tri[3 * t + 1] = c, tri[3 * t + 2] = d, ++t;
            } else {
                tri[3 * t] = a, tri[3 * t + 1] = b, tri[3 * t + 2] = d, ++t;
                tri[3 * t] = b, tri[3 * t + 1] = c, tri[3 * t + 2] = d, ++t;
            }
        }
    return t;
}

static int make_plane(base_mesh *b, size_t target_nv)
{
    size_t n = (size_t)floor(sqrt((double)target_nv) + 0.5);
    if (n < 3)
        n = 3;
    if (!base_alloc(b, n * n, 2 * (n - 1) * (n - 1)))
        return 0;
    for (size_t j = 0; j < n; ++j)
        for (size_t i = 0; i < n; ++i) {
            size_t v = j * n + i;
            double x = (double)PLANE_SIDE * ((double)i / (double)(n - 1) - 0.5);
            double y = (double)PLANE_SIDE * ((double)j / (double)(n - 1) - 0.5);
            b->p[3 * v] = x, b->p[3 * v + 1] = y, b->p[3 * v + 2] = 0.0;
            b->n[3 * v] = 0.0, b->n[3 * v + 1] = 0.0, b->n[3 * v + 2] = 1.0;
            b->uv[2 * v] = x, b->uv[2 * v + 1] = y;
        }
    b->nt = grid_triangles(b->tri, n, n, 0);
    return 1;
}

static int make_cylinder(base_mesh *b, size_t target_nv)
{
    /* Square cells: (2 pi / s) * (H / s) = target. */
    double s = sqrt(2.0 * RELIEF_PI * CYL_HEIGHT / (double)target_nv);
    size_t nu = (size_t)floor(2.0 * RELIEF_PI / s + 0.5), nz = (size_t)floor(CYL_HEIGHT / s + 0.5) + 1;
    if (nu < 8)
        nu = 8;
    if (nz < 3)
        nz = 3;
    if (!base_alloc(b, nu * nz, 2 * nu * (nz - 1)))
        return 0;
    for (size_t j = 0; j < nz; ++j)
        for (size_t i = 0; i < nu; ++i) {
            size_t v = j * nu + i;
            double a = 2.0 * RELIEF_PI * (double)i / (double)nu - RELIEF_PI; /* angle from -x */
            double z = CYL_HEIGHT * (double)j / (double)(nz - 1);
            b->p[3 * v] = cos(a), b->p[3 * v + 1] = sin(a), b->p[3 * v + 2] = z;
            b->n[3 * v] = cos(a), b->n[3 * v + 1] = sin(a), b->n[3 * v + 2] = 0.0;
            b->uv[2 * v] = a, b->uv[2 * v + 1] = z;
        }
    b->nt = grid_triangles(b->tri, nu, nz, 1);
    return 1;
}

/* Index of the point `pos` steps from corner P toward corner Q on the
 * icosahedron edge PQ, for an icosphere of frequency f whose edge points are
 * numbered from v0_edges on, f - 1 per edge, from the lower-numbered end. */
static size_t edge_point(const int edge[30][2], int P, int Q, size_t pos, size_t f,
                         size_t v0_edges)
{
    int lo = P < Q ? P : Q, hi = P < Q ? Q : P, e = 0;
    size_t at;
    while (edge[e][0] != lo || edge[e][1] != hi)
        ++e;
    at = P == lo ? pos : f - pos;
    return v0_edges + (size_t)e * (f - 1) + (at - 1);
}

/* The icosahedron the icosphere starts from: its 12 corners (unnormalised)
 * and 20 faces. */
#define ICO_T 1.6180339887498949
static const double ico_corner[12][3] = {
    {-1, ICO_T, 0}, {1, ICO_T, 0},  {-1, -ICO_T, 0}, {1, -ICO_T, 0},
    {0, -1, ICO_T}, {0, 1, ICO_T},  {0, -1, -ICO_T}, {0, 1, -ICO_T},
    {ICO_T, 0, -1}, {ICO_T, 0, 1},  {-ICO_T, 0, -1}, {-ICO_T, 0, 1}};
static const int ico_face[20][3] = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10},
                                    {0, 10, 11}, {1, 5, 9}, {5, 11, 4},  {11, 10, 2},
                                    {10, 7, 6}, {7, 1, 8},  {3, 9, 4},   {3, 4, 2},
                                    {3, 2, 6},  {3, 6, 8},  {3, 8, 9},   {4, 9, 5},
                                    {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};

/* Point idx of b: (x, y, z) put on the unit sphere. */
static void set_unit(base_mesh *b, size_t idx, double x, double y, double z)
{
    double l = sqrt(x * x + y * y + z * z);
    b->p[3 * idx] = x / l, b->p[3 * idx + 1] = y / l, b->p[3 * idx + 2] = z / l;
}

/* Face fi of the icosahedron cut into f^2 triangles, appended to b->tri
 * at *nt: its corners and edge points are shared (edge_point), its inner
 * points are its own, numbered from v0_faces + fi per_face. 0 when out of
 * memory. */
static int sphere_face(base_mesh *b, const int edge[30][2], int fi, size_t f, size_t v0_edges,
                       size_t v0_faces, size_t per_face, size_t *nt)
{
    const int A = ico_face[fi][0], B = ico_face[fi][1], C = ico_face[fi][2];
    const double(*ico)[3] = ico_corner;
    size_t local = 0;
    size_t *idx = malloc((f + 1) * (f + 1) * sizeof *idx);
    if (!idx)
        return 0;
    for (size_t j = 0; j <= f; ++j)
        for (size_t k = 0; j + k <= f; ++k) {
            size_t i = f - j - k, id;
            if (j == 0 && k == 0)
                id = (size_t)A;
            else if (j == f)
                id = (size_t)B;
            else if (k == f)
                id = (size_t)C;
            else if (k == 0)
                id = edge_point(edge, A, B, j, f, v0_edges);
            else if (j == 0)
                id = edge_point(edge, A, C, k, f, v0_edges);
            else if (i == 0)
                id = edge_point(edge, B, C, k, f, v0_edges);
            else {
                id = v0_faces + (size_t)fi * per_face + local++;
                set_unit(b, id,
                         ((double)i * ico[A][0] + (double)j * ico[B][0] + (double)k * ico[C][0]),
                         ((double)i * ico[A][1] + (double)j * ico[B][1] + (double)k * ico[C][1]),
                         ((double)i * ico[A][2] + (double)j * ico[B][2] + (double)k * ico[C][2]));
            }
            idx[j * (f + 1) + k] = id;
        }
    for (size_t j = 0; j < f; ++j)
        for (size_t k = 0; j + k < f; ++k) {
            b->tri[3 * *nt] = (uint32_t)idx[j * (f + 1) + k];
            b->tri[3 * *nt + 1] = (uint32_t)idx[(j + 1) * (f + 1) + k];
            b->tri[3 * *nt + 2] = (uint32_t)idx[j * (f + 1) + k + 1];
            ++*nt;
            if (j + k + 1 < f) {
                b->tri[3 * *nt] = (uint32_t)idx[(j + 1) * (f + 1) + k];
                b->tri[3 * *nt + 1] = (uint32_t)idx[(j + 1) * (f + 1) + k + 1];
                b->tri[3 * *nt + 2] = (uint32_t)idx[j * (f + 1) + k + 1];
                ++*nt;
            }
        }
    free(idx);
    return 1;
}

/* The icosahedron's face list is not consistently wound: make every
 * triangle counter-clockwise seen from outside. */
static void wind_outwards(base_mesh *b)
{
    for (size_t tt = 0; tt < b->nt; ++tt) {
        uint32_t *q = b->tri + 3 * tt;
        const double *a = b->p + 3 * q[0], *c1 = b->p + 3 * q[1], *c2 = b->p + 3 * q[2];
        double e1[3], e2[3], n[3];
        for (int k = 0; k < 3; ++k)
            e1[k] = c1[k] - a[k], e2[k] = c2[k] - a[k];
        n[0] = e1[1] * e2[2] - e1[2] * e2[1];
        n[1] = e1[2] * e2[0] - e1[0] * e2[2];
        n[2] = e1[0] * e2[1] - e1[1] * e2[0];
        if (n[0] * a[0] + n[1] * a[1] + n[2] * a[2] < 0.0) {
            uint32_t tmp = q[1];
            q[1] = q[2];
            q[2] = tmp;
        }
    }
}

/* Geodesic icosphere of frequency f: every icosahedron face cut into f^2
 * triangles, 10 f^2 + 2 vertices. Points on a shared edge are computed from
 * the edge's lower-numbered end, so both faces agree to the bit. */
static int make_sphere(base_mesh *b, size_t target_nv)
{
    int edge[30][2], ne = 0;
    size_t f = (size_t)floor(sqrt(((double)target_nv - 2.0) / 10.0) + 0.5);
    size_t per_edge, per_face, v0_edges, v0_faces, nt = 0;

    if (f < 1)
        f = 1;
    per_edge = f - 1;
    per_face = f >= 3 ? (f - 1) * (f - 2) / 2 : 0;
    v0_edges = 12;
    v0_faces = v0_edges + 30 * per_edge;
    if (!base_alloc(b, 10 * f * f + 2, 20 * f * f))
        return 0;

    for (int fi = 0; fi < 20; ++fi)
        for (int k = 0; k < 3; ++k) {
            int a = ico_face[fi][k], c = ico_face[fi][(k + 1) % 3], lo = a < c ? a : c,
                hi = a < c ? c : a, e;
            for (e = 0; e < ne; ++e)
                if (edge[e][0] == lo && edge[e][1] == hi)
                    break;
            if (e == ne)
                edge[ne][0] = lo, edge[ne][1] = hi, ++ne;
        }
    for (int v = 0; v < 12; ++v)
        set_unit(b, (size_t)v, ico_corner[v][0], ico_corner[v][1], ico_corner[v][2]);
    for (int e = 0; e < 30; ++e)
        for (size_t k = 1; k < f; ++k) {
            const double *a = ico_corner[edge[e][0]], *c = ico_corner[edge[e][1]];
            double s = (double)k / (double)f;
            set_unit(b, v0_edges + (size_t)e * per_edge + (k - 1), a[0] + (c[0] - a[0]) * s,
                     a[1] + (c[1] - a[1]) * s, a[2] + (c[2] - a[2]) * s);
        }
    for (int fi = 0; fi < 20; ++fi)
        if (!sphere_face(b, (const int(*)[2])edge, fi, f, v0_edges, v0_faces, per_face, &nt))
            return 0;
    b->nt = nt;
    for (size_t v = 0; v < b->nv; ++v) {
        memcpy(b->n + 3 * v, b->p + 3 * v, 3 * sizeof(double));
        b->uv[2 * v] = atan2(b->p[3 * v + 1], b->p[3 * v]);
        b->uv[2 * v + 1] = b->p[3 * v + 2];
    }
    wind_outwards(b);
    return 1;
}

/* Fibonacci-lattice dimple centres: near-uniform on the sphere. */
static int make_dimples(relief_field *f, relief_rng *rng)
{
    const int n = 110;
    const double golden = RELIEF_PI * (3.0 - sqrt(5.0));
    double twist = 2.0 * RELIEF_PI * relief_rng_uniform(rng);
    f->dimple = malloc((size_t)n * sizeof *f->dimple);
    if (!f->dimple)
        return 0;
    for (int i = 0; i < n; ++i) {
        double z = 1.0 - 2.0 * (i + 0.5) / n, r = sqrt(1.0 - z * z);
        double a = golden * i + twist;
        f->dimple[i][0] = r * cos(a);
        f->dimple[i][1] = r * sin(a);
        f->dimple[i][2] = z;
    }
    f->n_dimples = n;
    return 1;
}

/* plane-noise: one rounded bump per cell of a jittered square grid, its
 * centre within a quarter cell of the cell's, its height and radius drawn
 * within 20 % and 10 %. A sum of a few dozen random waves, the surface's
 * first form, is not stationary at the hole's scale (nearby wave vectors
 * beat over the whole plane): over synth seeds 1 to 8 its truth's own
 * hole differed in MSI from the captured part by 0.1 to 15 %, so no
 * completion, which can only copy the capture, could be held to 5 %. The
 * bumps keep every cell alike: 0.3 to 4.8 % over the same seeds. */
static int make_pebbles(relief_field *f, relief_rng *rng)
{
    const double cell = PEBBLE_CELL;
    const int n = (int)ceil((double)PLANE_SIDE / cell) + 2; /* a cell of margin */
    double volume = 0.0;
    f->pebble_side = n;
    f->pebble_cell = cell;
    f->pebble_lo = -0.5 * (double)n * cell;
    f->pebble = malloc((size_t)n * (size_t)n * sizeof *f->pebble);
    if (!f->pebble)
        return 0;
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            double *pb = f->pebble[(size_t)j * (size_t)n + (size_t)i];
            pb[0] = f->pebble_lo + cell * (i + 0.5 + 0.5 * (relief_rng_uniform(rng) - 0.5));
            pb[1] = f->pebble_lo + cell * (j + 0.5 + 0.5 * (relief_rng_uniform(rng) - 0.5));
            pb[2] = 0.03 * (1.0 - 0.2 * relief_rng_uniform(rng));
            pb[3] = 0.6 * cell * (1.0 - 0.1 * relief_rng_uniform(rng));
            volume += pb[2] * RELIEF_PI * pb[3] * pb[3] / 3.0; /* of h (1 - q)^2 over the disc */
        }
    f->pebble_mean = volume / ((double)n * (double)n * cell * cell);
    return 1;
}

/* Is base point `p` with normal `n` in the capture? */
static int captured(relief_synth_kind kind, const double p[3], const double n[3])
{
    if (kind == RELIEF_SYNTH_PLANE_WAVES || kind == RELIEF_SYNTH_PLANE_NOISE)
        return p[0] * p[0] + p[1] * p[1] > HOLE_RADIUS * HOLE_RADIUS;
    /* A scanner looking down -x sees normals within the view cone of +x. */
    return n[0] > cos(VIEW_HALF_ANGLE * RELIEF_PI / 180.0);
}

relief_status relief_synth_params_validate(const relief_synth_params *params,
                                           relief_error *err)
{
    RELIEF_ENTRY_ERR(err);
    if (!params)
        return relief_fail(err, RELIEF_E_USAGE, "params is NULL");
    if ((unsigned)params->kind >= RELIEF_SYNTH_KIND_COUNT)
        return relief_fail_param(err, RELIEF_E_RANGE, "kind", "synthetic kind %d out of range",
                                 (int)params->kind);
    if (params->vertices < 100 || params->vertices > 4000000)
        return relief_fail_param(err, RELIEF_E_RANGE, "vertices",
                                 "vertices %zu out of range: expected 100..4000000",
                                 params->vertices);
    if (!(params->noise >= 0.0 && params->noise <= 0.1))
        return relief_fail_param(err, RELIEF_E_RANGE, "noise",
                                 "noise %g out of range: expected 0..0.1 (fraction of the "
                                 "primitive's size)",
                                 params->noise);
    return RELIEF_OK;
}

/* The kind's base mesh and relief field, drawn from rng in a fixed order;
 * 0 when out of memory. */
static int synth_base(const relief_synth_params *params, relief_field *field, base_mesh *b,
                      relief_rng *rng)
{
    int ok;
    field->kind = params->kind;
    switch (params->kind) {
    case RELIEF_SYNTH_PLANE_WAVES:
        ok = make_plane(b, params->vertices);
        break;
    case RELIEF_SYNTH_PLANE_NOISE:
        ok = make_plane(b, params->vertices) && make_pebbles(field, rng);
        break;
    case RELIEF_SYNTH_CYLINDER_BANDS:
    case RELIEF_SYNTH_CYLINDER_BARK:
        ok = make_cylinder(b, params->vertices);
        if (params->kind == RELIEF_SYNTH_CYLINDER_BARK)
            make_meander(field->w, rng);
        else
            make_waves(field->w, rng, 0.35, 0.9, 1);
        break;
    default:
        ok = make_sphere(b, params->vertices) && make_dimples(field, rng);
        break;
    }
    make_waves(field->cw, rng, 0.1, 0.3, params->kind == RELIEF_SYNTH_CYLINDER_BANDS ||
                                            params->kind == RELIEF_SYNTH_CYLINDER_BARK);
    field->norm = 1.0 / sqrt(N_WAVES / 2.0);
    /* plane-noise's colour follows its height alone: colour takes half of
     * a match's weight, and with the other kinds' variation (0.06) as well
     * its colour completions at 2000 vertices over seeds 1 to 8 differed in
     * MSI by up to 6.2 %, against 4.1 % without (the truth's own parts
     * differ by up to 4.8 %). The other kinds keep the variation. */
    field->colour_var = params->kind == RELIEF_SYNTH_PLANE_NOISE ? 0.0 : 0.06;
    return ok;
}

/* The truth: the base displaced by the field's heights (h, nv), labelled
 * by what the scanner sees (keep, nv), coloured by height when asked. */
static void synth_truth(const relief_synth_params *params, const relief_field *field,
                        const base_mesh *b, relief_mesh *truth, uint8_t *keep, double *h)
{
    double hmin = INFINITY, hmax = -INFINITY;
    for (size_t v = 0; v < b->nv; ++v) {
        h[v] = relief_height(field, b->p + 3 * v, b->uv[2 * v], b->uv[2 * v + 1]);
        hmin = h[v] < hmin ? h[v] : hmin;
        hmax = h[v] > hmax ? h[v] : hmax;
        keep[v] = (uint8_t)captured(params->kind, b->p + 3 * v, b->n + 3 * v);
        truth->label[v] = keep[v] ? RELIEF_LABEL_CAPTURED : RELIEF_LABEL_COMPLETED;
        for (int k = 0; k < 3; ++k)
            truth->pos[3 * v + k] = b->p[3 * v + k] + h[v] * b->n[3 * v + k];
    }
    if (params->colour)
        for (size_t v = 0; v < b->nv; ++v) {
            double t = hmax > hmin ? (h[v] - hmin) / (hmax - hmin) : 0.5;
            double var = field->norm * wave_sum(field->cw, b->uv[2 * v], b->uv[2 * v + 1]);
            relief_colour(field, t, var, truth->col + 3 * v);
        }
}

/* The capture: the truth's kept vertices, with scanner noise along the
 * normal drawn from rng; remap: nv scratch. */
static relief_status synth_capture(const relief_synth_params *params, const base_mesh *b,
                                   const relief_mesh *truth, const uint8_t *keep,
                                   uint32_t *remap, relief_rng *rng, relief_mesh **cap,
                                   relief_error *err)
{
    relief_status st = relief_mesh_subset(truth, keep, cap, remap, err);
    if (st != RELIEF_OK)
        return st;
    if (params->noise > 0.0)
        for (size_t v = 0; v < b->nv; ++v) {
            double d;
            if (remap[v] == UINT32_MAX)
                continue;
            d = params->noise * relief_rng_normal(rng);
            for (int k = 0; k < 3; ++k)
                (*cap)->pos[3 * (size_t)remap[v] + k] += d * b->n[3 * v + k];
        }
    for (size_t v = 0; v < (*cap)->nv; ++v)
        (*cap)->label[v] = RELIEF_LABEL_CAPTURED;
    return RELIEF_OK;
}

relief_status relief_synth(const relief_synth_params *params, relief_mesh **captured_out,
                           relief_mesh **truth_out, relief_error *err)
{
    RELIEF_ENTRY_ERR(err);
    relief_field field;
    base_mesh b;
    relief_rng rng;
    relief_mesh *truth = NULL, *cap = NULL;
    uint8_t *keep = NULL;
    uint32_t *remap = NULL;
    double *h = NULL;
    relief_status st = relief_synth_params_validate(params, err);

    if (st != RELIEF_OK)
        return st;
    memset(&field, 0, sizeof field);
    memset(&b, 0, sizeof b);
    relief_rng_seed(&rng, params->seed);
    if (!synth_base(params, &field, &b, &rng)) {
        st = relief_fail(err, RELIEF_E_NOMEM, "cannot allocate a %zu-vertex surface",
                         params->vertices);
        goto done;
    }
    st = relief_mesh_create(b.nv, b.nt,
                            RELIEF_MESH_LABELS | (params->colour ? RELIEF_MESH_COLOURS : 0u),
                            &truth, err);
    if (st != RELIEF_OK)
        goto done;
    memcpy(truth->tri, b.tri, b.nt * 3 * sizeof *b.tri);
    keep = malloc(b.nv);
    h = malloc(b.nv * sizeof *h);
    remap = malloc(b.nv * sizeof *remap);
    if (!keep || !h || !remap) {
        st = relief_fail(err, RELIEF_E_NOMEM, "cannot allocate a %zu-vertex surface", b.nv);
        goto done;
    }
    synth_truth(params, &field, &b, truth, keep, h);
    if (captured_out)
        st = synth_capture(params, &b, truth, keep, remap, &rng, &cap, err);

done:
    if (st == RELIEF_OK) {
        if (captured_out)
            *captured_out = cap;
        if (truth_out)
            *truth_out = truth;
        else
            relief_mesh_destroy(truth);
    } else {
        relief_mesh_destroy(cap);
        relief_mesh_destroy(truth);
    }
    free(remap);
    free(h);
    free(keep);
    free(field.dimple);
    free(field.pebble);
    base_free(&b);
    return st;
}
