/* The radix sort of (key, index) pairs (sort.h). */
#include "base/sort.h"

#include <stdlib.h>
#include <string.h>

int relief_sort_keyed(relief_keyed *a, size_t n)
{
    relief_keyed *tmp, *src = a, *dst;
    uint64_t differ = 0;
    if (n < 2)
        return 0;
    tmp = malloc(n * sizeof *tmp);
    if (!tmp)
        return -1;
    dst = tmp;
    for (size_t i = 1; i < n; ++i)
        differ |= a[i].key ^ a[0].key;
    for (int shift = 0; shift < 64; shift += 8) {
        size_t count[257] = {0};
        if (!((differ >> shift) & 0xff))
            continue; /* every key has this byte: the pass would keep the order */
        for (size_t i = 0; i < n; ++i)
            ++count[((src[i].key >> shift) & 0xff) + 1];
        for (int b = 0; b < 256; ++b)
            count[b + 1] += count[b];
        for (size_t i = 0; i < n; ++i)
            dst[count[(src[i].key >> shift) & 0xff]++] = src[i];
        {
            relief_keyed *t = src;
            src = dst, dst = t;
        }
    }
    if (src != a)
        memcpy(a, src, n * sizeof *a);
    free(tmp);
    return 0;
}
