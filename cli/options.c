#include "cli/options.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

static int parse_double(const char *s, double *out)
{
    char *end;
    errno = 0;
    double v = strtod(s, &end);
    if (end == s || *end != '\0' || errno == ERANGE || !isfinite(v))
        return 0;
    *out = v;
    return 1;
}

/* Parses one option's value; returns 0 and prints why on failure. */
static int parse_value(const plm_command_help *help, plm_option *o, const char *value)
{
    const char *cmd = help->usage;
    switch (o->kind) {
    case PLM_OPT_FLAG:
        *(int *)o->target = 1;
        return 1;
    case PLM_OPT_STRING:
        *(const char **)o->target = value;
        return 1;
    case PLM_OPT_LIST: {
        plm_opt_list *list = o->target;
        if (list->count == PLM_OPT_LIST_MAX) {
            fprintf(stderr, "error: %s: at most %d may be given\n", o->name, PLM_OPT_LIST_MAX);
            return 0;
        }
        list->items[list->count++] = value;
        return 1;
    }
    case PLM_OPT_CHOICE:
        for (int i = 0; o->choices[i]; ++i)
            if (strcmp(o->choices[i], value) == 0) {
                *(int *)o->target = i;
                return 1;
            }
        fprintf(stderr, "error: %s: '%s' is not one of:", o->name, value);
        for (int i = 0; o->choices[i]; ++i)
            fprintf(stderr, " %s", o->choices[i]);
        fprintf(stderr, "\n");
        return 0;
    case PLM_OPT_INT: {
        double v;
        if (!parse_double(value, &v) || v != floor(v) || v < o->lo || v > o->hi) {
            fprintf(stderr, "error: %s: '%s' must be a whole number in [%.0f, %.0f]\n", o->name, value, o->lo, o->hi);
            return 0;
        }
        *(int *)o->target = (int)v;
        return 1;
    }
    case PLM_OPT_DOUBLE:
    case PLM_OPT_DOUBLES: {
        int count = o->kind == PLM_OPT_DOUBLE ? 1 : o->count;
        double vals[16];
        char buf[512];
        snprintf(buf, sizeof buf, "%s", value);
        int n = 0;
        char *save = NULL;
        for (char *tok = strtok_r(buf, ",", &save); tok; tok = strtok_r(NULL, ",", &save)) {
            if (n >= count || !parse_double(tok, &vals[n]))
                break;
            ++n;
            if (vals[n - 1] < o->lo || vals[n - 1] > o->hi) {
                fprintf(stderr, "error: %s: %.10g is out of range [%.10g, %.10g]\n", o->name, vals[n - 1], o->lo, o->hi);
                return 0;
            }
        }
        if (n != count || strtok_r(NULL, ",", &save)) {
            fprintf(stderr, "error: %s: '%s' must be %d comma-separated number%s in [%.10g, %.10g]\n", o->name, value,
                    count, count > 1 ? "s" : "", o->lo, o->hi);
            return 0;
        }
        memcpy(o->target, vals, (size_t)count * sizeof(double));
        return 1;
    }
    }
    (void)cmd;
    return 0;
}

/* Help lines are wrapped at HELP_WIDTH columns; a line the text already
 * breaks by hand is left alone unless it runs past HELP_SLACK. */
enum { HELP_WIDTH = 100, HELP_SLACK = 112 };

/* Prints text starting at column col, breaking too long lines at spaces
 * before HELP_WIDTH where the words allow. A continuation starts at column
 * indent, or under the first word of its line if that is further in; the
 * text's own newlines and leading spaces are kept. Ends with a newline. */
static void print_wrapped(FILE *out, const char *text, int col, int indent)
{
    int line_indent = indent, words = 0, wrap = 0;
    for (const char *p = text; *p;) {
        if (words == 0 && (p == text || p[-1] == '\n'))
            wrap = col + (int)strcspn(p, "\n") > HELP_SLACK;
        if (*p == '\n') {
            fputc('\n', out);
            col = 0, line_indent = indent, words = 0;
            ++p;
        } else if (*p == ' ') {
            size_t next = strcspn(p + 1, " \n");
            if (wrap && words > 0 && next > 0 && col + 1 + (int)next > HELP_WIDTH) {
                fprintf(out, "\n%*s", line_indent, "");
                col = line_indent;
            } else {
                fputc(' ', out);
                ++col;
            }
            ++p;
        } else {
            if (words == 0 && col > line_indent)
                line_indent = col;
            size_t n = strcspn(p, " \n");
            fwrite(p, 1, n, out);
            col += (int)n, ++words;
            p += n;
        }
    }
    fputc('\n', out);
}

static const plm_param *table_field(const plm_param_block *b, const char *field)
{
    for (int i = 0; i < b->count; ++i)
        if (strcmp(b->params[i].name, field) == 0)
            return &b->params[i];
    fprintf(stderr, "internal error: %s has no field %s\n", b->name, field);
    abort();
}

void plm_option_range_from(plm_option *o, const plm_param_block *b, const char *field)
{
    const plm_param *p = table_field(b, field);
    o->lo = p->min;
    o->hi = p->max;
}

int plm_option_check_open(const plm_option *o, const plm_param_block *b, const char *field)
{
    const plm_param *p = table_field(b, field);
    double v = *(const double *)o->target;
    if ((v == p->min && (p->open & PLM_PARAM_OPEN_MIN)) || (v == p->max && (p->open & PLM_PARAM_OPEN_MAX))) {
        fprintf(stderr, "error: %s: %.10g is out of range %s%.10g, %.10g%s\n", o->name, v,
                p->open & PLM_PARAM_OPEN_MIN ? "(" : "[", p->min, p->max, p->open & PLM_PARAM_OPEN_MAX ? ")" : "]");
        return 0;
    }
    return 1;
}

static plm_opt_kind option_kind(plm_param_type t, int *count)
{
    *count = t == PLM_PARAM_RGB || t == PLM_PARAM_VEC3 ? 3 : t == PLM_PARAM_PAIR ? 2 : 1;
    return t == PLM_PARAM_INT ? PLM_OPT_INT : *count > 1 ? PLM_OPT_DOUBLES : PLM_OPT_DOUBLE;
}

void plm_option_param(plm_option *o, plm_option_text *text, const plm_param_block *b, const char *field, void *target,
                      const char *metavar)
{
    const plm_param *p = table_field(b, field);
    snprintf(text->name, sizeof text->name, "--%s", field);
    for (char *c = text->name; *c; ++c)
        *c = *c == '_' ? '-' : *c;
    int count;
    *o = (plm_option){text->name, option_kind(p->type, &count), target, count, p->min, p->max, NULL, metavar,
                      text->help, 0};
    char value[96];
    if (o->kind == PLM_OPT_INT)
        snprintf(value, sizeof value, "%d", *(const int *)target);
    else {
        const double *v = target;
        int n = snprintf(value, sizeof value, "%g", v[0]);
        for (int i = 1; i < count; ++i)
            n += snprintf(value + n, sizeof value - (size_t)n, ",%g", v[i]);
    }
    snprintf(text->help, sizeof text->help, "%s%s%s%s; default %s", p->meaning, p->unit[0] ? " (" : "", p->unit,
             p->unit[0] ? ")" : "", value);
}

void plm_print_help(FILE *out, const plm_command_help *help, const plm_option *opts, int n_opts)
{
    fprintf(out, "usage: %s\n\n", help->usage);
    print_wrapped(out, help->summary, 0, 0);
    fprintf(out, "\noptions:\n");
    for (int i = 0; i < n_opts + 1; ++i) {
        char left[96];
        if (i < n_opts)
            snprintf(left, sizeof left, "%s%s%s", opts[i].name, opts[i].metavar ? " " : "",
                     opts[i].metavar ? opts[i].metavar : "");
        else
            snprintf(left, sizeof left, "--help");
        int col = fprintf(out, "  %-30s ", left);
        print_wrapped(out, i < n_opts ? opts[i].help : "show this help and exit", col, 33);
    }
}

int plm_parse_options(const plm_command_help *help, int argc, char **argv, int first, plm_option *opts,
                      int n_opts, const char **positional, int max_positional, int *n_positional)
{
    if (n_positional)
        *n_positional = 0;
    for (int i = first; i < argc; ++i) {
        const char *arg = argv[i];
        if (strcmp(arg, "--help") == 0 || strcmp(arg, "-h") == 0) {
            plm_print_help(stdout, help, opts, n_opts);
            return 1;
        }
        if (strncmp(arg, "-", 1) != 0 || strcmp(arg, "-") == 0) {
            if (!n_positional || *n_positional >= max_positional) {
                fprintf(stderr, "error: unexpected argument '%s' (see --help)\n", arg);
                return 2;
            }
            positional[(*n_positional)++] = arg;
            continue;
        }
        /* Accept both "--name value" and "--name=value". */
        const char *eq = strchr(arg, '=');
        size_t name_len = eq ? (size_t)(eq - arg) : strlen(arg);
        plm_option *o = NULL;
        for (int k = 0; k < n_opts && !o; ++k)
            if (strlen(opts[k].name) == name_len && strncmp(opts[k].name, arg, name_len) == 0)
                o = &opts[k];
        if (!o) {
            fprintf(stderr, "error: unknown option '%.*s' (see --help)\n", (int)name_len, arg);
            return 2;
        }
        const char *value = eq ? eq + 1 : NULL;
        if (o->kind == PLM_OPT_FLAG) {
            if (value) {
                fprintf(stderr, "error: %s takes no value\n", o->name);
                return 2;
            }
        } else if (!value) {
            if (i + 1 >= argc) {
                fprintf(stderr, "error: %s needs a value (%s)\n", o->name, o->metavar ? o->metavar : "value");
                return 2;
            }
            value = argv[++i];
        }
        if (!parse_value(help, o, value))
            return 2;
        o->seen = 1;
    }
    return 0;
}

int plm_read_numbers(FILE *in, const char *command, long *line_number, double *values, int n)
{
    char line[4096];
    while (fgets(line, sizeof line, in)) {
        ++*line_number;
        if (!strchr(line, '\n') && !feof(in)) {
            fprintf(stderr, "error: %s: stdin line %ld is too long\n", command, *line_number);
            return -1;
        }
        char *hash = strchr(line, '#');
        if (hash)
            *hash = '\0';
        char *p = line;
        while (*p == ' ' || *p == '\t' || *p == '\r' || *p == '\n')
            ++p;
        if (*p == '\0')
            continue;
        int got = 0;
        for (;;) {
            char *end;
            double v = strtod(p, &end);
            if (end == p)
                break;
            if (got < n)
                values[got] = v;
            if (!isfinite(v))
                got = n + 1; /* NaN and Inf are never valid directions */
            ++got;
            p = end;
        }
        while (*p == ' ' || *p == '\t' || *p == '\r' || *p == '\n')
            ++p;
        if (got != n || *p != '\0') {
            fprintf(stderr, "error: %s: stdin line %ld: expected exactly %d finite numbers (--help shows the format)\n", command,
                    *line_number, n);
            return -1;
        }
        return 1;
    }
    return 0;
}

static void print_table(FILE *out, const char *usage_line, const char *kind, const plm_subcommand *table)
{
    fprintf(out, "usage: %s\n\n%ss:\n", usage_line, kind);
    for (const plm_subcommand *c = table; c->name; ++c)
        fprintf(out, "  %-10s %s\n", c->name, c->summary);
    fprintf(out, "\nEach %s has its own --help.\n", kind);
}

int plm_dispatch(const char *usage_line, const char *kind, const plm_subcommand *table, int argc, char **argv)
{
    if (argc < 2) {
        print_table(stderr, usage_line, kind, table);
        return 2;
    }
    if (strcmp(argv[1], "--help") == 0 || strcmp(argv[1], "-h") == 0 || strcmp(argv[1], "help") == 0) {
        print_table(stdout, usage_line, kind, table);
        return 0;
    }
    for (const plm_subcommand *c = table; c->name; ++c)
        if (strcmp(argv[1], c->name) == 0)
            return c->run(argc - 1, argv + 1);
    fprintf(stderr, "error: unknown %s '%s'\n\n", kind, argv[1]);
    print_table(stderr, usage_line, kind, table);
    return 2;
}

/* "640x480" -> 640, 480 (each in [1, 16384]). */
int plm_parse_resolution(const char *s, int *w, int *h)
{
    char *end;
    long a = strtol(s, &end, 10);
    if (end == s || (*end != 'x' && *end != 'X'))
        return 0;
    const char *p = end + 1;
    long b = strtol(p, &end, 10);
    if (end == p || *end || a < 1 || a > 16384 || b < 1 || b > 16384)
        return 0;
    *w = (int)a;
    *h = (int)b;
    return 1;
}
