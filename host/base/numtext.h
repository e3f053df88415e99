/* Numbers in text, read and written in the C locale whatever the caller's.
 *
 * relief's files (PLY, OFF, PCD, PFM headers, JSON, the report), its
 * parameter strings and its messages write a number as "0.5": '.' for the
 * decimal point, no digit grouping. strtod and the printf family follow the
 * calling program's LC_NUMERIC instead, and a GTK host such as GIMP, or
 * Python after locale.setlocale, may have set one with ','; strtod("0.5")
 * then stops at the '.', and "%g" writes "0,5". Every parser and writer in
 * the library goes through these instead (tests/test_layout.sh keeps strtod,
 * atof and scanf out of host/ but here).
 *
 * How: the C locale as a POSIX 2008 locale_t, made current on the calling
 * thread only (uselocale) for the strtod or the printf, and the thread's own
 * put back after. uselocale is per thread, so nothing the caller sees
 * changes, two threads may do it at once, and the library's worker threads
 * (base/pool.c, base/parallel.c), which start in the process's global
 * locale, get the same answer. The locale_t is made for each use and freed
 * after it, so the library keeps no global state: glibc and musl hand back
 * their one static C locale for newlocale(LC_ALL_MASK, "C", 0) and their
 * freelocale leaves it be, so a use costs a few pointer swaps. (strtod_l is
 * a GNU and BSD extension outside POSIX 2008, and there is no snprintf_l in
 * glibc: uselocale serves both.) */
#ifndef RELIEF_HOST_NUMTEXT_H
#define RELIEF_HOST_NUMTEXT_H

#include <locale.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>

#include "base/error.h" /* RELIEF_PRINTF */

/* The C locale made current on this thread between relief_numtext_begin and
 * relief_numtext_end, for a writer of many numbers (one scope, not one per
 * number). Scopes nest. */
typedef struct relief_numtext_scope {
    locale_t c;     /* the C locale of this scope; (locale_t)0 when none could be made */
    locale_t saved; /* the thread's locale before it */
} relief_numtext_scope;

/* Make the C locale current on the calling thread. Where it cannot be made
 * (out of memory, on a C library that allocates it) the thread's locale
 * stays, and numbers follow it as they would without this. */
void relief_numtext_begin(relief_numtext_scope *s);
/* Put back the thread's locale from before begin(s). */
void relief_numtext_end(relief_numtext_scope *s);

/* strtod in the C locale: "0.5" is a half whatever the caller's locale;
 * "0,5" reads as 0 and stops at the ','. */
double relief_strtod(const char *s, char **end);

/* snprintf, vsnprintf and fprintf in the C locale ("%g" of a half is "0.5"). */
int relief_snprintf_c(char *buf, size_t size, const char *fmt, ...) RELIEF_PRINTF(3, 4);
int relief_vsnprintf_c(char *buf, size_t size, const char *fmt, va_list ap);
int relief_fprintf_c(FILE *f, const char *fmt, ...) RELIEF_PRINTF(2, 3);

#endif
