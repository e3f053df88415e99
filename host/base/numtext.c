/* Numbers in text in the C locale (numtext.h): uselocale around the call. */
#include "base/numtext.h"

#include <stdlib.h>

void relief_numtext_begin(relief_numtext_scope *s)
{
    /* LC_ALL_MASK over no base: the whole C locale, which glibc and musl
     * return without allocating. Only LC_NUMERIC matters here; the other
     * categories are the C locale's for the few calls inside a scope. */
    s->c = newlocale(LC_ALL_MASK, "C", (locale_t)0);
    s->saved = s->c ? uselocale(s->c) : (locale_t)0;
}

void relief_numtext_end(relief_numtext_scope *s)
{
    if (!s->c)
        return;
    uselocale(s->saved);
    freelocale(s->c);
    s->c = (locale_t)0;
}

double relief_strtod(const char *s, char **end)
{
    relief_numtext_scope scope;
    double v;
    relief_numtext_begin(&scope);
    v = strtod(s, end);
    relief_numtext_end(&scope);
    return v;
}

int relief_vsnprintf_c(char *buf, size_t size, const char *fmt, va_list ap)
{
    relief_numtext_scope scope;
    int n;
    relief_numtext_begin(&scope);
    n = vsnprintf(buf, size, fmt, ap);
    relief_numtext_end(&scope);
    return n;
}

int relief_snprintf_c(char *buf, size_t size, const char *fmt, ...)
{
    va_list ap;
    int n;
    va_start(ap, fmt);
    n = relief_vsnprintf_c(buf, size, fmt, ap);
    va_end(ap);
    return n;
}

int relief_fprintf_c(FILE *f, const char *fmt, ...)
{
    relief_numtext_scope scope;
    va_list ap;
    int n;
    relief_numtext_begin(&scope);
    va_start(ap, fmt);
    n = vfprintf(f, fmt, ap);
    va_end(ap);
    relief_numtext_end(&scope);
    return n;
}
