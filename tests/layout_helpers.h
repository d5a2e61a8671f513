/* Helpers shared by the layout tests: the prototypes' feathers, instance
 * matrices applied, layouts compared. Include after <cmocka.h>. */
#ifndef PLUMAGE_TESTS_LAYOUT_HELPERS_H
#define PLUMAGE_TESTS_LAYOUT_HELPERS_H

#include <stdlib.h>

#include "generate/layout.h"
#include "texture/feather.h"

/* The prototypes' meshes at the renderer's default level. */
static inline plm_feather *generate_prototypes(const plm_layout *l, const plm_species *const *species)
{
    plm_feather *f = calloc((size_t)l->prototype_count, sizeof *f);
    for (int i = 0; i < l->prototype_count; ++i) {
        plm_species sp = *species[l->prototypes[i].species];
        sp.shape = l->prototypes[i].shape;
        sp.pigment = l->prototypes[i].pigment;
        plm_feather_options opt = {.no_textures = 1};
        assert_int_equal(plm_feather_generate(&sp, &opt, &f[i], NULL), PLM_OK);
    }
    return f;
}

static inline void free_prototypes(plm_feather *f, int n)
{
    for (int i = 0; i < n; ++i)
        plm_feather_free(&f[i]);
    free(f);
}

static inline vec3 xf(const plm_layout_instance *in, vec3 p)
{
    return v3(in->m[0][0] * p.x + in->m[0][1] * p.y + in->m[0][2] * p.z + in->m[0][3],
              in->m[1][0] * p.x + in->m[1][1] * p.y + in->m[1][2] * p.z + in->m[1][3],
              in->m[2][0] * p.x + in->m[2][1] * p.y + in->m[2][2] * p.z + in->m[2][3]);
}

static inline vec3 column(const plm_layout_instance *in, int c) { return v3(in->m[0][c], in->m[1][c], in->m[2][c]); }

static inline void assert_same_layout(const plm_layout *a, const plm_layout *b)
{
    assert_int_equal(a->instance_count, b->instance_count);
    assert_int_equal(a->prototype_count, b->prototype_count);
    assert_memory_equal(a->instances, b->instances, sizeof *a->instances * (size_t)a->instance_count);
    assert_memory_equal(a->prototypes, b->prototypes, sizeof *a->prototypes * (size_t)a->prototype_count);
}

#endif
