/* Validating JSON reads on top of cJSON.
 *
 * A plm_json_reader remembers which file it reads so every error names the
 * file and the field path ("scene.json: camera.fov: 200 is out of range
 * (0, 180)"). Readers are zero-initialisable apart from file and err.
 * Unknown fields are errors: callers list the keys an object may have. */
#ifndef PLUMAGE_COMMON_JSON_H
#define PLUMAGE_COMMON_JSON_H

#include <stddef.h>

#include <cjson/cJSON.h>
#include "common/error.h"
#include "common/vec.h"

typedef struct plm_json_reader {
    const char *file; /* shown in messages */
    plm_error *err;   /* may be NULL */
    int record_paths; /* scene files: write each resolved path back into the tree, absolute
                         (the resolved scene of scene/scene_file.h) */
} plm_json_reader;

/* Parses a file; on a syntax error the message gives the line and column.
 * *out is NULL after any failure, so callers may always cJSON_Delete it. */
plm_result plm_json_load(const char *path, cJSON **out, plm_error *err);
/* The same for text in memory (not necessarily NUL-terminated); name is shown in messages. */
plm_result plm_json_parse(const char *text, size_t length, const char *name, cJSON **out, plm_error *err);

/* Fails if obj (at path) is not an object or has a key outside allowed
 * (a NULL-terminated list). */
plm_result plm_json_check_object(const plm_json_reader *r, const cJSON *obj, const char *path,
                                 const char *const *allowed);

/* Typed optional fields: absent -> *out = def. Present with the wrong type or
 * outside [lo, hi] -> error naming path.key and the range. */
plm_result plm_json_number(const plm_json_reader *r, const cJSON *obj, const char *path, const char *key,
                           double def, double lo, double hi, double *out);
plm_result plm_json_int(const plm_json_reader *r, const cJSON *obj, const char *path, const char *key,
                        int def, int lo, int hi, int *out);
plm_result plm_json_bool(const plm_json_reader *r, const cJSON *obj, const char *path, const char *key,
                         int def, int *out);
/* *out points into obj (valid while obj lives); absent -> def (may be NULL). */
plm_result plm_json_string(const plm_json_reader *r, const cJSON *obj, const char *path, const char *key,
                           const char *def, const char **out);
/* One of the listed choices (NULL-terminated); *out is its index. */
plm_result plm_json_enum(const plm_json_reader *r, const cJSON *obj, const char *path, const char *key,
                         const char *const *choices, int def, int *out);
/* An array of 3 numbers, each in [lo, hi]. */
plm_result plm_json_vec3(const plm_json_reader *r, const cJSON *obj, const char *path, const char *key,
                         vec3 def, double lo, double hi, vec3 *out);
plm_result plm_json_rgb(const plm_json_reader *r, const cJSON *obj, const char *path, const char *key,
                        rgb def, double lo, double hi, rgb *out);

/* Error helper for custom checks: "file: path.key: message". */
plm_result plm_json_fail(const plm_json_reader *r, const char *path, const char *key, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 4, 5)))
#endif
    ;

#endif
