/* The contract between the glTF loader (asset_module.c, in plumage_export)
 * and the Assimp adapter (asset_assimp.cpp), built as a module opened the
 * first time a glTF file is written or read (common/module.h): Assimp and
 * what it links add about 9 ms of CPU and 4 MiB to every command's start
 * when linked, so only `plumage export` and its tests load it. Callers use
 * export/asset.h, never this file. */
#ifndef PLUMAGE_EXPORT_ASSET_MODULE_H
#define PLUMAGE_EXPORT_ASSET_MODULE_H

#include "export/asset.h"

typedef struct plm_asset_module {
    unsigned size; /* sizeof(plm_asset_module) as the module was built: a stale module is refused */
    plm_result (*write_gltf)(const char *path, const plm_asset *asset, plm_error *err);
    plm_result (*read_gltf)(const char *path, plm_asset_summary *out, plm_error *err);
} plm_asset_module;

#define PLM_ASSET_MODULE_SYMBOL "plm_asset_module_table"
#define PLM_ASSET_MODULE_FILE "plumage_gltf_assimp.so"
#define PLM_ASSET_MODULE_ENV "PLUMAGE_GLTF_MODULE"

#endif
