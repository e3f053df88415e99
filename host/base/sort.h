/* Sorting (key, index) pairs by key: an LSD radix sort, stable, in
 * O(n) per byte of the keys that differ, for the cell orders of the point
 * engines, where qsort's comparisons were a tenth of a fit. */
#ifndef RELIEF_HOST_BASE_SORT_H
#define RELIEF_HOST_BASE_SORT_H

#include <stddef.h>
#include <stdint.h>

typedef struct relief_keyed {
    uint64_t key;
    uint32_t index;
} relief_keyed;

/* Sort a (n) by key, pairs of equal keys keeping their order: with the
 * indices ascending on entry, the order of (key, index). 0, or -1 when the
 * scratch (n pairs) cannot be allocated (a then unchanged). */
int relief_sort_keyed(relief_keyed *a, size_t n);

#endif
