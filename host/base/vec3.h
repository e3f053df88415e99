/* Small 3-vector helpers on double[3], shared by the host modules and the
 * tests (header-only). */
#ifndef RELIEF_HOST_VEC3_H
#define RELIEF_HOST_VEC3_H

/* pi, the one definition the host uses. */
#define RELIEF_PI 3.14159265358979323846

/* r = a - b */
static inline void sub3(const double *a, const double *b, double *r)
{
    r[0] = a[0] - b[0];
    r[1] = a[1] - b[1];
    r[2] = a[2] - b[2];
}

static inline double dot3(const double *a, const double *b)
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

/* r = a x b (r must not alias a or b) */
static inline void cross3(const double *a, const double *b, double *r)
{
    r[0] = a[1] * b[2] - a[2] * b[1];
    r[1] = a[2] * b[0] - a[0] * b[2];
    r[2] = a[0] * b[1] - a[1] * b[0];
}

#endif
