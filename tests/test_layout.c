/* Layouts (generate/layout.h): counts, roots on the surface, nothing below
 * it (checked with the prototypes' full-resolution meshes), coverage of the
 * surface, shingling, reproducibility. The wing is test_layout_wing.c. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>
#include "assert_double.h"
#include "layout_helpers.h"
#include "test_files.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "generate/geometry.h"
#include "generate/layout.h"
#include "generate/outline.h"
#include "texture/feather.h"

/* Lowest height of any vertex of an instance's meshes, by a height function. */
typedef double (*height_fn)(vec3 p, const void *ctx);

static double lowest_point(const plm_layout_instance *in, const plm_feather *f, height_fn h, const void *ctx)
{
    double lowest = INFINITY;
    const plm_mesh *m[2] = {&f->vane, &f->rachis};
    for (int k = 0; k < 2; ++k)
        for (int i = 0; i < m[k]->vertex_count; ++i) {
            const float *p = m[k]->positions + 3 * i;
            lowest = fmin(lowest, h(xf(in, v3(p[0], p[1], p[2])), ctx));
        }
    return lowest;
}

static double plane_height(vec3 p, const void *ctx) { (void)ctx; return p.z; }
static double sphere_height(vec3 p, const void *ctx) { return v3_length(p) - *(const double *)ctx; }

/* ---- Pelt on a plane ---- */

static plm_layout plane_pelt(const plm_species *sp, int count, uint64_t seed)
{
    plm_layout_species list[1] = {{sp, 1.0}};
    plm_pelt_params p = {0};
    p.surface.kind = PLM_SURFACE_PLANE;
    p.surface.width = 0.4;
    p.surface.height = 0.3;
    p.count = count;
    p.seed = seed;
    plm_layout l;
    plm_error err = {{0}};
    plm_result rc = plm_layout_pelt(&p, list, 1, &l, &err);
    if (rc != PLM_OK)
        fprintf(stderr, "%s\n", err.message);
    assert_int_equal(rc, PLM_OK);
    return l;
}

/* The flat feather point (x, y) of an instance whose projection onto z = 0 is q (x, y only). */
static int flat_under(const plm_layout_instance *in, vec3 q, double *x, double *y)
{
    double a = in->m[0][0], b = in->m[0][1], c = in->m[1][0], d = in->m[1][1];
    double det = a * d - b * c;
    if (fabs(det) < 1e-300)
        return 0;
    double rx = q.x - in->m[0][3], ry = q.y - in->m[1][3];
    *x = (d * rx - b * ry) / det;
    *y = (-c * rx + a * ry) / det;
    return 1;
}

/* 1 if the instance's vane (its outline's vane region, down strands included) lies over
 * q (x, y) above the height q.z: the flat point found through the projection
 * of the flat feather, its height on the bent and cupped vane. */
static int vane_over(const plm_layout_instance *in, const plm_outline *o, vec3 q)
{
    double x, y;
    if (!flat_under(in, q, &x, &y) || y < 0.0 || y > o->shape.length)
        return 0;
    return plm_outline_sample(o, x, y).region == PLM_FLAT_VANE && xf(in, plm_vane_point(o, x, y)).z > q.z;
}

static plm_outline *outlines_of(const plm_layout *l)
{
    plm_outline *o = calloc((size_t)l->prototype_count, sizeof *o);
    for (int i = 0; i < l->prototype_count; ++i)
        assert_int_equal(plm_outline_init(&o[i], &l->prototypes[i].shape, NULL, NULL), PLM_OK);
    return o;
}

static void pelt_counts_roots_and_surface(void **state)
{
    (void)state;
    plm_species sp = load_preset("covert_parrot");
    plm_layout l = plane_pelt(&sp, 300, 11);
    assert_int_equal(l.instance_count, 300);
    assert_int_equal(l.prototype_count, 4);
    const plm_species *list[1] = {&sp};
    plm_feather *f = generate_prototypes(&l, list);
    int used[4] = {0};
    for (int i = 0; i < l.instance_count; ++i) {
        const plm_layout_instance *in = &l.instances[i];
        assert_true(in->prototype >= 0 && in->prototype < 4);
        used[in->prototype]++;
        /* The calamus base on the surface, lifted by the rachis radius and, where it settles on a
         * neighbour's vane, by less than a tenth of its length (measured: up to 5.3%). */
        double s = v3_length(column(in, 0));
        double r = 0.5 * l.prototypes[in->prototype].shape.rachis_base_width * s;
        assert_true(in->m[2][3] >= r - 1e-9 && in->m[2][3] <= r + 0.1 * s * l.prototypes[in->prototype].shape.length);
        assert_true(fabs(in->m[0][3]) <= 0.2 && fabs(in->m[1][3]) <= 0.15);
        /* Nothing of the full-resolution meshes below the plane. */
        assert_true(lowest_point(in, &f[in->prototype], plane_height, NULL) >= 0.0);
        /* Variation within its bounds (sizes down to 0.6 x 0.6 toward the head and the edges); tints in (0, 1]. */
        assert_true(in->scale >= 0.36 * 0.85 - 1e-12 && in->scale <= 1.15 + 1e-12);
        assert_true(in->tint.r > 0.0 && in->tint.r <= 1.0 && in->tint.g > 0.0 && in->tint.b <= 1.0);
        /* Orthogonal frames: a rotation times the scale, the dorsal axis pressed flatter by at most 10x. */
        assert_double_near(v3_dot(column(in, 0), column(in, 1)), 0.0, 1e-12);
        assert_double_near(v3_dot(column(in, 1), column(in, 2)), 0.0, 1e-12);
        assert_true(v3_length(column(in, 2)) >= 0.1 * s - 1e-12 && v3_length(column(in, 2)) <= s + 1e-12);
    }
    for (int k = 0; k < 4; ++k)
        assert_true(used[k] > 30);
    free_prototypes(f, l.prototype_count);
    plm_layout_free(&l);
    plm_species_free(&sp);
}

/* Coverage of the inner part of the plane by vanes (down strands included), and shingling:
 * the part of each feather's rachis lying under other feathers' vanes. */
static void pelt_covers_and_shingles(void **state)
{
    (void)state;
    plm_species sp = load_preset("covert_parrot");
    plm_layout l = plane_pelt(&sp, 600, 5);
    plm_outline *o = outlines_of(&l);
    int covered = 0, total = 0;
    for (int i = 0; i < 40; ++i)
        for (int j = 0; j < 30; ++j) {
            /* Away from the edges, which feathers reach from one side only. */
            vec3 q = v3(-0.15 + 0.3 * (i + 0.5) / 40, -0.1 + 0.2 * (j + 0.5) / 30, 0.0);
            int hit = 0;
            for (int k = 0; k < l.instance_count && !hit; ++k)
                hit = vane_over(&l.instances[k], &o[l.instances[k].prototype], q);
            covered += hit;
            total++;
        }
    double coverage = (double)covered / total;
    printf("pelt coverage by vanes (down strands included): %.3f\n", coverage);
    assert_true(coverage >= 0.97);
    /* Shingling: along each feather's rachis (inner feathers), how often a
     * point lies under another feather's vane. The default overlap is 2/3:
     * the base two thirds should be hidden, the tip third show. */
    enum { STEPS = 30 };
    int under[STEPS] = {0}, feathers = 0;
    for (int k = 0; k < l.instance_count; ++k) {
        const plm_layout_instance *in = &l.instances[k];
        if (fabs(in->m[0][3]) > 0.12 || fabs(in->m[1][3]) > 0.08)
            continue;
        const plm_shape *sh = &l.prototypes[in->prototype].shape;
        for (int s = 0; s < STEPS; ++s) {
            vec3 q = xf(in, plm_rachis_frame_at(&o[in->prototype], sh->length * (s + 0.5) / STEPS).c);
            int hit = 0;
            for (int m = 0; m < l.instance_count && !hit; ++m)
                hit = m != k && vane_over(&l.instances[m], &o[l.instances[m].prototype], q);
            under[s] += hit;
        }
        feathers++;
    }
    /* Where the rachis comes out from under: the first position covered less than half the time. */
    int s50 = 0;
    while (s50 < STEPS && 2 * under[s50] > feathers)
        ++s50;
    double half = (double)s50 / STEPS, base = 0.0;
    for (int s = 0; s < STEPS / 2; ++s)
        base += (double)under[s] / feathers / (STEPS / 2);
    printf("rachis covered in its base half %.3f of the time; it comes out at %.2f of its length (%d feathers)\n",
           base, half, feathers);
    assert_true(base > 0.9);
    /* Settled feathers lie flat on those beneath, so the feathers beside them cover a little more than the
     * feathers behind alone (0.67): out at 0.62-0.85 of the length. */
    assert_true(half > 0.62 && half < 0.85);
    assert_true((double)under[STEPS - 1] / feathers < 0.1);
    free(o);
    plm_layout_free(&l);
    plm_species_free(&sp);
}

static void pelt_same_seed_same_instances(void **state)
{
    (void)state;
    plm_species sp = load_preset("covert_parrot");
    plm_layout a = plane_pelt(&sp, 200, 3), b = plane_pelt(&sp, 200, 3), c = plane_pelt(&sp, 200, 4);
    assert_same_layout(&a, &b);
    assert_true(memcmp(a.instances, c.instances, sizeof *a.instances * 200) != 0);
    /* Variants differ from one another and from the species. */
    assert_memory_equal(&a.prototypes[0].shape, &sp.shape, sizeof sp.shape);
    assert_true(memcmp(&a.prototypes[1].shape, &a.prototypes[2].shape, sizeof sp.shape) != 0);
    plm_layout_free(&a);
    plm_layout_free(&b);
    plm_layout_free(&c);
    plm_species_free(&sp);
}

/* ---- Sphere pelt, mesh pelt and ball ---- */

static void sphere_pelt_and_ball(void **state)
{
    (void)state;
    plm_species sp = load_preset("covert_parrot");
    plm_layout_species list[1] = {{&sp, 1.0}};
    const plm_species *plist[1] = {&sp};
    double radius = 0.5;
    plm_pelt_params p = {0};
    p.surface.kind = PLM_SURFACE_SPHERE;
    p.surface.radius = radius;
    p.count = 400;
    plm_layout l;
    assert_int_equal(plm_layout_pelt(&p, list, 1, &l, NULL), PLM_OK);
    assert_int_equal(l.instance_count, 400);
    plm_feather *f = generate_prototypes(&l, plist);
    for (int i = 0; i < l.instance_count; ++i) {
        const plm_layout_instance *in = &l.instances[i];
        double s = v3_length(column(in, 0)), r = 0.5 * l.prototypes[in->prototype].shape.rachis_base_width * s;
        double lifted = v3_length(v3(in->m[0][3], in->m[1][3], in->m[2][3])) - radius - r;
        assert_double_near(lifted, 0.0, 1e-9); /* curved surfaces: not settled (docs/layouts.md) */
        assert_true(lowest_point(in, &f[in->prototype], sphere_height, &radius) >= 0.0);
    }
    free_prototypes(f, l.prototype_count);
    plm_layout_free(&l);

    plm_ball_params b = {0};
    b.radius = radius;
    assert_int_equal(plm_layout_ball(&b, list, 1, &l, NULL), PLM_OK);
    assert_int_equal(l.instance_count, 496);
    f = generate_prototypes(&l, plist);
    for (int i = 0; i < l.instance_count; ++i) {
        const plm_layout_instance *in = &l.instances[i];
        vec3 root = v3(in->m[0][3], in->m[1][3], in->m[2][3]);
        vec3 t = v3_normalize(column(in, 1));
        /* Radiating: within the spread (10 degrees) of the radial direction. */
        assert_true(v3_dot(t, v3_normalize(root)) >= cos(plm_radians(10.0)) - 1e-9);
        assert_true(lowest_point(in, &f[in->prototype], sphere_height, &radius) >= 0.0);
    }
    free_prototypes(f, l.prototype_count);
    plm_layout_free(&l);
    plm_species_free(&sp);
}

/* A UV sphere of radius 1 with vertex normals: `rings` rings of 2 rings quads. */
static plm_mesh unit_sphere(int rings)
{
    int seg = 2 * rings, nv = (rings + 1) * (seg + 1);
    plm_mesh m = {0};
    m.vertex_count = nv;
    m.triangle_count = 2 * rings * seg;
    m.positions = malloc(sizeof(float) * 3 * (size_t)nv);
    m.normals = malloc(sizeof(float) * 3 * (size_t)nv);
    m.indices = malloc(sizeof(uint32_t) * 3 * (size_t)m.triangle_count);
    for (int i = 0; i <= rings; ++i)
        for (int j = 0; j <= seg; ++j) {
            double th = PLM_PI * i / rings, ph = PLM_TWO_PI * j / seg;
            float *p = m.positions + 3 * (i * (seg + 1) + j), *n = m.normals + 3 * (i * (seg + 1) + j);
            p[0] = n[0] = (float)(sin(th) * cos(ph));
            p[1] = n[1] = (float)(sin(th) * sin(ph));
            p[2] = n[2] = (float)cos(th);
        }
    uint32_t *t = m.indices;
    for (int i = 0; i < rings; ++i)
        for (int j = 0; j < seg; ++j) {
            uint32_t a = (uint32_t)(i * (seg + 1) + j), b = a + 1, c = a + (uint32_t)seg + 1, d = c + 1;
            /* Counter-clockwise seen from outside. */
            uint32_t tri[6] = {a, c, b, b, c, d};
            memcpy(t, tri, sizeof tri);
            t += 6;
        }
    return m;
}

static void mesh_pelt_follows_the_mesh(void **state)
{
    (void)state;
    plm_species sp = load_preset("covert_parrot");
    plm_layout_species list[1] = {{&sp, 1.0}};
    plm_mesh sphere = unit_sphere(64);
    plm_pelt_params p = {0};
    p.surface.kind = PLM_SURFACE_MESH;
    p.surface.mesh = &sphere;
    p.density = 40.0; /* about 500 over the sphere's 4 pi */
    plm_layout l;
    assert_int_equal(plm_layout_pelt(&p, list, 1, &l, NULL), PLM_OK);
    assert_true(l.instance_count > 480 && l.instance_count < 510);
    for (int i = 0; i < l.instance_count; ++i) {
        const plm_layout_instance *in = &l.instances[i];
        vec3 root = v3(in->m[0][3], in->m[1][3], in->m[2][3]);
        double s = v3_length(column(in, 0)), r = 0.5 * sp.shape.rachis_base_width * 1.1 * s;
        /* On the faceted sphere: between the inscribed facets and the sphere, plus the lift. */
        assert_true(v3_length(root) >= 0.998 && v3_length(root) <= 1.0 + r);
        /* Feathers lie along the surface: the dorsal axis near the normal. */
        assert_true(v3_dot(v3_normalize(column(in, 2)), v3_normalize(root)) > cos(plm_radians(60.0)));
    }
    plm_layout_free(&l);
    /* A mesh with no triangles is refused. */
    plm_mesh empty = {0};
    p.surface.mesh = &empty;
    plm_error err = {{0}};
    assert_int_equal(plm_layout_pelt(&p, list, 1, &l, &err), PLM_ERR_INVALID);
    assert_non_null(strstr(err.message, "mesh"));
    plm_mesh_free(&sphere);
    plm_species_free(&sp);
}

/* A mesh's per-vertex density: the upper half of a unit sphere 4 times as
 * dense as the lower takes 4 times the feathers (3 to 5 allowed) at half
 * the size (mean scale ratio 0.4 to 0.6), away from the equator's blend. */
static void mesh_density_sets_spacing(void **state)
{
    (void)state;
    plm_species sp = load_preset("covert_parrot");
    plm_layout_species list[1] = {{&sp, 1.0}};
    plm_mesh sphere = unit_sphere(64);
    sphere.density = malloc(sizeof(float) * (size_t)sphere.vertex_count);
    for (int i = 0; i < sphere.vertex_count; ++i)
        sphere.density[i] = sphere.positions[3 * i + 2] > 0.0f ? 4.0f : 1.0f;
    plm_pelt_params p = {0};
    p.surface.kind = PLM_SURFACE_MESH;
    p.surface.mesh = &sphere;
    p.count = 1000;
    plm_layout l;
    assert_int_equal(plm_layout_pelt(&p, list, 1, &l, NULL), PLM_OK);
    int n[2] = {0, 0};
    double scale[2] = {0.0, 0.0};
    for (int i = 0; i < l.instance_count; ++i) {
        double z = l.instances[i].m[2][3];
        if (fabs(z) < 0.1)
            continue;
        n[z > 0.0]++;
        scale[z > 0.0] += l.instances[i].scale;
    }
    double ratio = (double)n[1] / n[0], size = (scale[1] / n[1]) / (scale[0] / n[0]);
    printf("upper / lower half: %.2f times the feathers, %.2f the size\n", ratio, size);
    assert_true(ratio >= 3.0 && ratio <= 5.0);
    assert_true(size >= 0.4 && size <= 0.6);
    plm_layout_free(&l);
    /* Densities must be positive and span at most a factor of 100. */
    plm_error err = {{0}};
    sphere.density[5] = 0.0f;
    assert_int_equal(plm_layout_pelt(&p, list, 1, &l, &err), PLM_ERR_INVALID);
    assert_non_null(strstr(err.message, "density at vertex 5"));
    sphere.density[5] = 1000.0f;
    assert_int_equal(plm_layout_pelt(&p, list, 1, &l, &err), PLM_ERR_INVALID);
    assert_non_null(strstr(err.message, "factor of 100"));
    plm_mesh_free(&sphere);
    plm_species_free(&sp);
}

static void bad_parameters_are_named(void **state)
{
    (void)state;
    plm_species sp = load_preset("covert_parrot");
    plm_layout_species list[1] = {{&sp, 1.0}};
    plm_pelt_params p = {0};
    plm_layout l;
    plm_error err = {{0}};
    p.overlap = 0.99;
    assert_int_equal(plm_layout_pelt(&p, list, 1, &l, &err), PLM_ERR_INVALID);
    assert_non_null(strstr(err.message, "overlap"));
    p.overlap = 0.0;
    p.density = 1e9;
    assert_int_equal(plm_layout_pelt(&p, list, 1, &l, &err), PLM_ERR_INVALID);
    assert_non_null(strstr(err.message, "feathers"));
    plm_ball_params b = {0};
    b.spread = plm_radians(95.0);
    assert_int_equal(plm_layout_ball(&b, list, 1, &l, &err), PLM_ERR_INVALID);
    assert_non_null(strstr(err.message, "spread"));
    plm_species_free(&sp);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(pelt_counts_roots_and_surface),
        cmocka_unit_test(pelt_covers_and_shingles),
        cmocka_unit_test(pelt_same_seed_same_instances),
        cmocka_unit_test(sphere_pelt_and_ball),
        cmocka_unit_test(mesh_pelt_follows_the_mesh),
        cmocka_unit_test(mesh_density_sets_spacing),
        cmocka_unit_test(bad_parameters_are_named),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
