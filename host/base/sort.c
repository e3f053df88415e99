/* The radix sorts of (key, index) pairs and of doubles (sort.h). */
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

/* A double's bits as a key in the doubles' order: the sign bit set for the
 * positive, every bit flipped for the negative (-0 before +0). */
static uint64_t order_key(uint64_t b) { return b >> 63 ? ~b : b | (uint64_t)1 << 63; }
static uint64_t order_bits(uint64_t k) { return k >> 63 ? k & ~((uint64_t)1 << 63) : ~k; }

int relief_sort_doubles(double *a, size_t n)
{
    uint64_t *k, *tmp, *src, *dst, differ = 0;
    if (n < 2)
        return 0;
    k = malloc(n * sizeof *k);
    tmp = k ? malloc(n * sizeof *tmp) : NULL;
    if (!tmp) {
        free(k);
        return -1;
    }
    for (size_t i = 0; i < n; ++i) {
        uint64_t b;
        memcpy(&b, a + i, sizeof b);
        k[i] = order_key(b);
        differ |= k[i] ^ k[0];
    }
    src = k, dst = tmp;
    for (int shift = 0; shift < 64; shift += 8) {
        size_t count[257] = {0};
        if (!((differ >> shift) & 0xff))
            continue; /* every key has this byte */
        for (size_t i = 0; i < n; ++i)
            ++count[((src[i] >> shift) & 0xff) + 1];
        for (int b = 0; b < 256; ++b)
            count[b + 1] += count[b];
        for (size_t i = 0; i < n; ++i)
            dst[count[(src[i] >> shift) & 0xff]++] = src[i];
        {
            uint64_t *t = src;
            src = dst, dst = t;
        }
    }
    for (size_t i = 0; i < n; ++i) {
        uint64_t b = order_bits(src[i]);
        memcpy(a + i, &b, sizeof b);
    }
    free(k), free(tmp);
    return 0;
}
