/* Command-line options for every plumage subcommand, table-driven so each
 * command gets the same --help, the same errors for unknown options and
 * out-of-range values, and no parsing code of its own. */
#ifndef PLUMAGE_CLI_OPTIONS_H
#define PLUMAGE_CLI_OPTIONS_H

#include <stdio.h>

#include "common/params.h"

typedef enum plm_opt_kind {
    PLM_OPT_FLAG,    /* int: set to 1 when present */
    PLM_OPT_INT,     /* int in [lo, hi] */
    PLM_OPT_DOUBLE,  /* double in [lo, hi] */
    PLM_OPT_DOUBLES, /* `count` comma-separated doubles, each in [lo, hi] ("0.1,0.2,0.3") */
    PLM_OPT_STRING,  /* const char* pointing into argv */
    PLM_OPT_CHOICE,  /* int index into `choices` (NULL-terminated) */
    PLM_OPT_LIST     /* plm_opt_list: a string option that may be repeated */
} plm_opt_kind;

#define PLM_OPT_LIST_MAX 256

typedef struct plm_opt_list {
    const char *items[PLM_OPT_LIST_MAX]; /* pointing into argv, in command-line order */
    int count;
} plm_opt_list;

typedef struct plm_option {
    const char *name;  /* "--eccentricity" */
    plm_opt_kind kind;
    void *target;      /* int*, double* (array for DOUBLES), const char**, int*, plm_opt_list* */
    int count;         /* DOUBLES only */
    double lo, hi;     /* allowed closed range for numbers */
    const char *const *choices; /* CHOICE only */
    const char *metavar;        /* "E", "R,G,B" */
    const char *help;           /* one line, including the default */
    int seen;                   /* set by the parser */
} plm_option;

typedef struct plm_command_help {
    const char *usage;   /* "plumage probe fiber [options] < directions" */
    const char *summary; /* a paragraph printed above the options */
} plm_command_help;

/* Parses argv[first..argc). Positional arguments (not starting with "--")
 * are collected into positional[] up to max_positional. Returns 0 on
 * success, 1 if --help was printed (caller exits 0), 2 on error (message on
 * stderr naming the option and its allowed range). */
int plm_parse_options(const plm_command_help *help, int argc, char **argv, int first, plm_option *opts,
                      int n_opts, const char **positional, int max_positional, int *n_positional);

/* Takes o's range from the field of a parameter table (common/params.h), so
 * an option accepts what the scene and species files accept. Aborts if the
 * table has no such field (a programming error). */
void plm_option_range_from(plm_option *o, const plm_param_block *b, const char *field);
/* The name and help text an option built from a table holds. */
typedef struct plm_option_text {
    char name[48], help[320];
} plm_option_text;
/* Makes *o the option of a parameter table's field: its name ("--beta-m" for
 * beta_m), kind, range, meaning and unit are the table's, as scene and species
 * files have them, and its help ends with the default, the value target
 * holds now (angles in degrees, as on the command line). The text goes into
 * *text, which must outlive o. Open bounds: plm_option_check_open. */
void plm_option_param(plm_option *o, plm_option_text *text, const plm_param_block *b, const char *field, void *target,
                      const char *metavar);
/* After parsing: a PLM_OPT_DOUBLE's value on a bound the table leaves open
 * is refused as the parser refuses the others, naming the option and the
 * range ("(0, 20]"). Returns 0 (message on stderr) if so, else 1. */
int plm_option_check_open(const plm_option *o, const plm_param_block *b, const char *field);

/* "640x480" -> 640, 480; returns 0 unless both are whole numbers in [1, 16384]. */
int plm_parse_resolution(const char *s, int *w, int *h);

void plm_print_help(FILE *out, const plm_command_help *help, const plm_option *opts, int n_opts);

/* Reads the next non-empty line of stdin (stripping '#' comments) and parses
 * exactly n whitespace-separated numbers. Returns 1 on success, 0 at end of
 * input, -1 on a malformed line (message on stderr with the line number). */
int plm_read_numbers(FILE *in, const char *command, long *line_number, double *values, int n);

/* A table of subcommands (NULL-terminated) and the one dispatcher that
 * serves `plumage`, `plumage probe` and `plumage bench`: usage on no
 * argument (exit 2) or --help (exit 0), an error naming an unknown entry. */
typedef struct plm_subcommand {
    const char *name;
    int (*run)(int argc, char **argv);
    const char *summary;
} plm_subcommand;

int plm_dispatch(const char *usage_line, const char *kind, const plm_subcommand *table, int argc, char **argv);

#endif
