/* A plumage scene as a glTF 2.0 file (docs/assets.md, "glTF export"): each
 * distinct (mesh, material) pair once, each placed feather a node with its
 * transform referring to its vane and rachis, every other instance (body,
 * surface) a node of its own, under a root node that turns the scene's up
 * axis into glTF's +y. Curves (a feather's fluff) go out as line segments,
 * their colour the fiber's, baked alike. Feather materials get a base colour texture baked
 * from the renderer's BSDF (export/bake.h) with the vane's transparency as
 * alpha, and their orientation texture rides along in an unlit material of
 * its own. */
#ifndef PLUMAGE_EXPORT_GLTF_H
#define PLUMAGE_EXPORT_GLTF_H

#include "common/error.h"
#include "export/bake.h"
#include "render/scene.h"

/* Zero-initialised: everything exported, the bake's defaults. */
typedef struct plm_gltf_options {
    int no_fluff;        /* leave the fluffy bases (part "fluff": lines or meshes) out */
    plm_bake_options bake;
    int table_threads;   /* fiber table builds: 0 = all cores */
} plm_gltf_options;

typedef struct plm_gltf_report {
    int nodes;        /* with the root */
    int feathers;     /* nodes of placed feathers */
    int meshes;       /* distinct (mesh, material) pairs: glTF primitives */
    int materials;    /* with the orientation materials */
    int textures;
    int instances;    /* the scene's instances exported */
    int left_out;     /* instances left out (the fluff with no_fluff) */
    int line_meshes;  /* meshes of line segments (curves: fluff) */
    long segments;    /* their segments */
    double bake_seconds, write_seconds;
} plm_gltf_report;

/* Writes path (.glb, or .gltf with NAME.bin and NAME.MATERIAL.*.png beside
 * it). The bake builds (or reads from the cache) each feather optics' fiber
 * tables as rendering does, one optics at a time, and frees them once baked.
 * report may be NULL. */
plm_result plm_gltf_export(const plm_scene *scene, const char *path, const plm_gltf_options *o, plm_gltf_report *report,
                           plm_error *err);

/* The root node's transform: a rotation taking the scene's up axis (its
 * camera's up, rounded to the nearest axis) onto +y. */
void plm_gltf_root_matrix(const plm_scene *scene, double m[3][4]);

#endif
