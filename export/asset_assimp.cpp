// Assimp adapter behind export/asset.h, built as the module asset_module.c
// opens on first use: a plm_asset to glTF 2.0 (.glb or .gltf) and a glTF
// file back to a summary.
//
// Writing: the asset becomes an aiScene (a mesh per plm_asset_mesh, a node
// per plm_asset_node referring to meshes by index, so many nodes share one
// mesh) and Assimp's glTF 2 exporter writes it into memory through an
// IOSystem of our own; the bytes then go out through plm_write_file (a
// temporary beside each destination, renamed when complete). What Assimp
// 5.2 does with it, checked by tests/test_export.c and docs/assets.md:
//  - a mesh referred to by many nodes is written once and every node refers
//    to it: sharing survives;
//  - a node with two meshes gets one glTF mesh of two primitives (its
//    MergeMeshes step), and every other node with the same pair refers to
//    that merged mesh;
//  - it flips v (glTF's v runs down the image), so plumage's uvs go in as
//    they are;
//  - its GLB writer pads the binary chunk with the JSON chunk's padding
//    length instead of its own, so the file can come out a few bytes short
//    of the length its header states; the binary chunk is padded here;
//  - it writes a node's matrix only if aiMatrix4x4::IsIdentity says no,
//    which allows 0.01 in every element: an offset under 0.01 scene units,
//    a rotation under half a degree or a 1% scale would be lost;
//    such nodes get their matrix written into the JSON here.
#include <assimp/Exporter.hpp>
#include <assimp/GltfMaterial.h>
#include <assimp/IOStream.hpp>
#include <assimp/IOSystem.hpp>
#include <assimp/Importer.hpp>
#include <assimp/material.h>
#include <assimp/scene.h>

#include <cjson/cJSON.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <map>
#include <memory>
#include <string>
#include <vector>

extern "C" {
#include "common/fileio.h"
#include "export/asset_module.h"
}
#include "common/adapter_guard.hpp"

namespace {

typedef std::map<std::string, std::vector<char>> file_map;

// A file Assimp writes, kept in memory.
class memory_stream : public Assimp::IOStream {
public:
    explicit memory_stream(std::vector<char> &data) : data_(data) { data_.clear(); }
    size_t Read(void *, size_t, size_t) override { return 0; }
    size_t Write(const void *buffer, size_t size, size_t count) override
    {
        size_t n = size * count;
        if (pos_ + n > data_.size())
            data_.resize(pos_ + n);
        if (n)
            std::memcpy(data_.data() + pos_, buffer, n);
        pos_ += n;
        return count;
    }
    aiReturn Seek(size_t offset, aiOrigin origin) override
    {
        size_t base = origin == aiOrigin_SET ? 0 : origin == aiOrigin_CUR ? pos_ : data_.size();
        pos_ = base + offset;
        return aiReturn_SUCCESS;
    }
    size_t Tell() const override { return pos_; }
    size_t FileSize() const override { return data_.size(); }
    void Flush() override {}

private:
    std::vector<char> &data_;
    size_t pos_ = 0;
};

// Assimp owns (and deletes) its IOSystem; the files live in the caller's map.
class memory_io : public Assimp::IOSystem {
public:
    explicit memory_io(file_map &files) : files_(files) {}
    bool Exists(const char *path) const override { return files_.count(path) != 0; }
    char getOsSeparator() const override { return '/'; }
    Assimp::IOStream *Open(const char *path, const char *mode) override
    {
        if (!mode || mode[0] != 'w')
            return nullptr;
        return new memory_stream(files_[path]);
    }
    void Close(Assimp::IOStream *stream) override { delete stream; }

private:
    file_map &files_;
};

aiMatrix4x4 to_ai(const double m[3][4])
{
    return aiMatrix4x4((ai_real)m[0][0], (ai_real)m[0][1], (ai_real)m[0][2], (ai_real)m[0][3], (ai_real)m[1][0],
                       (ai_real)m[1][1], (ai_real)m[1][2], (ai_real)m[1][3], (ai_real)m[2][0], (ai_real)m[2][1],
                       (ai_real)m[2][2], (ai_real)m[2][3], 0, 0, 0, 1);
}

void from_ai(const aiMatrix4x4 &a, double m[3][4])
{
    const ai_real *r[3] = {&a.a1, &a.b1, &a.c1};
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 4; ++j)
            m[i][j] = r[i][j];
}

aiMesh *make_mesh(const plm_asset_mesh &src)
{
    std::unique_ptr<aiMesh> m(new aiMesh());
    m->mName = aiString(src.name);
    m->mMaterialIndex = (unsigned)src.material;
    m->mPrimitiveTypes = src.lines ? aiPrimitiveType_LINE : aiPrimitiveType_TRIANGLE;
    unsigned nv = (unsigned)src.vertex_count;
    m->mNumVertices = nv;
    m->mVertices = new aiVector3D[nv];
    if (src.normals)
        m->mNormals = new aiVector3D[nv];
    if (src.uvs) {
        m->mTextureCoords[0] = new aiVector3D[nv];
        m->mNumUVComponents[0] = 2;
    }
    for (unsigned i = 0; i < nv; ++i) {
        const float *p = src.positions + 3 * (size_t)i;
        m->mVertices[i] = aiVector3D(p[0], p[1], p[2]);
        if (src.normals) {
            const float *n = src.normals + 3 * (size_t)i;
            m->mNormals[i] = aiVector3D(n[0], n[1], n[2]);
        }
        if (src.uvs)
            m->mTextureCoords[0][i] = aiVector3D(src.uvs[2 * (size_t)i], src.uvs[2 * (size_t)i + 1], 0);
    }
    unsigned per_face = src.lines ? 2 : 3, nf = (unsigned)src.index_count / per_face;
    m->mNumFaces = nf;
    m->mFaces = new aiFace[nf];
    for (unsigned f = 0; f < nf; ++f) {
        m->mFaces[f].mNumIndices = per_face;
        m->mFaces[f].mIndices = new unsigned[per_face];
        for (unsigned k = 0; k < per_face; ++k)
            m->mFaces[f].mIndices[k] = src.indices[(size_t)per_face * f + k];
    }
    return m.release();
}

aiMaterial *make_material(const plm_asset_material &src, const plm_asset *asset)
{
    std::unique_ptr<aiMaterial> m(new aiMaterial());
    aiString name(src.name);
    m->AddProperty(&name, AI_MATKEY_NAME);
    aiColor4D colour(src.base_color[0], src.base_color[1], src.base_color[2], src.base_color[3]);
    m->AddProperty(&colour, 1, AI_MATKEY_BASE_COLOR);
    float metallic = 0.0f, roughness = 1.0f;
    m->AddProperty(&metallic, 1, AI_MATKEY_METALLIC_FACTOR);
    m->AddProperty(&roughness, 1, AI_MATKEY_ROUGHNESS_FACTOR);
    int two_sided = src.double_sided ? 1 : 0;
    m->AddProperty(&two_sided, 1, AI_MATKEY_TWOSIDED);
    aiString mode(src.blend ? "BLEND" : "OPAQUE");
    m->AddProperty(&mode, AI_MATKEY_GLTF_ALPHAMODE);
    if (src.unlit) { // the exporter reads the shading model as raw bytes: a buffer property, not an integer
        aiShadingMode shading = aiShadingMode_Unlit;
        m->AddProperty<aiShadingMode>(&shading, 1, AI_MATKEY_SHADING_MODEL);
    }
    // Assimp 5.2 declares KHR_materials_volume for a material that does not
    // state a volume (an inverted test); stating the extension's defaults
    // keeps it out of the file.
    float thickness = 0.0f, distance = INFINITY;
    aiColor3D attenuation(1.0f, 1.0f, 1.0f);
    m->AddProperty(&thickness, 1, AI_MATKEY_VOLUME_THICKNESS_FACTOR);
    m->AddProperty(&distance, 1, AI_MATKEY_VOLUME_ATTENUATION_DISTANCE);
    m->AddProperty(&attenuation, 1, AI_MATKEY_VOLUME_ATTENUATION_COLOR);
    if (src.texture >= 0) {
        const plm_asset_texture &t = asset->textures[src.texture];
        // "*N" names the scene's embedded texture N; any other path is a uri.
        aiString path(t.uri[0] ? std::string(t.uri) : "*" + std::to_string(src.texture));
        m->AddProperty(&path, AI_MATKEY_TEXTURE(aiTextureType_BASE_COLOR, 0));
    }
    return m.release();
}

aiTexture *make_texture(const plm_asset_texture &src, int index)
{
    std::unique_ptr<aiTexture> t(new aiTexture());
    t->mHeight = 0; // compressed: mWidth is the byte count
    t->mWidth = (unsigned)src.png_size;
    std::snprintf(t->achFormatHint, sizeof t->achFormatHint, "png");
    t->mFilename = aiString("texture" + std::to_string(index) + ".png");
    t->pcData = new aiTexel[(src.png_size + sizeof(aiTexel) - 1) / sizeof(aiTexel)];
    std::memcpy(t->pcData, src.png, src.png_size);
    return t.release();
}

std::unique_ptr<aiScene> make_scene(const plm_asset *a)
{
    std::unique_ptr<aiScene> s(new aiScene());
    s->mMeshes = new aiMesh *[a->mesh_count]();
    for (int i = 0; i < a->mesh_count; ++i, ++s->mNumMeshes)
        s->mMeshes[i] = make_mesh(a->meshes[i]);
    s->mMaterials = new aiMaterial *[a->material_count]();
    for (int i = 0; i < a->material_count; ++i, ++s->mNumMaterials)
        s->mMaterials[i] = make_material(a->materials[i], a);
    int embedded = 0;
    for (int i = 0; i < a->texture_count; ++i)
        embedded += a->textures[i].uri[0] == '\0';
    if (embedded) {
        s->mTextures = new aiTexture *[a->texture_count]();
        for (int i = 0; i < a->texture_count; ++i, ++s->mNumTextures) // indices stay those of the asset
            s->mTextures[i] = make_texture(a->textures[i], i);
    }
    std::vector<aiNode *> nodes((size_t)a->node_count);
    std::vector<unsigned> children((size_t)a->node_count, 0);
    for (int i = 1; i < a->node_count; ++i)
        children[(size_t)a->nodes[i].parent]++;
    for (int i = 0; i < a->node_count; ++i) {
        const plm_asset_node &src = a->nodes[i];
        aiNode *n = new aiNode(src.name);
        if (i == 0)
            s->mRootNode = n;
        else
            nodes[(size_t)src.parent]->addChildren(1, &n);
        nodes[(size_t)i] = n;
        n->mTransformation = to_ai(src.matrix);
        n->mNumMeshes = (unsigned)src.mesh_count;
        n->mMeshes = src.mesh_count ? new unsigned[src.mesh_count] : nullptr;
        for (int k = 0; k < src.mesh_count; ++k)
            n->mMeshes[k] = (unsigned)src.mesh[k];
    }
    return s;
}

// The asset's references are in range and its nodes come after their parents.
plm_result check_asset(const char *path, const plm_asset *a, plm_error *err)
{
    if (a->node_count < 1 || a->nodes[0].parent != -1)
        return plm_fail(err, PLM_ERR_INVALID, "%s: an asset needs a root node (node 0, parent -1)", path);
    for (int i = 1; i < a->node_count; ++i) {
        const plm_asset_node &n = a->nodes[i];
        if (n.parent < 0 || n.parent >= i)
            return plm_fail(err, PLM_ERR_INVALID, "%s: node %d's parent %d does not come before it", path, i, n.parent);
    }
    for (int i = 0; i < a->node_count; ++i)
        for (int k = 0; k < a->nodes[i].mesh_count; ++k)
            if (a->nodes[i].mesh[k] < 0 || a->nodes[i].mesh[k] >= a->mesh_count)
                return plm_fail(err, PLM_ERR_INVALID, "%s: node %d refers to mesh %d of %d", path, i,
                                a->nodes[i].mesh[k], a->mesh_count);
    for (int i = 0; i < a->mesh_count; ++i) {
        const plm_asset_mesh &m = a->meshes[i];
        int per_face = m.lines ? 2 : 3;
        if (m.material < 0 || m.material >= a->material_count || m.vertex_count <= 0 || m.index_count <= 0 ||
            m.index_count % per_face)
            return plm_fail(err, PLM_ERR_INVALID, "%s: mesh %s is empty or has a bad material or index count", path,
                            m.name);
        for (int k = 0; k < m.index_count; ++k)
            if (m.indices[k] >= (uint32_t)m.vertex_count)
                return plm_fail(err, PLM_ERR_INVALID, "%s: mesh %s refers to vertex %u of %d", path, m.name,
                                m.indices[k], m.vertex_count);
    }
    for (int i = 0; i < a->material_count; ++i)
        if (a->materials[i].texture >= a->texture_count)
            return plm_fail(err, PLM_ERR_INVALID, "%s: material %s refers to texture %d of %d", path,
                            a->materials[i].name, a->materials[i].texture, a->texture_count);
    return PLM_OK;
}

uint32_t read_u32(const std::vector<char> &d, size_t at)
{
    uint32_t v = 0;
    std::memcpy(&v, d.data() + at, 4); // GLB is little endian, as is every machine plumage builds on
    return v;
}

// Makes a GLB's binary chunk as long as its header says, zero-padded (see the top of this file).
void fix_glb_padding(std::vector<char> &d)
{
    if (d.size() < 20)
        return;
    size_t json_end = 20 + (size_t)read_u32(d, 12);
    if (d.size() < json_end + 8)
        return;
    size_t bin_end = json_end + 8 + (size_t)read_u32(d, json_end);
    size_t old = d.size();
    d.resize(bin_end, '\0');
    for (size_t i = old; i < bin_end; ++i)
        d[i] = '\0';
}

// A transform that Assimp's exporter takes for the identity though it is not (see the top).
bool dropped_by_assimp(const double m[3][4])
{
    if (!to_ai(m).IsIdentity())
        return false;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 4; ++j)
            if (m[i][j] != (i == j ? 1.0 : 0.0))
                return true;
    return false;
}

typedef std::map<std::string, int> node_names;

// The nodes whose matrix Assimp leaves out, by name (unique in plumage's assets).
node_names lost_matrices(const plm_asset *a)
{
    node_names lost;
    for (int i = 0; i < a->node_count; ++i)
        if (dropped_by_assimp(a->nodes[i].matrix))
            lost[a->nodes[i].name] = i;
    return lost;
}

// The glTF JSON json with the matrices of the lost nodes written in; false
// if it cannot be parsed or a lost node is not in it.
bool restore_matrices(std::string &json, const plm_asset *a, const node_names &lost)
{
    size_t restored = 0;
    cJSON *doc = cJSON_ParseWithLength(json.data(), json.size());
    const cJSON *nodes = doc ? cJSON_GetObjectItem(doc, "nodes") : nullptr, *node;
    cJSON_ArrayForEach(node, nodes)
    {
        const char *name = cJSON_GetStringValue(cJSON_GetObjectItem(node, "name"));
        auto it = name ? lost.find(name) : lost.end();
        if (it == lost.end() || cJSON_HasObjectItem(node, "matrix"))
            continue;
        const double(*m)[4] = a->nodes[it->second].matrix;
        double column_major[16];
        for (int k = 0; k < 16; ++k) // glTF: column by column; the last row 0 0 0 1
            column_major[k] = k % 4 == 3 ? (k == 15 ? 1.0 : 0.0) : m[k % 4][k / 4];
        cJSON_AddItemToObject((cJSON *)node, "matrix", cJSON_CreateDoubleArray(column_major, 16));
        restored++;
    }
    char *text = doc && restored == lost.size() ? cJSON_PrintUnformatted(doc) : nullptr;
    cJSON_Delete(doc);
    if (!text)
        return false;
    json = text;
    cJSON_free(text);
    return true;
}

// The same inside a GLB: its JSON chunk replaced, padded with spaces, and the lengths updated.
bool restore_glb_matrices(std::vector<char> &d, const plm_asset *a, const node_names &lost)
{
    if (d.size() < 20 || 20 + (size_t)read_u32(d, 12) > d.size())
        return false;
    size_t json_end = 20 + (size_t)read_u32(d, 12);
    std::string json(d.data() + 20, json_end - 20);
    if (!restore_matrices(json, a, lost))
        return false;
    json.resize((json.size() + 3) / 4 * 4, ' ');
    std::vector<char> out(d.begin(), d.begin() + 12);
    uint32_t json_size = (uint32_t)json.size(), total = (uint32_t)(20 + json.size() + (d.size() - json_end));
    out.resize(20);
    std::memcpy(out.data() + 8, &total, 4);
    std::memcpy(out.data() + 12, &json_size, 4);
    std::memcpy(out.data() + 16, "JSON", 4);
    out.insert(out.end(), json.begin(), json.end());
    out.insert(out.end(), d.begin() + (long)json_end, d.end());
    d.swap(out);
    return true;
}

plm_result write_files(const char *path, const plm_asset *a, file_map &files, plm_error *err)
{
    // Texture files and buffers first, the file that names them last, so
    // that a reader never finds the main file without what it refers to.
    std::string dir(path);
    size_t slash = dir.find_last_of('/');
    dir = slash == std::string::npos ? "" : dir.substr(0, slash + 1);
    std::vector<std::pair<std::string, std::vector<char>>> order;
    for (int i = 0; i < a->texture_count; ++i)
        if (a->textures[i].uri[0]) {
            const char *png = (const char *)a->textures[i].png;
            order.emplace_back(dir + a->textures[i].uri, std::vector<char>(png, png + a->textures[i].png_size));
        }
    for (auto &f : files)
        if (f.first != path)
            order.emplace_back(f.first, std::move(f.second));
    order.emplace_back(path, std::move(files[path]));
    std::vector<std::string> written;
    for (const auto &f : order) {
        plm_result rc = plm_write_file(f.first.c_str(), f.second.data(), f.second.size(), err);
        if (rc != PLM_OK) {
            for (const auto &w : written)
                std::remove(w.c_str());
            return rc;
        }
        written.push_back(f.first);
    }
    return PLM_OK;
}

plm_result asset_write(const char *path, const plm_asset *a, plm_error *err)
{
    char ext[16];
    plm_path_extension(path, ext, sizeof ext);
    bool glb = std::strcmp(ext, "glb") == 0;
    if (!glb && std::strcmp(ext, "gltf") != 0)
        return plm_fail(err, PLM_ERR_INVALID, "%s: unsupported format '.%s' (use .glb or .gltf)", path, ext);
    plm_result rc = check_asset(path, a, err);
    if (rc != PLM_OK)
        return rc;
    std::unique_ptr<aiScene> scene = make_scene(a);
    file_map files;
    Assimp::Exporter exporter;
    exporter.SetIOHandler(new memory_io(files));
    if (exporter.Export(scene.get(), glb ? "glb2" : "gltf2", path, 0) != AI_SUCCESS)
        return plm_fail(err, PLM_ERR_INTERNAL, "%s: Assimp's glTF exporter failed: %s", path,
                        exporter.GetErrorString());
    if (!files.count(path))
        return plm_fail(err, PLM_ERR_INTERNAL, "%s: Assimp's glTF exporter wrote no file", path);
    std::vector<char> &file = files[path];
    if (glb)
        fix_glb_padding(file);
    node_names lost = lost_matrices(a);
    bool restored = true;
    if (!lost.empty() && glb) {
        restored = restore_glb_matrices(file, a, lost);
    } else if (!lost.empty()) {
        std::string json(file.begin(), file.end());
        restored = restore_matrices(json, a, lost);
        file.assign(json.begin(), json.end());
    }
    if (!restored)
        return plm_fail(err, PLM_ERR_INTERNAL, "%s: cannot write the matrices Assimp's glTF exporter left out", path);
    return write_files(path, a, files, err);
}

// Parents before children, depth first, each with its world transform.
void summarise_nodes(const aiNode *n, int parent, const aiMatrix4x4 &above, std::vector<plm_asset_summary_node> &out)
{
    plm_asset_summary_node s;
    std::memset(&s, 0, sizeof s);
    std::snprintf(s.name, sizeof s.name, "%.63s", n->mName.C_Str());
    s.parent = parent;
    aiMatrix4x4 world = above * n->mTransformation;
    from_ai(world, s.world);
    s.mesh_count = (int)std::min<unsigned>(n->mNumMeshes, PLM_ASSET_NODE_MESHES);
    for (int k = 0; k < s.mesh_count; ++k)
        s.mesh[k] = (int)n->mMeshes[k];
    int self = (int)out.size();
    out.push_back(s);
    for (unsigned c = 0; c < n->mNumChildren; ++c)
        summarise_nodes(n->mChildren[c], self, world, out);
}

template <class T> T *copy_out(const std::vector<T> &v)
{
    T *p = (T *)std::calloc(v.size() + 1, sizeof(T));
    if (!p)
        throw std::bad_alloc();
    if (!v.empty())
        std::memcpy(p, v.data(), v.size() * sizeof(T));
    return p;
}

plm_result asset_read(const char *path, plm_asset_summary *out, plm_error *err)
{
    Assimp::Importer importer;
    const aiScene *s = importer.ReadFile(path, 0);
    if (!s || !s->mRootNode)
        return plm_fail(err, PLM_ERR_PARSE, "%s: Assimp cannot read it: %s", path, importer.GetErrorString());
    std::vector<plm_asset_summary_node> nodes;
    summarise_nodes(s->mRootNode, -1, aiMatrix4x4(), nodes);
    std::vector<plm_asset_summary_mesh> meshes;
    for (unsigned i = 0; i < s->mNumMeshes; ++i) {
        const aiMesh *m = s->mMeshes[i];
        meshes.push_back({(int)m->mNumVertices, (int)m->mNumFaces, (m->mPrimitiveTypes & aiPrimitiveType_LINE) != 0,
                          (int)m->mMaterialIndex, m->HasTextureCoords(0), m->HasNormals()});
    }
    std::vector<plm_asset_summary_material> materials;
    for (unsigned i = 0; i < s->mNumMaterials; ++i) {
        const aiMaterial *m = s->mMaterials[i];
        plm_asset_summary_material r;
        std::memset(&r, 0, sizeof r);
        aiString name, mode, tex;
        if (m->Get(AI_MATKEY_NAME, name) == AI_SUCCESS)
            std::snprintf(r.name, sizeof r.name, "%s", name.C_Str());
        r.base_color_textures = (int)m->GetTextureCount(aiTextureType_BASE_COLOR);
        if (r.base_color_textures && m->GetTexture(aiTextureType_BASE_COLOR, 0, &tex) == AI_SUCCESS)
            r.texture_embedded = s->GetEmbeddedTexture(tex.C_Str()) != nullptr;
        r.blend = m->Get(AI_MATKEY_GLTF_ALPHAMODE, mode) == AI_SUCCESS && std::strcmp(mode.C_Str(), "BLEND") == 0;
        materials.push_back(r);
    }
    out->nodes = copy_out(nodes);
    out->node_count = (int)nodes.size();
    out->meshes = copy_out(meshes);
    out->mesh_count = (int)meshes.size();
    out->materials = copy_out(materials);
    out->material_count = (int)materials.size();
    out->texture_count = (int)s->mNumTextures;
    return PLM_OK;
}

} // namespace

// The module's entry points let no exception out (common/adapter_guard.hpp).
static plm_result assimp_write(const char *path, const plm_asset *asset, plm_error *err)
{
    return plm_guard(err, path, [&] { return asset_write(path, asset, err); });
}

static void free_summary(plm_asset_summary *s)
{
    std::free(s->nodes);
    std::free(s->meshes);
    std::free(s->materials);
    std::memset(s, 0, sizeof *s);
}

static plm_result assimp_read(const char *path, plm_asset_summary *out, plm_error *err)
{
    std::memset(out, 0, sizeof *out);
    plm_result rc = plm_guard(err, path, [&] { return asset_read(path, out, err); });
    if (rc != PLM_OK)
        free_summary(out);
    return rc;
}

extern "C" __attribute__((visibility("default"))) const plm_asset_module plm_asset_module_table = {
    sizeof(plm_asset_module), assimp_write, assimp_read};
