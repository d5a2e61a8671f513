/* asset.h's functions, forwarded to the Assimp module opened on first use
 * (asset_module.h says why it is a module). */
#include <pthread.h>
#include <stdlib.h>
#include <string.h>

#include "common/module.h"
#include "export/asset_module.h"

/* Opened once per process, under pthread_once, as the image module is. */
static pthread_once_t module_once = PTHREAD_ONCE_INIT;
static const plm_asset_module *module_table;
static char module_message[sizeof ((plm_error *)0)->message];

static void load_module(void)
{
    static const plm_module_spec spec = {"glTF library", PLM_ASSET_MODULE_FILE, PLM_ASSET_MODULE_ENV,
                                         PLUMAGE_GLTF_MODULE_BUILD_PATH, PLM_ASSET_MODULE_SYMBOL,
                                         sizeof(plm_asset_module)};
    module_table = plm_module_open(&spec, module_message, sizeof module_message);
}

static const plm_asset_module *asset_module(const char *what, plm_error *err)
{
    pthread_once(&module_once, load_module);
    if (!module_table)
        plm_fail(err, PLM_ERR_INTERNAL, "%s: %s", what, module_message);
    return module_table;
}

plm_result plm_asset_write_gltf(const char *path, const plm_asset *asset, plm_error *err)
{
    const plm_asset_module *m = asset_module(path, err);
    return m ? m->write_gltf(path, asset, err) : PLM_ERR_INTERNAL;
}

plm_result plm_asset_read_gltf(const char *path, plm_asset_summary *out, plm_error *err)
{
    memset(out, 0, sizeof *out);
    const plm_asset_module *m = asset_module(path, err);
    return m ? m->read_gltf(path, out, err) : PLM_ERR_INTERNAL;
}

void plm_asset_summary_free(plm_asset_summary *s)
{
    if (!s)
        return;
    free(s->nodes);
    free(s->meshes);
    free(s->materials);
    memset(s, 0, sizeof *s);
}
