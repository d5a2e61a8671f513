/* Embree errors become plumage errors (render/embree.h): the device's error
 * callback records what Embree reports and the checks after each build step
 * return it; an allocation Embree cannot make is an out-of-memory result. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>

#include <string.h>

#include "render/embree.h"
#include "render/scene.h"
#include "render/world.h"

/* A triangle mesh scene of n x n quads on the device. */
static RTCScene grid_scene(RTCDevice device, int n)
{
    RTCScene scene = rtcNewScene(device);
    RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
    float *v = rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float),
                                       (size_t)(n + 1) * (n + 1));
    unsigned *t = rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned),
                                          2 * (size_t)n * n);
    if (v && t) {
        for (int j = 0; j <= n; ++j)
            for (int i = 0; i <= n; ++i) {
                float *p = v + 3 * (j * (n + 1) + i);
                p[0] = (float)i, p[1] = (float)j, p[2] = 0.0f;
            }
        for (int j = 0; j < n; ++j)
            for (int i = 0; i < n; ++i) {
                unsigned a = (unsigned)(j * (n + 1) + i), *q = t + 6 * (j * n + i);
                q[0] = a, q[1] = a + 1, q[2] = a + (unsigned)n + 2;
                q[3] = a, q[4] = a + (unsigned)n + 2, q[5] = a + (unsigned)n + 1;
            }
    }
    rtcCommitGeometry(g);
    rtcAttachGeometry(scene, g);
    rtcReleaseGeometry(g);
    rtcCommitScene(scene);
    return scene;
}

static void a_clean_build_checks_ok(void **state)
{
    (void)state;
    plm_embree e;
    plm_error err = {{0}};
    assert_int_equal(plm_embree_open(&e, 0, &err), PLM_OK);
    RTCScene s = grid_scene(e.device, 8);
    assert_int_equal(plm_embree_check(&e, "grid", &err), PLM_OK);
    rtcReleaseScene(s);
    plm_embree_close(&e);
}

/* A call Embree rejects is reported once, with Embree's message and what we were doing. */
static void an_embree_error_is_reported_once(void **state)
{
    (void)state;
    plm_embree e;
    plm_error err = {{0}};
    assert_int_equal(plm_embree_open(&e, 0, &err), PLM_OK);
    RTCGeometry g = rtcNewGeometry(e.device, (enum RTCGeometryType)9999);
    assert_null(g);
    assert_int_equal(plm_embree_check(&e, "a bad geometry", &err), PLM_ERR_INTERNAL);
    assert_non_null(strstr(err.message, "Embree, a bad geometry: "));
    assert_true(strlen(err.message) > strlen("Embree, a bad geometry: "));
    assert_int_equal(plm_embree_check(&e, "after", &err), PLM_OK);
    plm_embree_close(&e);
}

/* Embree allocating past the device's memory limit fails as a real
 * allocation failure would: an out-of-memory result, no crash. */
static void an_allocation_failure_is_out_of_memory(void **state)
{
    (void)state;
    plm_embree e;
    plm_error err = {{0}};
    assert_int_equal(plm_embree_open(&e, 64 * 1024, &err), PLM_OK);
    RTCScene s = grid_scene(e.device, 200); /* 80000 triangles: megabytes of BVH */
    assert_int_equal(plm_embree_check(&e, "a big grid", &err), PLM_ERR_NO_MEMORY);
    assert_non_null(strstr(err.message, "Embree, a big grid: out of memory"));
    rtcReleaseScene(s);
    plm_embree_close(&e);
    /* Without the limit the same build succeeds. */
    assert_int_equal(plm_embree_open(&e, 0, &err), PLM_OK);
    s = grid_scene(e.device, 200);
    assert_int_equal(plm_embree_check(&e, "a big grid", &err), PLM_OK);
    rtcReleaseScene(s);
    plm_embree_close(&e);
}

/* The world builds through the same device and checks. */
static void a_world_builds_and_checks(void **state)
{
    (void)state;
    plm_scene scene;
    plm_scene_init(&scene);
    plm_error err = {{0}};
    plm_mesh quad;
    assert_int_equal(plm_shape_quad(1.0, 1.0, 0.0, 4, &quad, &err), PLM_OK);
    plm_material m;
    memset(&m, 0, sizeof m);
    m.reflectance = rgb_gray(0.5);
    plm_instance in = {.mesh = plm_scene_add_mesh(&scene, "q", &quad), .material = plm_scene_add_material(&scene, &m),
                       .xform = plm_xform_identity(), .tint = rgb_gray(1.0)};
    assert_true(plm_scene_add_instance(&scene, &in) >= 0);
    plm_world w;
    assert_int_equal(plm_world_build(&scene, &w, &err), PLM_OK);
    assert_non_null(w.embree.device);
    plm_world_free(&w);
    plm_scene_free(&scene);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(a_clean_build_checks_ok),
        cmocka_unit_test(an_embree_error_is_reported_once),
        cmocka_unit_test(an_allocation_failure_is_out_of_memory),
        cmocka_unit_test(a_world_builds_and_checks),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
