/* Union-find over indices 0..n-1 held in the caller's parent array
 * (parent[i] = i to start): find with path halving, and a join whose
 * smaller root wins, so that a component's root, and any label numbered
 * from it, is its smallest index whatever the order of the joins. */
#ifndef RELIEF_HOST_UNION_FIND_H
#define RELIEF_HOST_UNION_FIND_H

#include <stdint.h>

static inline uint32_t relief_uf_find(uint32_t *parent, uint32_t i)
{
    while (parent[i] != i) {
        parent[i] = parent[parent[i]];
        i = parent[i];
    }
    return i;
}

static inline void relief_uf_join(uint32_t *parent, uint32_t a, uint32_t b)
{
    a = relief_uf_find(parent, a);
    b = relief_uf_find(parent, b);
    if (a < b)
        parent[b] = a;
    else if (b < a)
        parent[a] = b;
}

#endif
