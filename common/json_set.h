/* Assignments to a parsed JSON document by dotted path, for overrides given
 * on the command line (`plumage render --set camera.fov=30`) or in a batch
 * manifest. docs/batch.md describes the syntax.
 *
 *   "camera.fov=30"                      a number
 *   "lights.1.radiance=[2, 2, 2]"        an array element by index, an array value
 *   "feathers.f.species=other.json"      not valid JSON, so taken as a string
 *
 * Every segment but the last must exist (a typo fails instead of adding a
 * field nobody reads); the last may add a field to an existing object. */
#ifndef PLUMAGE_COMMON_JSON_SET_H
#define PLUMAGE_COMMON_JSON_SET_H

#include <cjson/cJSON.h>
#include "common/error.h"

/* Sets root's field at the dotted path to a copy of value. Errors name the
 * path and the segment that is missing or of the wrong type. */
plm_result plm_json_set(cJSON *root, const char *path, const cJSON *value, plm_error *err);

/* "path=value": value is parsed as JSON, and taken as a string if it is not JSON. */
plm_result plm_json_set_assignment(cJSON *root, const char *assignment, plm_error *err);

#endif
