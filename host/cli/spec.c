/* A command's options from its spec (options.h): the getopt table, the
 * parsing into the engine's parameters by their table, and the help, all
 * from one description. */
#include "cli/options.h"

#include <stdio.h>
#include <string.h>

#define MAX_OPTIONS 112
#define OPT_PARAM 1000    /* + index: a parameter of the table */
#define OPT_NO_PARAM 2000 /* + index: --no-NAME, a flag's 0 */
#define HELP_COLUMN 24
#define WIDTH 79

typedef struct option_table {
    struct option opts[MAX_OPTIONS];
    char names[MAX_OPTIONS][48];
    size_t n;
} option_table;

/* The shared options, in the order help lists them. */
static const struct {
    unsigned flag;
    struct option opt;
    const char *shown, *help;
} shared[] = {
    {CLI_OUTPUT, {"output", required_argument, 0, 'o'}, "-o, --output OUT", NULL},
    {CLI_REPORT, {"report", required_argument, 0, OPT_REPORT}, "--report R.json",
     "write the run's report: its parameters, counts, seconds per stage, backend"},
    {CLI_MASK, {"mask", required_argument, 0, OPT_MASK}, "--mask MASK", NULL},
    {CLI_SEED, {"seed", required_argument, 0, OPT_SEED}, "--seed N", "random seed (default 1)"},
    {CLI_QUIET, {"quiet", no_argument, 0, OPT_QUIET}, "--quiet", "no progress or notes on stderr"},
    {CLI_LIMIT, {"max-seconds", required_argument, 0, OPT_MAX_SECONDS}, "--max-seconds S",
     "stop (exit 1, no output) once the run has taken more than S seconds, measured; "
     "an estimate over S is a warning, never a stop (0, the default: no limit)"},
};

static int skipped(const cli_spec *s, const char *name)
{
    for (const char *const *k = s->skip; k && *k; ++k)
        if (strcmp(*k, name) == 0)
            return 1;
    return 0;
}

/* "--" + prefix + name with '_' as '-'. */
static void dashed(const char *prefix, const char *name, char *out, size_t n)
{
    snprintf(out, n, "%s%s", prefix, name);
    for (char *c = out; *c; ++c)
        if (*c == '_')
            *c = '-';
}

static void add(option_table *t, const char *name, int arg, int id)
{
    if (t->n + 2 >= MAX_OPTIONS)
        return;
    snprintf(t->names[t->n], sizeof t->names[0], "%s", name);
    t->opts[t->n] = (struct option){t->names[t->n], arg, 0, id};
    ++t->n;
}

static void build(const cli_spec *s, option_table *t)
{
    char name[48];
    t->n = 0;
    for (size_t i = 0; i < sizeof shared / sizeof shared[0]; ++i)
        if (s->shared & shared[i].flag)
            add(t, shared[i].opt.name, shared[i].opt.has_arg, shared[i].opt.val);
    for (size_t i = 0; i < s->n_params; ++i) {
        const relief_param *p = &s->params[i];
        if (skipped(s, p->name))
            continue;
        dashed("", p->name, name, sizeof name);
        add(t, name, p->kind == RELIEF_PARAM_FLAG ? no_argument : required_argument,
            OPT_PARAM + (int)i);
        if (p->kind == RELIEF_PARAM_FLAG) {
            dashed("no-", p->name, name, sizeof name);
            add(t, name, no_argument, OPT_NO_PARAM + (int)i);
        }
    }
    for (const cli_own *o = s->own; o && o->name; ++o)
        add(t, o->name, o->arg ? required_argument : no_argument, o->id);
    add(t, "help", no_argument, 'h');
    t->opts[t->n] = (struct option){0, 0, 0, 0};
}

/* A table parameter given on the command line. */
static int set_param(const cli_spec *s, void *params, int id, const char *arg)
{
    relief_error err = {0};
    const int no = id >= OPT_NO_PARAM;
    const relief_param *p = &s->params[id - (no ? OPT_NO_PARAM : OPT_PARAM)];
    const size_t n = strlen(p->name);
    char flag[48];
    if (relief_param_set(params, p, p->kind == RELIEF_PARAM_FLAG ? (no ? "0" : "1") : arg,
                         &err) == RELIEF_OK)
        return 1;
    /* The library names the parameter ("min_window: ..." with err.param
     * set, relief/core.h); the command line, its option. */
    dashed("--", p->name, flag, sizeof flag);
    if (strcmp(err.param, p->name) == 0)
        fprintf(stderr, "relief %s: %s%s\n", s->name, flag, err.message + n);
    else
        fprintf(stderr, "relief %s: %s: %s\n", s->name, flag, err.message);
    fprintf(stderr, "Try 'relief %s --help'.\n", s->name);
    return 0;
}

int cli_param_given(const cli_common *cm, const cli_spec *s, const char *name)
{
    const relief_param *p = relief_param_find(s->params, s->n_params, name);
    const size_t i = p ? (size_t)(p - s->params) : CLI_MAX_PARAMS;
    return i < CLI_MAX_PARAMS && (cm->given[i / 8] >> (i % 8) & 1u);
}

/* 0, or the help asked: CLI_HELP_TEXT (-h, --help), CLI_HELP_MAN
 * (--help-man) or CLI_HELP_MARKDOWN (--help-markdown). */
static int asks_help(int argc, char **argv)
{
    for (int i = 1; i < argc; ++i) {
        if (strcmp(argv[i], "--") == 0)
            return 0;
        if (strcmp(argv[i], "-h") == 0 || strcmp(argv[i], "--help") == 0)
            return CLI_HELP_TEXT;
        if (strcmp(argv[i], "--help-man") == 0)
            return CLI_HELP_MAN;
        if (strcmp(argv[i], "--help-markdown") == 0)
            return CLI_HELP_MARKDOWN;
    }
    return 0;
}

int cli_parse(const cli_spec *s, cli_common *cm, void *params,
              int (*take)(void *ctx, int id, const char *arg), void *ctx, int argc,
              char **argv)
{
    option_table t;
    int c, help = asks_help(argc, argv);
    if (help) { /* the defaults, whatever came before it */
        cli_help_as(s, params, stdout, help);
        return -1;
    }
    build(s, &t);
    cm->shared = s->shared;
    optind = 0;
    while ((c = getopt_long(argc, argv, "o:h", t.opts, NULL)) != -1) {
        int r = cli_common_option(cm, c, optarg);
        if (r < 0)
            return EXIT_USAGE;
        if (r > 0)
            continue;
        if (c >= OPT_PARAM && s->params) {
            const int i = c - (c >= OPT_NO_PARAM ? OPT_NO_PARAM : OPT_PARAM);
            if (!set_param(s, params, c, optarg))
                return EXIT_USAGE;
            if (i < CLI_MAX_PARAMS)
                cm->given[i / 8] |= (unsigned char)(1u << (i % 8));
        } else if (c >= OPT_COMMAND && c < OPT_PARAM && take) {
            if (!take(ctx, c, optarg))
                return EXIT_USAGE;
        } else {
            fprintf(stderr, "Try 'relief %s --help'.\n", s->name);
            return EXIT_USAGE;
        }
    }
    return 0;
}

/* ------------------------------------------------------------------ help */

/* `text` from column `indent` (the first line already at `at`), words
 * wrapped at WIDTH, "\n" a forced break. */
static void wrap(FILE *f, const char *text, int indent, int at)
{
    while (*text) {
        size_t word = strcspn(text, " \n");
        if (at > indent && at + 1 + (int)word > WIDTH) {
            fprintf(f, "\n%*s", indent, "");
            at = indent;
        } else if (at > indent) {
            fputc(' ', f);
            ++at;
        }
        fwrite(text, 1, word, f);
        at += (int)word;
        text += word;
        if (*text == '\n') {
            fprintf(f, "\n%*s", indent, "");
            at = indent;
        }
        while (*text == ' ' || *text == '\n')
            ++text;
    }
    fputc('\n', f);
}

static void option_line(FILE *f, const char *shown, const char *help)
{
    int at = fprintf(f, "  %s", shown);
    if (at >= HELP_COLUMN - 1) {
        fputc('\n', f);
        at = 0;
    }
    fprintf(f, "%*s", HELP_COLUMN - at, "");
    wrap(f, help ? help : "", HELP_COLUMN, HELP_COLUMN);
}

static void param_shown(const relief_param *p, const void *params, char *shown, size_t n);

static void param_line(FILE *f, const relief_param *p, const void *params)
{
    char shown[96];
    param_shown(p, params, shown, sizeof shown);
    option_line(f, shown, p->help);
}

static void shared_lines(FILE *f, const cli_spec *s, unsigned which)
{
    for (size_t i = 0; i < sizeof shared / sizeof shared[0]; ++i)
        if (s->shared & which & shared[i].flag)
            option_line(f, shared[i].shown,
                        shared[i].flag == CLI_OUTPUT ? s->out_help
                        : shared[i].flag == CLI_MASK ? s->mask_help
                                                     : shared[i].help);
}

/* ------------------------------------------------- the man page and docs */

/* `text` for troff: backslashes and dashes escaped, a line never starting
 * with a control character. */
static void troff(FILE *f, const char *text)
{
    for (const char *c = text; *c; ++c) {
        if ((c == text || c[-1] == '\n') && (*c == '.' || *c == '\''))
            fputs("\\&", f);
        if (*c == '\\')
            fputs("\\e", f);
        else if (*c == '-')
            fputs("\\-", f);
        else
            fputc(*c, f);
    }
}

/* `text` for a Markdown table cell: '|' escaped, line breaks as spaces. */
static void cell(FILE *f, const char *text)
{
    for (const char *c = text; *c; ++c)
        if (*c == '|')
            fputs("\\|", f);
        else
            fputc(*c == '\n' ? ' ' : *c, f);
}

/* One option, shown as `shown`, in the man page or a docs table. */
static void doc_option(FILE *f, int format, const char *shown, const char *help)
{
    if (format == CLI_HELP_MAN) {
        fputs(".TP\n.B ", f);
        troff(f, shown);
        fputc('\n', f);
        troff(f, help ? help : "");
        fputc('\n', f);
    } else {
        fputs("| `", f);
        cell(f, shown);
        fputs("` | ", f);
        cell(f, help ? help : "");
        fputs(" |\n", f);
    }
}

/* The shown form of a parameter, as param_line writes it. */
static void param_shown(const relief_param *p, const void *params, char *shown, size_t n)
{
    char name[48], value[32] = "0";
    int on = 0;
    if (p->kind == RELIEF_PARAM_FLAG && params) {
        relief_param_format(params, p, value, sizeof value);
        on = strcmp(value, "1") == 0;
    }
    dashed(on ? "--[no-]" : "--", p->name, name, sizeof name);
    if (p->kind == RELIEF_PARAM_FLAG)
        snprintf(shown, n, "%s", name);
    else
        snprintf(shown, n, "%s %s", name, p->value ? p->value : "V");
}

static void doc_shared(FILE *f, int format, const cli_spec *s, unsigned which)
{
    for (size_t i = 0; i < sizeof shared / sizeof shared[0]; ++i)
        if (s->shared & which & shared[i].flag)
            doc_option(f, format, shared[i].shown,
                       shared[i].flag == CLI_OUTPUT ? s->out_help
                       : shared[i].flag == CLI_MASK ? s->mask_help
                                                    : shared[i].help);
}

/* The command's section of relief(1), or its docs page's option table:
 * the same options, in the same order, with the same words as --help. */
static void cli_help_doc(const cli_spec *s, const void *params, FILE *f, int format)
{
    char shown[96];
    if (format == CLI_HELP_MAN) {
        fprintf(f, ".SS relief %s\n.B relief %s\n", s->name, s->name);
        troff(f, s->usage);
        fputs("\n.PP\n", f);
        for (const char *para = s->about; para && *para;) {
            const char *end = strstr(para, "\n\n");
            size_t n = end ? (size_t)(end - para) : strlen(para);
            char buf[2048];
            snprintf(buf, sizeof buf, "%.*s", (int)n, para);
            troff(f, buf);
            fputs("\n.PP\n", f);
            para = end ? end + 2 : para + n;
        }
    } else {
        fputs("| option | what it does |\n| --- | --- |\n", f);
    }
    doc_shared(f, format, s, CLI_OUTPUT | CLI_REPORT | CLI_MASK);
    for (const cli_own *o = s->own; o && o->name; ++o) {
        snprintf(shown, sizeof shown, "--%s%s%s", o->name, o->arg ? " " : "",
                 o->arg ? o->arg : "");
        doc_option(f, format, shown, o->help);
    }
    for (size_t i = 0; i < s->n_params; ++i)
        if (!skipped(s, s->params[i].name)) {
            param_shown(&s->params[i], params, shown, sizeof shown);
            doc_option(f, format, shown, s->params[i].help);
        }
    doc_shared(f, format, s, CLI_SEED | CLI_QUIET | CLI_LIMIT);
    if (s->tail && format == CLI_HELP_MAN) {
        fputs(".PP\n", f);
        troff(f, s->tail);
        fputc('\n', f);
    }
}

void cli_help_as(const cli_spec *s, const void *params, FILE *f, int format)
{
    if (format == CLI_HELP_TEXT)
        cli_help(s, params, f);
    else
        cli_help_doc(s, params, f, format);
}

void cli_help(const cli_spec *s, const void *params, FILE *f)
{
    const char *para = s->about;
    fprintf(f, "usage: relief %s %s\n\n", s->name, s->usage);
    while (para && *para) { /* paragraphs, each wrapped */
        const char *end = strstr(para, "\n\n");
        size_t n = end ? (size_t)(end - para) : strlen(para);
        char buf[2048];
        snprintf(buf, sizeof buf, "%.*s", (int)n, para);
        wrap(f, buf, 0, 0);
        fputc('\n', f);
        para = end ? end + 2 : para + n;
    }
    shared_lines(f, s, CLI_OUTPUT | CLI_REPORT | CLI_MASK);
    for (const cli_own *o = s->own; o && o->name; ++o) {
        char shown[96];
        snprintf(shown, sizeof shown, "--%s%s%s", o->name, o->arg ? " " : "",
                 o->arg ? o->arg : "");
        option_line(f, shown, o->help);
    }
    for (size_t i = 0; i < s->n_params; ++i)
        if (!skipped(s, s->params[i].name))
            param_line(f, &s->params[i], params);
    shared_lines(f, s, CLI_SEED | CLI_QUIET | CLI_LIMIT);
    option_line(f, "-h, --help", "this help");
    if (s->tail) {
        fputc('\n', f);
        wrap(f, s->tail, 0, 0);
    }
}
