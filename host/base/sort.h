/* Sorting (key, index) pairs by key, and doubles: LSD radix sorts, in
 * O(n) per byte of the keys that differ, for the cell orders of the point
 * engines, where qsort's comparisons were a tenth of a fit, and the range
 * check on reading a mesh. */
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

/* Sort a (n) ascending by value, as qsort with a < comparison sorts
 * numbers (-0 before +0; NaNs, which have no order, at the ends by sign),
 * in O(n) a byte of the values that differ: the range check of every mesh
 * read sorts all its coordinates, where qsort's calls through a comparison
 * took a quarter of a second on a 226 000-point scan. 0, or -1 when the
 * scratch (2 n values) cannot be allocated (a then unchanged). */
int relief_sort_doubles(double *a, size_t n);

#endif
