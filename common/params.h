/* Parameter tables: one table per parameter block (a JSON object read into a
 * struct) gives each field's name, type, range, unit and meaning, and the
 * struct member it fills. Validation, file reading, `plumage params` (the
 * help) and docs/scene-format.md all read the table, so a range is written
 * once. Defaults are not in the table: they are whatever the block's default
 * function puts in the struct, printed from such a struct.
 *
 * Angles are degrees in files, help and messages, radians in the struct. */
#ifndef PLUMAGE_COMMON_PARAMS_H
#define PLUMAGE_COMMON_PARAMS_H

#include <stddef.h>
#include <stdio.h>

#include "common/error.h"
#include "common/json.h"

typedef enum plm_param_type {
    PLM_PARAM_NUMBER, /* double */
    PLM_PARAM_ANGLE,  /* double, radians in the struct, degrees outside */
    PLM_PARAM_INT,    /* int */
    PLM_PARAM_BOOL,   /* int, 0 or 1; min and max unused */
    PLM_PARAM_SEED,   /* uint64_t, written as a whole number in [min, max] */
    PLM_PARAM_VEC3,   /* vec3, each component in [min, max] */
    PLM_PARAM_RGB,    /* rgb, each channel in [min, max] */
    PLM_PARAM_PAIR    /* two consecutive doubles, each in [min, max] */
} plm_param_type;

typedef struct plm_param {
    const char *name; /* the JSON key */
    plm_param_type type;
    size_t offset;    /* of the struct member (offsetof) */
    double min, max;  /* inclusive unless `open` says otherwise; degrees for angles */
    const char *unit; /* "" when dimensionless */
    const char *meaning;
    int open;         /* PLM_PARAM_OPEN_MIN and/or PLM_PARAM_OPEN_MAX: that bound is excluded */
} plm_param;

#define PLM_PARAM_OPEN_MIN 1
#define PLM_PARAM_OPEN_MAX 2

/* A table's row count from the table itself, so a new row is never left out. */
#define PLM_PARAM_COUNT(rows) ((int)(sizeof rows / sizeof rows[0]))

typedef struct plm_param_block {
    const char *name;    /* as in messages and help: "camera", "fiber", ... */
    const char *meaning; /* one line */
    const plm_param *params;
    int count;
} plm_param_block;

/* Checks every field of target against its range; the message names the
 * block, the field, its value and the range. */
plm_result plm_params_check(const plm_param_block *b, const void *target, plm_error *err);

/* Reads the fields present in obj into target (absent fields keep their
 * values). Unknown keys are errors unless listed in `extra` (NULL-terminated,
 * keys the caller reads itself; may be NULL). Errors name r's file, path.key
 * and the range. */
plm_result plm_params_read(const plm_json_reader *r, const cJSON *obj, const char *path, const plm_param_block *b,
                           const char *const *extra, void *target);

/* The table as text (markdown = 0) or as a markdown table, with one default
 * column per struct in `defaults` (labelled by `labels`; n_defaults >= 0). */
void plm_params_print(FILE *fp, const plm_param_block *b, int n_defaults, const char *const *labels,
                      const void *const *defaults, int markdown);

#endif
