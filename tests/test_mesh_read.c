/* plumage's own PLY and OBJ readers (common/mesh_read.c): the variants the
 * common tools write, and malformed files refused with a message naming the
 * file and the place, before anything large is allocated. Round trips with
 * the writer are in test_generate_mesh_io.c. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>
#include "assert_double.h"

#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "common/mesh.h"

static void write_bytes(const char *path, const void *data, size_t size)
{
    FILE *fp = fopen(path, "wb");
    assert_non_null(fp);
    assert_int_equal(fwrite(data, 1, size, fp), size);
    fclose(fp);
}

static void write_text(const char *path, const char *text) { write_bytes(path, text, strlen(text)); }

/* Reading path fails with code and a message containing both the file name and `expect`. */
static void assert_refused(const char *path, plm_result code, const char *expect)
{
    plm_mesh m;
    plm_error err = {{0}};
    assert_int_equal(plm_mesh_read(path, &m, &err), code);
    assert_non_null(strstr(err.message, path));
    if (!strstr(err.message, expect))
        fail_msg("\"%s\" does not say \"%s\"", err.message, expect);
    assert_null(m.positions);
    remove(path);
}

/* ASCII PLY with s/t texture coordinates (Blender's names) and a quad face, split into a fan. */
static void ascii_ply_with_st_and_a_quad(void **state)
{
    (void)state;
    write_text("mr_quad.ply", "ply\nformat ascii 1.0\ncomment made by hand\nelement vertex 4\n"
                              "property float x\nproperty float y\nproperty float z\n"
                              "property float s\nproperty float t\nelement face 1\n"
                              "property list uchar int vertex_indices\nend_header\n"
                              "0 0 0 0 0\n2 0 0 1 0\n2 1 0 1 1\n0 1 0 0 0.5\n4 0 1 2 3\n");
    plm_mesh m;
    plm_error err = {{0}};
    assert_int_equal(plm_mesh_read("mr_quad.ply", &m, &err), PLM_OK);
    assert_int_equal(m.vertex_count, 4);
    assert_int_equal(m.triangle_count, 2);
    const uint32_t expected[6] = {0, 1, 2, 0, 2, 3};
    assert_memory_equal(m.indices, expected, sizeof expected);
    assert_non_null(m.uvs);
    assert_double_near(m.uvs[7], 0.5, 0.0);
    assert_double_near(m.positions[3], 2.0, 0.0);
    assert_null(m.normals);
    assert_null(m.tangents);
    assert_null(m.density);
    plm_mesh_free(&m);
    remove("mr_quad.ply");
}

/* A per-vertex "density" property (a pelt's feather density) is read with the positions. */
static void ply_density_property(void **state)
{
    (void)state;
    write_text("mr_density.ply", "ply\nformat ascii 1.0\nelement vertex 3\n"
                                 "property float x\nproperty float y\nproperty float z\nproperty float density\n"
                                 "element face 1\nproperty list uchar int vertex_indices\nend_header\n"
                                 "0 0 0 1\n1 0 0 2.5\n0 1 0 4\n3 0 1 2\n");
    plm_mesh m;
    plm_error err = {{0}};
    assert_int_equal(plm_mesh_read("mr_density.ply", &m, &err), PLM_OK);
    assert_non_null(m.density);
    assert_double_near(m.density[0], 1.0, 0.0);
    assert_double_near(m.density[1], 2.5, 0.0);
    assert_double_near(m.density[2], 4.0, 0.0);
    plm_mesh_free(&m);
    remove("mr_density.ply");
}

static void put_be(unsigned char **p, const void *value, int size)
{
    for (int i = 0; i < size; ++i)
        (*p)[i] = ((const unsigned char *)value)[size - 1 - i]; /* the host is little endian */
    *p += size;
}

/* Big-endian binary with double positions, an extra property and an int8 list count. */
static void big_endian_binary_ply(void **state)
{
    (void)state;
    const char *header = "ply\nformat binary_big_endian 1.0\nelement vertex 3\nproperty double x\n"
                         "property double y\nproperty double z\nproperty uchar red\nelement face 1\n"
                         "property list char uint vertex_indices\nend_header\n";
    unsigned char buf[512], *p = buf + strlen(header);
    memcpy(buf, header, strlen(header));
    const double xyz[3][3] = {{0.5, -1.25, 3.0}, {1e-3, 2.0, 0.0}, {-7.0, 0.0, 1.0}};
    for (int v = 0; v < 3; ++v) {
        for (int k = 0; k < 3; ++k)
            put_be(&p, &xyz[v][k], 8);
        *p++ = 200;
    }
    *p++ = 3;
    for (uint32_t i = 0; i < 3; ++i) {
        uint32_t idx = 2 - i;
        put_be(&p, &idx, 4);
    }
    write_bytes("mr_be.ply", buf, (size_t)(p - buf));
    plm_mesh m;
    plm_error err = {{0}};
    assert_int_equal(plm_mesh_read("mr_be.ply", &m, &err), PLM_OK);
    assert_int_equal(m.vertex_count, 3);
    assert_int_equal(m.triangle_count, 1);
    for (int v = 0; v < 3; ++v)
        for (int k = 0; k < 3; ++k)
            assert_double_near(m.positions[3 * v + k], (float)xyz[v][k], 0.0);
    assert_int_equal(m.indices[0], 2);
    assert_int_equal(m.indices[2], 0);
    plm_mesh_free(&m);
    remove("mr_be.ply");
}

/* OBJ corners: negative indices, v//vn, and one position with two uvs (a seam) becoming two vertices. */
static void obj_corners_and_seams(void **state)
{
    (void)state;
    write_text("mr_seam.obj", "# two triangles sharing an edge, with a uv seam at vertex 1\n"
                              "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
                              "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvt 0.5 0.5\n"
                              "vn 0 0 1\n"
                              "f 1/1/1 2/2/1 3/3/1\n"
                              "f -4/5/-1 -2/3/-1 -1/4/-1\n");
    plm_mesh m;
    plm_error err = {{0}};
    assert_int_equal(plm_mesh_read("mr_seam.obj", &m, &err), PLM_OK);
    assert_int_equal(m.triangle_count, 2);
    assert_int_equal(m.vertex_count, 5); /* four positions, vertex 1 twice */
    assert_int_equal(m.indices[0], 0);
    assert_int_equal(m.indices[3], 4); /* the second copy of position 1 */
    assert_double_near(m.positions[12], 0.0, 0.0);
    assert_double_near(m.uvs[8], 0.5, 0.0);
    assert_double_near(m.uvs[0], 0.0, 0.0);
    assert_int_equal(m.indices[4], 2);
    assert_non_null(m.normals);
    assert_double_near(m.normals[14], 1.0, 0.0);
    plm_mesh_free(&m);
    remove("mr_seam.obj");
    /* Faces without uvs on some corners: no uvs at all rather than made-up ones. */
    write_text("mr_mixed.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2 3\n");
    assert_int_equal(plm_mesh_read("mr_mixed.obj", &m, &err), PLM_OK);
    assert_null(m.uvs);
    plm_mesh_free(&m);
    remove("mr_mixed.obj");
}

static void malformed_files_are_refused(void **state)
{
    (void)state;
    /* What OpenMesh crashed on (found by fuzz_mesh_obj and fuzz_mesh_ply). */
    write_text("mr_nov.obj", "vt 0 0\nvt 1 0\nvt 1 1\nf 1/1 2/2 3/3\n");
    assert_refused("mr_nov.obj", PLM_ERR_PARSE, "line 4: a face corner");
    write_text("mr_hdr.ply", "ply\nformat binary_little_endian 1.0\n\xe5lement vertex 4\nend_header\n");
    assert_refused("mr_hdr.ply", PLM_ERR_PARSE, "line 3: unknown header keyword");
    /* Counts are checked against the bytes really there before anything is allocated. */
    write_text("mr_count.ply", "ply\nformat binary_little_endian 1.0\nelement vertex 1000000000\n"
                               "property float x\nproperty float y\nproperty float z\nend_header\n");
    assert_refused("mr_count.ply", PLM_ERR_PARSE, "1000000000 vertex records cannot fit in the 0 bytes left");
    write_text("mr_huge.ply", "ply\nformat ascii 1.0\nelement vertex 1e12\nend_header\n");
    assert_refused("mr_huge.ply", PLM_ERR_PARSE, "line 3: expected \"element NAME COUNT\" with a count of at most");
    write_text("mr_index.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                               "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
                               "end_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n");
    assert_refused("mr_index.ply", PLM_ERR_PARSE, "face 0: a vertex index is not one of the vertices");
    write_text("mr_nan.obj", "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n");
    assert_refused("mr_nan.obj", PLM_ERR_PARSE, "non-finite");
    write_text("mr_empty.obj", "");
    assert_refused("mr_empty.obj", PLM_ERR_PARSE, "no faces");
    write_text("mr_short.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                               "property float z\nend_header\n0 0 0\n1 0 x\n0 1 0\n");
    assert_refused("mr_short.ply", PLM_ERR_PARSE, "vertex 1: truncated or malformed value");
    /* A list count beyond any integer type (found by fuzz_mesh_ply; converting it was undefined). */
    write_text("mr_list.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                              "property float z\nelement face 1\nproperty list uchar int vertex_indices\n"
                              "end_header\n0 0 0\n1 0 0\n0 1 0\n6666666666666666666666666666666666666666 0 1 2\n");
    assert_refused("mr_list.ply", PLM_ERR_PARSE, "face 0: a list's count must be a whole number in [0, 2^30]");
    /* A pipe is not read (opening it would wait for a writer). */
    remove("mr_fifo.ply");
    assert_int_equal(mkfifo("mr_fifo.ply", 0600), 0);
    assert_refused("mr_fifo.ply", PLM_ERR_IO, "not a regular file");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(ascii_ply_with_st_and_a_quad),
        cmocka_unit_test(ply_density_property),
        cmocka_unit_test(big_endian_binary_ply),
        cmocka_unit_test(obj_corners_and_seams),
        cmocka_unit_test(malformed_files_are_refused),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
