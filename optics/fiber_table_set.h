/* Fiber tables shared by every fiber with the same parameters. A scene's
 * species often repeat a fiber (a species' variants, colour patches that
 * differ only in their textures), and each table takes 32 MiB by default:
 * whoever renders or bakes keeps one set and gets its tables from it. */
#ifndef PLUMAGE_OPTICS_FIBER_TABLE_SET_H
#define PLUMAGE_OPTICS_FIBER_TABLE_SET_H

#include "optics/fiber_table.h"

typedef struct plm_fiber_table_set {
    plm_fiber_table_options options; /* the same for every table of the set */
    int count, capacity;
    double (*words)[PLM_FIBER_TABLE_PARAM_WORDS]; /* each table's parameters (plm_fiber_table_param_words) */
    plm_fiber_table **tables;                     /* owned */
} plm_fiber_table_set;

/* An empty set whose tables are built or read with options o (NULL: defaults). */
void plm_fiber_table_set_init(plm_fiber_table_set *s, const plm_fiber_table_options *o);
/* The set's table for p, loaded or built on first use; it lives as long as the set. */
plm_result plm_fiber_table_set_get(plm_fiber_table_set *s, const plm_fiber_params *p, const plm_fiber_table **out,
                                   plm_error *err);
void plm_fiber_table_set_free(plm_fiber_table_set *s);

#endif
