/* The radix sort of (key, index) pairs (base/sort.h) gives qsort's order
 * by (key, index): keys with many ties, keys that differ only in their
 * high bytes or low bytes, all keys equal, and 0, 1 and 2 pairs. The
 * sort of doubles gives qsort's values: signs, zeros of both signs,
 * infinities, ties, tiny and huge magnitudes. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "base/sort.h"

static int by_key_index(const void *a, const void *b)
{
    const relief_keyed *x = a, *y = b;
    if (x->key != y->key)
        return x->key < y->key ? -1 : 1;
    return (x->index > y->index) - (x->index < y->index);
}

/* n pairs of keys from draw(i), indices ascending: sorted both ways. */
static void check_keys(size_t n, uint64_t (*draw)(uint64_t *s), const char *what)
{
    relief_keyed *a = malloc((n ? n : 1) * sizeof *a), *b = malloc((n ? n : 1) * sizeof *b);
    uint64_t s = 12345;
    for (size_t i = 0; i < n; ++i)
        a[i] = (relief_keyed){draw(&s), (uint32_t)i};
    memcpy(b, a, n * sizeof *a);
    CHECK(relief_sort_keyed(a, n) == 0, "%s: out of memory", what);
    qsort(b, n, sizeof *b, by_key_index);
    CHECK(n == 0 || !memcmp(a, b, n * sizeof *a), "%s (%zu pairs): not qsort's order", what, n);
    free(a), free(b);
}

static uint64_t next(uint64_t *s)
{
    *s = *s * 6364136223846793005ULL + 1442695040888963407ULL;
    return *s >> 11;
}
static uint64_t ties(uint64_t *s) { return next(s) % 37; }
static uint64_t high(uint64_t *s) { return (next(s) % 300) << 52; }
static uint64_t spread(uint64_t *s) { return next(s) ^ (next(s) << 40); }
static uint64_t same(uint64_t *s) { (void)s; return 0xABCDEF; }

static int by_value(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* n doubles from draw: relief_sort_doubles against qsort, value by value
 * (-0 == +0), and -0 before +0. */
static void check_doubles(size_t n, double (*draw)(uint64_t *s), const char *what)
{
    double *a = malloc((n ? n : 1) * sizeof *a), *b = malloc((n ? n : 1) * sizeof *b);
    uint64_t s = 777;
    int same = 1, zeros = 1;
    for (size_t i = 0; i < n; ++i)
        a[i] = b[i] = draw(&s);
    CHECK(relief_sort_doubles(a, n) == 0, "%s: out of memory", what);
    qsort(b, n, sizeof *b, by_value);
    for (size_t i = 0; i < n; ++i) {
        same &= a[i] == b[i];
        zeros &= !(i > 0 && a[i] == 0.0 && signbit(a[i]) && !signbit(a[i - 1]));
    }
    CHECK(same && zeros, "%s (%zu values): not qsort's order", what, n);
    free(a), free(b);
}

static double mixed(uint64_t *s)
{
    static const double special[6] = {0.0, -0.0, INFINITY, -INFINITY, 1e-310, -1e300};
    uint64_t r = next(s);
    if (r % 10 == 0)
        return special[(r / 10) % 6];
    return ((double)(int64_t)(r % 2001) - 1000.0) * pow(10.0, (double)(r % 61) - 30.0);
}
static double few(uint64_t *s) { return (double)(next(s) % 7) - 3.0; }

int main(void)
{
    for (size_t n = 0; n < 4; ++n)
        check_doubles(n, mixed, "a few doubles");
    check_doubles(30000, mixed, "mixed doubles");
    check_doubles(30000, few, "7 values");
    for (size_t n = 0; n < 4; ++n)
        check_keys(n, spread, "a few");
    check_keys(20000, ties, "37 keys");
    check_keys(20000, high, "high bytes");
    check_keys(20000, spread, "all bytes");
    check_keys(5000, same, "one key");
    printf("sort: 20 000 pairs three ways, 5000 of one key and 30 000 doubles two ways in "
           "qsort's order\n");
    return check_result();
}
