/* A whole feather from a species, in memory or on disk: the vane and rachis
 * meshes (generate/) and the feather and pigment textures (texture/).
 *
 *   plm_species sp;  plm_feather f;  plm_error err;
 *   plm_species_load("presets/species/remex.json", &sp, &err);
 *   plm_feather_options opt = {0};               // zero = defaults
 *   plm_feather_generate(&sp, &opt, &f, &err);   // f.vane, f.rachis, f.fluff, f.texture, f.pigment
 *   ...
 *   plm_feather_free(&f);  plm_species_free(&sp);
 *
 * Meshes are in millimetres in the feather frame of generate/species.h
 * (rachis along +y, dorsal side +z). The rachis is its own closed tube mesh
 * (all of it is rachis); the feather texture also marks the texels under the
 * tube as rachis, so the vane alone still shows a shaft. */
#ifndef PLUMAGE_TEXTURE_FEATHER_H
#define PLUMAGE_TEXTURE_FEATHER_H

#include "common/image_io.h"
#include "common/curves.h"
#include "common/mesh.h"
#include "generate/outline.h"
#include "generate/species.h"

#define PLM_FEATHER_DEFAULT_LEVEL 3

typedef struct plm_feather_options {
    int level;                         /* subdivision level 1..6; 0 = PLM_FEATHER_DEFAULT_LEVEL */
    int texture_width, texture_height; /* 0 = 1024 */
    int no_textures;                   /* meshes only */
    int no_meshes;                     /* textures only */
    int no_pigment;                    /* skip the pigment image */
} plm_feather_options;

typedef struct plm_feather {
    plm_outline outline;
    plm_mesh vane, rachis;
    plm_curves fluff;  /* the fluffy base and afterfeather as fibers (generate/fluff.h); with the meshes */
    plm_image texture; /* the 3-channel feather texture (texture/texture.h) */
    plm_image barb;    /* its barb coordinate (1 channel); files carry it as a 4th channel */
    plm_image pigment; /* 3 pigment channels, or empty */
} plm_feather;

plm_result plm_feather_generate(const plm_species *species, const plm_feather_options *options, plm_feather *out,
                                plm_error *err);

/* Which files plm_feather_write produces. */
typedef struct plm_feather_files {
    int obj;     /* also vane.obj and rachis.obj */
    int no_exr;  /* skip the EXR copies of the textures */
    int no_png;  /* skip the 16-bit PNG copies */
} plm_feather_files;

/* Writes into dir (created if missing): vane.ply, rachis.ply, texture.exr and
 * texture.png (the feather texture), pigment.exr and pigment.png (when
 * present), and feather.json (rendering it writes feather.exr/.png into the
 * working directory, hence the texture's other name),
 * a scene for `plumage render` whose feather material carries `optics` (a
 * species' optics block, copied as it is; NULL: the renderer's defaults) and
 * whose rachis mesh is diffuse in the colour `rachis`, the one the renderer
 * reads from those optics (scene/feathers.h: plm_species_optics_load).
 * Each file is written atomically. */
plm_result plm_feather_write(const plm_feather *f, const cJSON *optics, rgb rachis, const char *dir,
                             const plm_feather_files *files, plm_error *err);

/* Writes only the textures (the `plumage texture` command). */
plm_result plm_feather_write_textures(const plm_feather *f, const char *dir, const plm_feather_files *files,
                                      plm_error *err);

void plm_feather_free(plm_feather *f);

#endif
