#include "optics/fiber_table_set.h"

#include <stdlib.h>
#include <string.h>

void plm_fiber_table_set_init(plm_fiber_table_set *s, const plm_fiber_table_options *o)
{
    memset(s, 0, sizeof *s);
    if (o)
        s->options = *o;
}

static plm_result grow(plm_fiber_table_set *s, plm_error *err)
{
    if (s->count < s->capacity)
        return PLM_OK;
    int capacity = s->capacity ? 2 * s->capacity : 8;
    void *words = realloc(s->words, sizeof *s->words * (size_t)capacity);
    if (words)
        s->words = words;
    void *tables = realloc(s->tables, sizeof *s->tables * (size_t)capacity);
    if (tables)
        s->tables = tables;
    if (!words || !tables)
        return plm_fail(err, PLM_ERR_NO_MEMORY, "fiber tables: out of memory");
    s->capacity = capacity;
    return PLM_OK;
}

plm_result plm_fiber_table_set_get(plm_fiber_table_set *s, const plm_fiber_params *p, const plm_fiber_table **out,
                                   plm_error *err)
{
    double w[PLM_FIBER_TABLE_PARAM_WORDS];
    plm_fiber_table_param_words(p, w);
    for (int i = 0; i < s->count; ++i)
        if (memcmp(s->words[i], w, sizeof w) == 0) {
            *out = s->tables[i];
            return PLM_OK;
        }
    plm_result rc = grow(s, err);
    plm_fiber_table *t = NULL;
    if (rc == PLM_OK)
        rc = plm_fiber_table_get(p, &s->options, &t, err);
    if (rc != PLM_OK)
        return rc;
    memcpy(s->words[s->count], w, sizeof w);
    s->tables[s->count++] = t;
    *out = t;
    return PLM_OK;
}

void plm_fiber_table_set_free(plm_fiber_table_set *s)
{
    for (int i = 0; i < s->count; ++i)
        plm_fiber_table_free(s->tables[i]);
    free(s->words);
    free(s->tables);
    memset(s, 0, sizeof *s);
}
