/* PLY or OBJ meshes (FUZZ_FILE_NAME's extension chooses the reader): a mesh
 * that reads must be one the renderer can use as it is. */
#include <math.h>

#include "common/mesh.h"
#include "tests/fuzz/fuzz_input.h"

static void check_mesh(const plm_mesh *m)
{
    if (m->vertex_count <= 0 || m->triangle_count <= 0 || !m->positions || !m->indices)
        abort();
    for (long i = 0; i < 3L * m->triangle_count; ++i)
        if (m->indices[i] >= (uint32_t)m->vertex_count)
            abort();
    for (long i = 0; i < 3L * m->vertex_count; ++i)
        if (!isfinite(m->positions[i]))
            abort();
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    const char *path = fuzz_write_input(data, size, FUZZ_FILE_NAME);
    plm_mesh mesh;
    plm_error err = {{0}};
    plm_result rc = plm_mesh_read(path, &mesh, &err);
    fuzz_check_failure(rc, &err);
    if (rc == PLM_OK) {
        check_mesh(&mesh);
        plm_mesh_free(&mesh);
    }
    return 0;
}
