// OpenMesh adapter behind common/mesh.h: writes PLY and OBJ files of a
// plm_mesh (common/mesh_read.c reads them).
//
// PLY (binary, little endian) carries positions, normals, uvs and tangents.
// The uvs are named "s", "t", the names most PLY readers know (Blender 3.4
// knows no other; OpenMesh reads them as texture coordinates too), and the
// tangents are three extra float vertex properties "tx", "ty", "tz". OpenMesh's
// writer names texture coordinates "u", "v" with no way to change it, so in PLY
// both travel as its custom persistent properties (see docs/assets.md).
// OBJ has no place for tangents:
// it carries positions, normals and uvs, and readers derive tangents from the
// uvs. The bytes go out through plm_write_file (common/fileio.h): a temporary
// file beside the destination renamed into place, so a failed write leaves
// nothing behind.
// OpenMesh's property vectors default-construct uninitialised points, which
// gcc 12 reports inside its headers; nothing of ours is affected.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif
#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <mutex>
#include <sstream>

extern "C" {
#include "common/fileio.h"
#include "common/mesh.h"
}
#include "common/adapter_guard.hpp"

namespace {

struct plm_om_traits : OpenMesh::DefaultTraits {
    typedef OpenMesh::Vec3f Point;
    typedef OpenMesh::Vec3f Normal;
    typedef OpenMesh::Vec2f TexCoord2D;
    VertexAttributes(OpenMesh::Attributes::Normal | OpenMesh::Attributes::TexCoord2D);
};
typedef OpenMesh::TriMesh_ArrayKernelT<plm_om_traits> om_mesh;

const char *const tangent_names[3] = {"tx", "ty", "tz"};
const char *const ply_uv_names[2] = {"s", "t"};

// OpenMesh prints its own diagnostics on std::cerr; plumage reports errors
// through plm_error instead, so they are switched off once per process.
void quiet_openmesh()
{
    static std::once_flag once;
    std::call_once(once, [] {
        omerr().disable(); // (disconnecting std::cerr would leak OpenMesh's target object)
        omlog().disable();
        omout().disable();
    });
}

bool is_supported_extension(const char *path, char *ext, size_t ext_size)
{
    plm_path_extension(path, ext, ext_size);
    return std::strcmp(ext, "ply") == 0 || std::strcmp(ext, "obj") == 0;
}

bool all_finite(const float *v, size_t n)
{
    for (size_t i = 0; i < n; ++i)
        if (!std::isfinite(v[i]))
            return false;
    return true;
}

// Stores n components per vertex of `values` as n float vertex properties
// that OpenMesh's writers save by name.
void add_named_properties(om_mesh &om, const char *const *names, int n, const float *values)
{
    for (int c = 0; c < n; ++c) {
        OpenMesh::VPropHandleT<float> h;
        om.add_property(h, names[c]);
        om.property(h).set_persistent(true);
        for (size_t i = 0; i < om.n_vertices(); ++i)
            om.property(h, om.vertex_handle((unsigned)i)) = values[(size_t)n * i + c];
    }
}

// ply: the uvs become the named properties "s", "t" instead of OpenMesh's
// texture coordinates.
plm_result build_om_mesh(const char *path, const plm_mesh *m, bool ply, om_mesh &om, plm_error *err)
{
    if (m->vertex_count <= 0 || m->triangle_count <= 0 || !m->positions || !m->indices)
        return plm_fail(err, PLM_ERR_INVALID, "%s: the mesh is empty (%d vertices, %d triangles)", path,
                        m->vertex_count, m->triangle_count);
    size_t nv = (size_t)m->vertex_count;
    if (!all_finite(m->positions, 3 * nv) || (m->normals && !all_finite(m->normals, 3 * nv)) ||
        (m->uvs && !all_finite(m->uvs, 2 * nv)) || (m->tangents && !all_finite(m->tangents, 3 * nv)))
        return plm_fail(err, PLM_ERR_INVALID, "%s: the mesh has a non-finite vertex attribute", path);
    om.reserve(nv, 3 * (size_t)m->triangle_count, (size_t)m->triangle_count);
    for (size_t i = 0; i < nv; ++i) {
        const float *p = m->positions + 3 * i;
        om_mesh::VertexHandle vh = om.add_vertex(om_mesh::Point(p[0], p[1], p[2]));
        if (m->normals)
            om.set_normal(vh, om_mesh::Normal(m->normals[3 * i], m->normals[3 * i + 1], m->normals[3 * i + 2]));
        if (m->uvs && !ply)
            om.set_texcoord2D(vh, om_mesh::TexCoord2D(m->uvs[2 * i], m->uvs[2 * i + 1]));
    }
    for (int t = 0; t < m->triangle_count; ++t) {
        const uint32_t *idx = m->indices + 3 * (size_t)t;
        if (idx[0] >= nv || idx[1] >= nv || idx[2] >= nv)
            return plm_fail(err, PLM_ERR_INVALID, "%s: triangle %d refers to a vertex beyond %d", path, t,
                            m->vertex_count);
        if (idx[0] == idx[1] || idx[1] == idx[2] || idx[2] == idx[0])
            return plm_fail(err, PLM_ERR_INVALID, "%s: triangle %d (%u %u %u) repeats a vertex", path, t, idx[0],
                            idx[1], idx[2]);
        om_mesh::FaceHandle fh = om.add_face(om.vertex_handle(idx[0]), om.vertex_handle(idx[1]),
                                             om.vertex_handle(idx[2]));
        if (!fh.is_valid())
            return plm_fail(err, PLM_ERR_INVALID,
                            "%s: triangle %d (%u %u %u) makes the mesh non-manifold", path, t,
                            idx[0], idx[1], idx[2]);
    }
    if (m->uvs && ply)
        add_named_properties(om, ply_uv_names, 2, m->uvs);
    if (m->tangents)
        add_named_properties(om, tangent_names, 3, m->tangents);
    return PLM_OK;
}

} // namespace

extern "C" void plm_mesh_free(plm_mesh *mesh)
{
    if (!mesh)
        return;
    std::free(mesh->positions);
    std::free(mesh->normals);
    std::free(mesh->uvs);
    std::free(mesh->tangents);
    std::free(mesh->density);
    std::free(mesh->indices);
    std::memset(mesh, 0, sizeof *mesh);
}

static plm_result mesh_write(const char *path, const plm_mesh *mesh, plm_error *err)
{
    char ext[16];
    if (!is_supported_extension(path, ext, sizeof ext))
        return plm_fail(err, PLM_ERR_INVALID, "%s: unsupported mesh format '.%s' (use .ply or .obj)", path, ext);
    quiet_openmesh();
    bool ply = std::strcmp(ext, "ply") == 0;
    om_mesh om;
    plm_result rc = build_om_mesh(path, mesh, ply, om, err);
    if (rc != PLM_OK)
        return rc;
    OpenMesh::IO::Options opt;
    if (ply)
        opt += OpenMesh::IO::Options::Binary | OpenMesh::IO::Options::LSB;
    if (mesh->normals)
        opt += OpenMesh::IO::Options::VertexNormal;
    if (mesh->uvs && !ply)
        opt += OpenMesh::IO::Options::VertexTexCoord;
    if (mesh->tangents || (mesh->uvs && ply))
        opt += OpenMesh::IO::Options::Custom;
    // OpenMesh writes into memory and plumage writes the bytes, so that a full
    // disk or an unwritable folder is reported as it is and nothing is left half-written.
    std::ostringstream bytes(std::ios::out | std::ios::binary);
    bool ok = false;
    try {
        ok = OpenMesh::IO::write_mesh(om, bytes, ext, opt, 9);
    } catch (const std::exception &) {
        ok = false;
    }
    if (!ok)
        return plm_fail(err, PLM_ERR_INTERNAL, "%s: the OpenMesh writer failed", path);
    const std::string data = bytes.str();
    return plm_write_file(path, data.data(), data.size(), err);
}

extern "C" plm_result plm_mesh_write(const char *path, const plm_mesh *mesh, plm_error *err)
{
    return plm_guard(err, path, [&] { return mesh_write(path, mesh, err); });
}
