/* relief_weld_copies (mesh/weld.h): a split bow-tie vertex whose pinch a
 * fill closed is welded again and its triangles of no area dropped; copies
 * whose fans would stay two are left apart, as is every other vertex. */
#include <math.h>
#include <string.h>

#include "check.h"
#include "base/vec3.h"
#include "mesh/weld.h"

/* A hexagon about c = 0 (ring r = 1..6 counter-clockwise) and c's copy
 * c' = 7 at the same place, as the reader's split leaves a bow-tie:
 * fan A (c, r1, r2), (c, r2, r3) and fan B (c', r4, r5), (c', r5, r6). */
static void hexagon(double pos[8 * 3])
{
    memset(pos, 0, 8 * 3 * sizeof *pos);
    for (int k = 0; k < 6; ++k) {
        pos[3 * (k + 1)] = cos(k * RELIEF_PI / 3.0);
        pos[3 * (k + 1) + 1] = sin(k * RELIEF_PI / 3.0);
    }
}

/* Both wedges between the fans filled, as the ears lay them: each one
 * triangle of the wedge and one of no area joining c and c'. */
static void closed_pinch(void)
{
    double pos[8 * 3];
    uint32_t tri[] = {0, 1, 2, 0, 2, 3, 7, 4, 5, 7, 5, 6, /* the fans */
                      0, 3, 7, 7, 3, 4,                    /* wedge r3 r4 */
                      7, 6, 1, 7, 1, 0};                   /* wedge r6 r1 */
    size_t nt = sizeof tri / sizeof tri[0] / 3, welded = 0;
    relief_error err = {0};
    hexagon(pos);
    CHECK(relief_weld_copies(pos, 8, tri, &nt, &welded, &err) == RELIEF_OK, "%s", err.message);
    CHECK(welded == 1 && nt == 6, "closed pinch: %zu welded, %zu triangles (1, 6 wanted)",
          welded, nt);
    for (size_t t = 0; t < nt; ++t)
        CHECK(tri[3 * t] == 0 && tri[3 * t + 1] != 7 && tri[3 * t + 2] != 7 &&
                  tri[3 * t + 2] == tri[3 * t + 1] % 6 + 1,
              "closed pinch: triangle %zu is (%u, %u, %u), not (0, r, r + 1)", t, tri[3 * t],
              tri[3 * t + 1], tri[3 * t + 2]);
}

/* One wedge filled, the other open: the welded vertex is a border vertex
 * with one fan (a half-disc), and is welded. */
static void half_closed(void)
{
    double pos[8 * 3];
    uint32_t tri[] = {0, 1, 2, 0, 2, 3, 7, 4, 5, 7, 5, 6, 0, 3, 7, 7, 3, 4};
    size_t nt = 6, welded = 0;
    relief_error err = {0};
    hexagon(pos);
    CHECK(relief_weld_copies(pos, 8, tri, &nt, &welded, &err) == RELIEF_OK, "%s", err.message);
    CHECK(welded == 1 && nt == 5, "one wedge filled: %zu welded, %zu triangles (1, 5 wanted)",
          welded, nt);
}

/* The fans still apart: a triangle of no area joins the copies, but
 * welding them would make a bow-tie again; nothing changes. */
static void open_pinch(void)
{
    double pos[8 * 3];
    uint32_t tri[] = {0, 1, 2, 7, 4, 5, 0, 2, 7};
    const uint32_t before[] = {0, 1, 2, 7, 4, 5, 0, 2, 7};
    size_t nt = 3, welded = 0;
    relief_error err = {0};
    hexagon(pos);
    CHECK(relief_weld_copies(pos, 8, tri, &nt, &welded, &err) == RELIEF_OK, "%s", err.message);
    CHECK(welded == 0 && nt == 3 && memcmp(tri, before, sizeof before) == 0,
          "open pinch: %zu welded, %zu triangles (0, 3 unchanged wanted)", welded, nt);
}

/* Coincident vertices no triangle joins (two sheets touching) and a
 * mesh with no copies: left as they are. */
static void untouched(void)
{
    double pos[8 * 3];
    uint32_t tri[] = {0, 1, 2, 0, 2, 3, 7, 4, 5, 7, 5, 6};
    const uint32_t before[] = {0, 1, 2, 0, 2, 3, 7, 4, 5, 7, 5, 6};
    size_t nt = 4, welded = 0;
    relief_error err = {0};
    hexagon(pos);
    CHECK(relief_weld_copies(pos, 8, tri, &nt, &welded, &err) == RELIEF_OK, "%s", err.message);
    CHECK(welded == 0 && nt == 4 && memcmp(tri, before, sizeof before) == 0,
          "unjoined copies: %zu welded, %zu triangles", welded, nt);
    nt = 0;
    CHECK(relief_weld_copies(pos, 8, tri, &nt, &welded, &err) == RELIEF_OK && welded == 0,
          "no triangles: %s", err.message);
}

int main(void)
{
    closed_pinch();
    half_closed();
    open_pinch();
    untouched();
    return check_result();
}
