/* Result codes and error messages shared by every plumage library.
 *
 * Functions that can fail return a plm_result and, when given a non-NULL
 * plm_error, leave a one-line human-readable message in it. Messages name the
 * offending file, field or option and the allowed range, so callers can print
 * them as they are. */
#ifndef PLUMAGE_COMMON_ERROR_H
#define PLUMAGE_COMMON_ERROR_H

typedef enum plm_result {
    PLM_OK = 0,
    PLM_ERR_INVALID = 1,     /* a parameter or input value is out of range or malformed */
    PLM_ERR_IO = 2,          /* a file could not be read or written */
    PLM_ERR_PARSE = 3,       /* a file's contents could not be parsed */
    PLM_ERR_NO_MEMORY = 4,
    PLM_ERR_INTERRUPTED = 5, /* the user asked to stop (Ctrl-C) */
    PLM_ERR_INTERNAL = 6     /* a library we call failed in a way we did not expect */
} plm_result;

typedef struct plm_error {
    char message[1024];
} plm_error;

/* Formats the message into err (if not NULL) and returns code, so that a
 * failure reads `return plm_fail(err, PLM_ERR_INVALID, "...", ...);`. */
plm_result plm_fail(plm_error *err, plm_result code, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 3, 4)))
#endif
    ;

/* Prefixes an existing message, e.g. with the file it came from. */
void plm_error_prefix(plm_error *err, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;

const char *plm_result_name(plm_result code);

#endif
