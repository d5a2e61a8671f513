/* A scene for other tools as plain arrays (meshes, materials, textures,
 * nodes) and the glTF 2.0 files it is written to and read back from. The
 * files are written and read by Assimp behind a thin adapter
 * (export/asset_assimp.cpp); export/gltf.h builds the asset from a plumage
 * scene. Nothing here knows plumage's scenes. */
#ifndef PLUMAGE_EXPORT_ASSET_H
#define PLUMAGE_EXPORT_ASSET_H

#include <stddef.h>
#include <stdint.h>

#include "common/error.h"

/* A triangle or line mesh of one material (glTF: one primitive). */
typedef struct plm_asset_mesh {
    char name[128];
    int material;        /* index into the asset's materials */
    int vertex_count;
    const float *positions; /* 3 per vertex */
    const float *normals;   /* 3 per vertex, or NULL */
    const float *uvs;       /* 2 per vertex, or NULL; v up (0 at the image's bottom row), as plumage's meshes */
    int lines;              /* 0: triangles (3 indices each); 1: line segments (2 each) */
    int index_count;
    const uint32_t *indices;
} plm_asset_mesh;

/* A metallic-roughness material (metallic 0, roughness 1). */
typedef struct plm_asset_material {
    char name[128];
    float base_color[4];  /* linear RGBA factor */
    int texture;          /* base colour texture (sRGB RGBA): index into the textures, or -1 */
    int blend;            /* alpha mode BLEND (else OPAQUE) */
    int double_sided;
    int unlit;            /* KHR_materials_unlit: the texture shown as it is (data, not a surface) */
} plm_asset_material;

/* A PNG image: embedded in the file's binary buffer, or, when uri is not
 * empty, referenced by that relative path (the caller writes the file). */
typedef struct plm_asset_texture {
    const unsigned char *png;
    size_t png_size;
    char uri[256];
} plm_asset_texture;

/* A node: its transform relative to its parent, and up to three meshes
 * drawn there (a feather's vane, rachis and fluff; a node's meshes become
 * one glTF mesh of as many primitives). Nodes come after their parent;
 * node 0 is the root. */
#define PLM_ASSET_NODE_MESHES 3
typedef struct plm_asset_node {
    char name[64];
    int parent;              /* -1 for the root */
    double matrix[3][4];     /* rows of [linear | translation] */
    int mesh_count;
    int mesh[PLM_ASSET_NODE_MESHES];
} plm_asset_node;

typedef struct plm_asset {
    plm_asset_mesh *meshes;
    int mesh_count;
    plm_asset_material *materials;
    int material_count;
    plm_asset_texture *textures;
    int texture_count;
    plm_asset_node *nodes;
    int node_count;
} plm_asset;

/* Writes a .glb (textures embedded) or .gltf (JSON, its buffer in
 * NAME.bin beside it, textures with a uri as files the caller writes) by the
 * path's extension. Every file goes through a temporary name and is renamed
 * into place once all are complete; on failure none is left. */
plm_result plm_asset_write_gltf(const char *path, const plm_asset *asset, plm_error *err);

/* What a glTF file holds, as Assimp reads it back: a mesh per primitive. */
typedef struct plm_asset_summary_node {
    char name[64];
    int parent;
    double world[3][4]; /* the node's transform composed with its parents' */
    int mesh_count;
    int mesh[PLM_ASSET_NODE_MESHES];
} plm_asset_summary_node;

typedef struct plm_asset_summary_mesh {
    int vertex_count, face_count, lines, material, has_uvs, has_normals;
} plm_asset_summary_mesh;

typedef struct plm_asset_summary_material {
    char name[128];
    int base_color_textures; /* textures of the base colour slot */
    int texture_embedded;    /* the first one's image is in the file */
    int blend;
} plm_asset_summary_material;

typedef struct plm_asset_summary {
    plm_asset_summary_node *nodes; /* parents first */
    int node_count;
    plm_asset_summary_mesh *meshes;
    int mesh_count;
    plm_asset_summary_material *materials;
    int material_count;
    int texture_count;             /* images embedded in the file */
} plm_asset_summary;

plm_result plm_asset_read_gltf(const char *path, plm_asset_summary *out, plm_error *err);
void plm_asset_summary_free(plm_asset_summary *s);

#endif
