/* Mesh files through OpenMesh (common/mesh_io.cpp): PLY and OBJ round trips,
 * atomic writes, and clear errors for bad paths and bad meshes. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>
#include "assert_double.h"
#include "test_files.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "common/mesh.h"

/* A 3x2 grid of quads (12 triangles) with distinct, non-round attribute
 * values so a swapped or truncated channel shows. */
static plm_mesh make_grid(int with_tangents)
{
    enum { NX = 4, NY = 3 };
    plm_mesh m = {0};
    m.vertex_count = NX * NY;
    m.triangle_count = 2 * (NX - 1) * (NY - 1);
    m.positions = malloc(3 * sizeof(float) * NX * NY);
    m.normals = malloc(3 * sizeof(float) * NX * NY);
    m.uvs = malloc(2 * sizeof(float) * NX * NY);
    m.tangents = with_tangents ? malloc(3 * sizeof(float) * NX * NY) : NULL;
    m.indices = malloc(3 * sizeof(uint32_t) * m.triangle_count);
    for (int j = 0; j < NY; ++j)
        for (int i = 0; i < NX; ++i) {
            int k = j * NX + i;
            float *p = m.positions + 3 * k, *n = m.normals + 3 * k;
            p[0] = 0.137f * i;
            p[1] = 0.291f * j;
            p[2] = 0.01f * (float)(i * j) - 0.003f;
            n[0] = 0.6f;
            n[1] = 0.0f;
            n[2] = 0.8f - 0.001f * k;
            m.uvs[2 * k] = (float)i / (NX - 1);
            m.uvs[2 * k + 1] = (float)j / (NY - 1) * 0.987f;
            if (with_tangents) {
                m.tangents[3 * k] = 0.8f;
                m.tangents[3 * k + 1] = 0.001f * k;
                m.tangents[3 * k + 2] = -0.6f;
            }
        }
    uint32_t *t = m.indices;
    for (int j = 0; j + 1 < NY; ++j)
        for (int i = 0; i + 1 < NX; ++i) {
            uint32_t a = j * NX + i, b = a + 1, c = a + NX, d = c + 1;
            *t++ = a, *t++ = b, *t++ = d;
            *t++ = a, *t++ = d, *t++ = c;
        }
    return m;
}

/* The same triangle as a set: a reader may start a triangle's vertex list
 * anywhere, but must keep the orientation (cyclic order). */
static int same_triangle(const uint32_t *a, const uint32_t *b)
{
    for (int r = 0; r < 3; ++r)
        if (a[0] == b[r] && a[1] == b[(r + 1) % 3] && a[2] == b[(r + 2) % 3])
            return 1;
    return 0;
}

static void assert_floats(const float *a, const float *b, size_t n, float tol)
{
    for (size_t i = 0; i < n; ++i)
        assert_double_near(a[i], b[i], tol);
}

static void round_trip(const char *path, int tangents_expected, float tol)
{
    plm_mesh m = make_grid(1), r;
    plm_error err = {{0}};
    assert_int_equal(plm_mesh_write(path, &m, &err), PLM_OK);
    assert_int_equal(plm_mesh_read(path, &r, &err), PLM_OK);
    assert_int_equal(r.vertex_count, m.vertex_count);
    assert_int_equal(r.triangle_count, m.triangle_count);
    assert_floats(r.positions, m.positions, 3 * (size_t)m.vertex_count, tol);
    assert_non_null(r.normals);
    assert_floats(r.normals, m.normals, 3 * (size_t)m.vertex_count, tol);
    assert_non_null(r.uvs);
    assert_floats(r.uvs, m.uvs, 2 * (size_t)m.vertex_count, tol);
    if (tangents_expected) {
        assert_non_null(r.tangents);
        assert_floats(r.tangents, m.tangents, 3 * (size_t)m.vertex_count, tol);
    } else {
        assert_null(r.tangents);
    }
    for (int t = 0; t < m.triangle_count; ++t)
        assert_true(same_triangle(m.indices + 3 * t, r.indices + 3 * t));
    plm_mesh_free(&m);
    plm_mesh_free(&r);
    assert_null(r.positions);
    remove(path);
}

/* Binary PLY keeps every float bit for bit, tangents included. */
static void ply_round_trip_is_exact(void **state)
{
    (void)state;
    round_trip("mesh_io_test.ply", 1, 0.0f);
}

/* OBJ is text with 9 significant digits and has no tangent field. */
static void obj_round_trip_keeps_geometry(void **state)
{
    (void)state;
    round_trip("mesh_io_test.obj", 0, 1e-6f);
}

static void optional_attributes_stay_absent(void **state)
{
    (void)state;
    plm_mesh m = make_grid(0), r;
    free(m.normals);
    free(m.uvs);
    m.normals = NULL;
    m.uvs = NULL;
    plm_error err = {{0}};
    assert_int_equal(plm_mesh_write("mesh_io_bare.ply", &m, &err), PLM_OK);
    assert_int_equal(plm_mesh_read("mesh_io_bare.ply", &r, &err), PLM_OK);
    assert_null(r.normals);
    assert_null(r.uvs);
    assert_null(r.tangents);
    assert_floats(r.positions, m.positions, 3 * (size_t)m.vertex_count, 0.0f);
    plm_mesh_free(&m);
    plm_mesh_free(&r);
    remove("mesh_io_bare.ply");
}

/* The PLY header names the uvs "s", "t": Blender 3.4's importer knows no
 * other names (see docs/assets.md). Files with "u", "v" still read. */
static void ply_uvs_are_named_s_t(void **state)
{
    (void)state;
    plm_mesh m = make_grid(1);
    plm_error err = {{0}};
    assert_int_equal(plm_mesh_write("mesh_io_names.ply", &m, &err), PLM_OK);
    char header[1024] = {0};
    FILE *f = fopen("mesh_io_names.ply", "rb");
    assert_non_null(f);
    size_t n = fread(header, 1, sizeof header - 1, f);
    fclose(f);
    header[n] = '\0';
    char *end = strstr(header, "end_header");
    assert_non_null(end);
    *end = '\0';
    assert_non_null(strstr(header, "property float s\nproperty float t\n"));
    assert_null(strstr(header, "property float u\n"));
    remove("mesh_io_names.ply");
    plm_mesh_free(&m);

    static const char uv_ply[] = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                                 "property float z\nproperty float u\nproperty float v\nelement face 1\n"
                                 "property list uchar int vertex_indices\nend_header\n"
                                 "0 0 0 0.25 0.5\n1 0 0 0.75 0.5\n0 1 0 0.25 1\n3 0 1 2\n";
    f = fopen("mesh_io_uv.ply", "wb");
    assert_non_null(f);
    fputs(uv_ply, f);
    fclose(f);
    plm_mesh r;
    assert_int_equal(plm_mesh_read("mesh_io_uv.ply", &r, &err), PLM_OK);
    assert_non_null(r.uvs);
    const float expected[6] = {0.25f, 0.5f, 0.75f, 0.5f, 0.25f, 1.0f};
    assert_floats(r.uvs, expected, 6, 0.0f);
    plm_mesh_free(&r);
    remove("mesh_io_uv.ply");
}

/* Writing the same mesh twice gives the same bytes. */
static void writes_are_reproducible(void **state)
{
    (void)state;
    plm_mesh m = make_grid(1);
    plm_error err = {{0}};
    const char *names[2] = {"mesh_io_a.ply", "mesh_io_b.ply"};
    unsigned char *bytes[2];
    long sizes[2];
    for (int k = 0; k < 2; ++k) {
        assert_int_equal(plm_mesh_write(names[k], &m, &err), PLM_OK);
        bytes[k] = read_whole_file(names[k], &sizes[k]);
        remove(names[k]);
    }
    assert_int_equal(sizes[0], sizes[1]);
    assert_memory_equal(bytes[0], bytes[1], (size_t)sizes[0]);
    free(bytes[0]);
    free(bytes[1]);
    plm_mesh_free(&m);
}

/* Counts directory entries starting with prefix (left-over temporaries). */
static int count_entries(const char *dir, const char *prefix)
{
    char cmd[512];
    snprintf(cmd, sizeof cmd, "ls -a %s | grep -c '^%s' || true", dir, prefix);
    FILE *p = popen(cmd, "r");
    int n = 0;
    if (p) {
        if (fscanf(p, "%d", &n) != 1)
            n = -1;
        pclose(p);
    }
    return n;
}

static void bad_input_fails_cleanly(void **state)
{
    (void)state;
    plm_mesh m = make_grid(1), r;
    plm_error err = {{0}};
    assert_int_equal(plm_mesh_write("mesh_io_test.stl", &m, &err), PLM_ERR_INVALID);
    assert_non_null(strstr(err.message, ".stl"));
    assert_int_equal(plm_mesh_write("no_such_dir/x.ply", &m, &err), PLM_ERR_IO);
    assert_int_equal(plm_mesh_read("mesh_io_missing.ply", &r, &err), PLM_ERR_IO);
    assert_non_null(strstr(err.message, "mesh_io_missing.ply"));
    /* An index out of range is refused before anything is written. */
    remove("mesh_io_badidx.ply");
    m.indices[4] = 999;
    assert_int_equal(plm_mesh_write("mesh_io_badidx.ply", &m, &err), PLM_ERR_INVALID);
    assert_non_null(strstr(err.message, "triangle 1"));
    assert_int_equal(access("mesh_io_badidx.ply", F_OK), -1);
    m.indices[4] = m.indices[3]; /* a degenerate triangle */
    assert_int_equal(plm_mesh_write("mesh_io_badidx.ply", &m, &err), PLM_ERR_INVALID);
    assert_non_null(strstr(err.message, "repeats a vertex"));
    m.indices[4] = 5;
    m.positions[7] = 0.0f / 0.0f;
    assert_int_equal(plm_mesh_write("mesh_io_nan.ply", &m, &err), PLM_ERR_INVALID);
    assert_non_null(strstr(err.message, "non-finite"));
    assert_int_equal(count_entries(".", ".mesh_io"), 0);
    /* Garbage is a parse error naming the file. */
    FILE *fp = fopen("mesh_io_garbage.ply", "wb");
    fputs("ply\nformat nonsense\n", fp);
    fclose(fp);
    assert_int_equal(plm_mesh_read("mesh_io_garbage.ply", &r, &err), PLM_ERR_PARSE);
    assert_non_null(strstr(err.message, "mesh_io_garbage.ply"));
    assert_null(r.positions);
    remove("mesh_io_garbage.ply");
    plm_mesh_free(&m);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(ply_round_trip_is_exact),
        cmocka_unit_test(obj_round_trip_keeps_geometry),
        cmocka_unit_test(optional_attributes_stay_absent),
        cmocka_unit_test(ply_uvs_are_named_s_t),
        cmocka_unit_test(writes_are_reproducible),
        cmocka_unit_test(bad_input_fails_cleanly),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
