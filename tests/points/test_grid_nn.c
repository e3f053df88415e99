/* The texture optimisation's grid search (host/points/grid_nn.c): brute
 * force on the host and by kernels/grid.cl on OpenCL give the same
 * neighbours, in more queries than one device launch takes; both are the
 * true k nearest (checked in double against every exemplar); the kd-tree
 * finds the same ones where no two distances tie; ties go to the lower
 * index; bad k is refused. The OpenCL half skips without a platform. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "points/grid_nn.h"

#define NZ 700
#define DIMS 75
#define NQ 70 /* over one launch's 64 */
#define K 8

static uint64_t state = 88172645463325252ull;
static float draw(void)
{
    state ^= state << 13, state ^= state >> 7, state ^= state << 17;
    return (float)((state >> 11) * (1.0 / 9007199254740992.0));
}

static relief_status search(relief_grid_search s, relief_backend b, const float *z,
                            const float *q, uint32_t *idx, char *name, relief_error *err)
{
    relief_grid_nn *nn = NULL;
    relief_status st = relief_grid_nn_create(s, b, -1, z, NZ, DIMS, 2, &nn, NULL, 0, NULL, err);
    if (st == RELIEF_OK) {
        st = relief_grid_nn_query(nn, q, NQ, K, idx, err);
        snprintf(name, 320, "%s", relief_grid_nn_name(nn));
    }
    relief_grid_nn_destroy(nn);
    return st;
}

int main(void)
{
    float *z = malloc(NZ * DIMS * sizeof *z), *q = malloc(NQ * DIMS * sizeof *q);
    uint32_t scalar[NQ * K], cl[NQ * K], kd[NQ * K];
    char name[320];
    relief_error err;
    relief_status st;
    size_t exact = 0;
    for (int i = 0; i < NZ * DIMS; ++i)
        z[i] = draw();
    for (int i = 0; i < NQ * DIMS; ++i)
        q[i] = draw();
    /* Exemplar 5 twice (at 5 and 600), query 3 on it: the tie goes to 5. */
    memcpy(z + 600 * DIMS, z + 5 * DIMS, DIMS * sizeof *z);
    memcpy(q + 3 * DIMS, z + 5 * DIMS, DIMS * sizeof *z);

    CHECK(search(RELIEF_GRID_SEARCH_BRUTE, RELIEF_BACKEND_SCALAR, z, q, scalar, name, &err) ==
              RELIEF_OK, "%s", err.message);
    printf("%s\n", name);
    for (int i = 0; i < NQ; ++i) {
        double d[NZ], kth;
        int nearer = 0;
        for (int e = 0; e < NZ; ++e) {
            d[e] = 0;
            for (int t = 0; t < DIMS; ++t)
                d[e] += ((double)q[i * DIMS + t] - z[e * DIMS + t]) *
                        ((double)q[i * DIMS + t] - z[e * DIMS + t]);
        }
        kth = d[scalar[i * K + K - 1]];
        for (int e = 0; e < NZ; ++e)
            nearer += d[e] < kth - 1e-9;
        for (int j = 1; j < K; ++j)
            CHECK(d[scalar[i * K + j - 1]] <= d[scalar[i * K + j]] + 1e-9, "query %d: %d before %d "
                  "out of order", i, j - 1, j);
        exact += nearer <= K - 1;
    }
    CHECK(exact == NQ, "%zu of %d queries got their true %d nearest", exact, NQ, K);
    CHECK(scalar[3 * K] == 5 && scalar[3 * K + 1] == 600, "a tie went to %u before %u",
          scalar[3 * K], scalar[3 * K + 1]);

    st = search(RELIEF_GRID_SEARCH_BRUTE, RELIEF_BACKEND_OPENCL, z, q, cl, name, &err);
    if (st == RELIEF_E_DEVICE || st == RELIEF_E_NOT_BUILT)
        printf("OpenCL skipped: %s\n", err.message);
    else {
        CHECK(st == RELIEF_OK, "%s", err.message);
        printf("%s\n", name);
        CHECK(memcmp(cl, scalar, sizeof cl) == 0, "OpenCL and the scalar twin disagree");
    }

    CHECK(search(RELIEF_GRID_SEARCH_KDTREE, RELIEF_BACKEND_AUTO, z, q, kd, name, &err) == RELIEF_OK,
          "%s", err.message);
    {
        int differ = 0;
        for (int i = 0; i < NQ; ++i)
            if (i != 3) /* the tie: the kd-tree may take either */
                differ += memcmp(kd + i * K, scalar + i * K, K * sizeof *kd) != 0;
        CHECK(differ == 0, "the kd-tree and brute force differ on %d queries", differ);
    }

    {
        relief_grid_nn *nn = NULL;
        CHECK(relief_grid_nn_create(RELIEF_GRID_SEARCH_BRUTE, RELIEF_BACKEND_SCALAR, -1, z, NZ, DIMS, 1,
                                    &nn, NULL, 0, NULL, &err) == RELIEF_OK, "%s", err.message);
        CHECK(nn && relief_grid_nn_query(nn, q, 1, 9, scalar, &err) == RELIEF_E_RANGE,
              "k 9 accepted");
        relief_grid_nn_destroy(nn);
        CHECK(relief_grid_nn_create(RELIEF_GRID_SEARCH_BRUTE, RELIEF_BACKEND_SCALAR, -1, z, 0, DIMS, 1,
                                    &nn, NULL, 0, NULL, &err) == RELIEF_E_RANGE, "no exemplars accepted");
    }
    free(z), free(q);
    return check_result();
}
