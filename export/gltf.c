/* A plumage scene as a plm_asset (export/asset.h), written as glTF: the
 * scene's meshes and instances as they are, grouped into feather nodes, and
 * its materials baked (export/bake.h). */
#include "export/gltf.h"
#include "common/clock.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "common/fileio.h"
#include "common/image_io.h"
#include "export/asset.h"
#include "optics/feather_bsdf.h"
#include "optics/fiber_table_set.h"
#include "render/material.h"

void plm_gltf_root_matrix(const plm_scene *scene, double m[3][4])
{
    /* The axis nearest the camera's up, with its sign s, goes to +y by a
     * quarter or half turn about one of the others: z-up (x, y, z) becomes
     * (x, s z, -s y), as Blender writes its own z-up scenes, so that an
     * importer's turn back gives the scene as authored. */
    double up[3] = {scene->camera.up.x, scene->camera.up.y, scene->camera.up.z};
    int a = 1;
    for (int k = 0; k < 3; ++k)
        if (fabs(up[k]) > fabs(up[a]))
            a = k;
    double s = up[a] < 0.0 ? -1.0 : 1.0;
    memset(m, 0, sizeof(double) * 12);
    if (a == 1) { /* y-up: a half turn about z if upside down */
        m[0][0] = s, m[1][1] = s, m[2][2] = 1.0;
    } else if (a == 2) { /* about x */
        m[0][0] = 1.0, m[1][2] = s, m[2][1] = -s;
    } else { /* x-up: about z */
        m[0][1] = -s, m[1][0] = s, m[2][2] = 1.0;
    }
}

/* What is being built, with what it owns. */
typedef struct builder {
    const plm_scene *scene;
    const plm_gltf_options *o;
    const char *path;
    plm_asset a;
    int *material_of;        /* scene material -> asset material, -1: unused */
    rgb *tint_sum;           /* per scene material: sum of its instances' tints */
    int *tint_count;
    int *node_of_feather;    /* feather id -> node, -1: none yet */
    unsigned char **pngs;    /* per texture, owned */
    int *source_mesh;        /* per asset mesh: the scene mesh it is */
    float **line_points;     /* per asset mesh of curves: its vertices, owned */
    uint32_t **line_indices; /* and its segments */
} builder;

static plm_result grow_fail(plm_error *err) { return plm_fail(err, PLM_ERR_NO_MEMORY, "glTF export: out of memory"); }

/* Everything but the fluffy bases with no_fluff: curves (a generated feather's fluff) go out as lines. */
static int keep(const builder *b, const plm_instance *in) { return !(b->o->no_fluff && in->part == PLM_PART_FLUFF); }

/* Curves as line segments: each polyline's points as vertices (the radius
 * dropped: glTF lines have no width), consecutive ones joined. */
static plm_result add_lines(builder *b, plm_asset_mesh *am, const plm_curves *c, plm_error *err)
{
    int segments = plm_curves_segment_count(c);
    float *p = malloc(3 * sizeof *p * ((size_t)c->point_count + 1));
    uint32_t *idx = malloc(2 * sizeof *idx * ((size_t)segments + 1));
    b->line_points[b->a.mesh_count] = p;
    b->line_indices[b->a.mesh_count] = idx;
    if (!p || !idx)
        return grow_fail(err);
    for (int i = 0; i < c->point_count; ++i)
        memcpy(p + 3 * (size_t)i, c->points + 4 * (size_t)i, 3 * sizeof *p);
    size_t n = 0;
    for (int k = 0; k < c->curve_count; ++k)
        for (int i = c->first[k]; i + 1 < c->first[k + 1]; ++i)
            idx[n++] = (uint32_t)i, idx[n++] = (uint32_t)i + 1;
    am->lines = 1;
    am->vertex_count = c->point_count;
    am->positions = p;
    am->index_count = 2 * segments;
    am->indices = idx;
    return PLM_OK;
}

/* The asset mesh of an instance's (mesh, material), added on first use. */
static plm_result mesh_for(builder *b, const plm_instance *in, int *out, plm_error *err)
{
    for (int i = 0; i < b->a.mesh_count; ++i)
        if (b->a.meshes[i].material == b->material_of[in->material] && b->source_mesh[i] == in->mesh) {
            *out = i;
            return PLM_OK;
        }
    const plm_scene_mesh *sm = &b->scene->meshes[in->mesh];
    const plm_mesh *m = &sm->mesh;
    plm_asset_mesh *am = &b->a.meshes[b->a.mesh_count];
    memset(am, 0, sizeof *am);
    snprintf(am->name, sizeof am->name, "%s", sm->name);
    am->material = b->material_of[in->material];
    b->source_mesh[b->a.mesh_count] = in->mesh;
    if (sm->curves.curve_count > 0) {
        plm_result rc = add_lines(b, am, &sm->curves, err);
        if (rc != PLM_OK)
            return rc;
    } else {
        am->vertex_count = m->vertex_count;
        am->positions = m->positions;
        am->normals = m->normals;
        am->uvs = m->uvs;
        am->index_count = 3 * m->triangle_count;
        am->indices = m->indices;
    }
    *out = b->a.mesh_count++;
    return PLM_OK;
}

static void set_matrix(plm_asset_node *n, const double m[3][4]) { memcpy(n->matrix, m, sizeof n->matrix); }

static int same_matrix(const double a[3][4], const double b[3][4]) { return memcmp(a, b, sizeof(double) * 12) == 0; }

/* A new node under the root for an instance: a feather's first part or anything else. */
static int new_node(builder *b, int i)
{
    const plm_instance *in = &b->scene->instances[i];
    plm_asset_node *n = &b->a.nodes[b->a.node_count];
    memset(n, 0, sizeof *n);
    n->parent = 0;
    set_matrix(n, in->xform.m);
    if (in->feather > 0)
        snprintf(n->name, sizeof n->name, "feather_%04d", in->feather);
    else
        snprintf(n->name, sizeof n->name, "%.40s_%d", b->scene->meshes[in->mesh].name, i);
    return b->a.node_count++;
}

/* Nodes: the root, then a node per placed feather (its parts share a
 * transform) and per other instance, each naming its asset meshes. */
static plm_result build_nodes(builder *b, plm_gltf_report *r, plm_error *err)
{
    const plm_scene *s = b->scene;
    plm_asset_node *root = &b->a.nodes[b->a.node_count++];
    memset(root, 0, sizeof *root);
    snprintf(root->name, sizeof root->name, "plumage");
    root->parent = -1;
    plm_gltf_root_matrix(s, root->matrix);
    for (int i = 0; i < s->instance_count; ++i) {
        const plm_instance *in = &s->instances[i];
        if (!keep(b, in)) {
            r->left_out++;
            continue;
        }
        r->instances++;
        int mesh;
        plm_result rc = mesh_for(b, in, &mesh, err);
        if (rc != PLM_OK)
            return rc;
        int node = in->feather > 0 ? b->node_of_feather[in->feather] : -1;
        if (node < 0 || b->a.nodes[node].mesh_count == PLM_ASSET_NODE_MESHES ||
            !same_matrix(b->a.nodes[node].matrix, in->xform.m)) {
            node = new_node(b, i);
            if (in->feather > 0 && b->node_of_feather[in->feather] < 0) {
                b->node_of_feather[in->feather] = node;
                r->feathers++;
            }
        }
        plm_asset_node *n = &b->a.nodes[node];
        n->mesh[n->mesh_count++] = mesh;
    }
    return PLM_OK;
}

/* name with characters outside [A-Za-z0-9._-] as '_' (a file name). */
static void safe_name(const char *name, char *out, size_t size)
{
    size_t i = 0;
    for (; name[i] && i + 1 < size; ++i) {
        char c = name[i];
        int ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '.' || c == '-' ||
                 c == '_';
        out[i] = ok ? c : '_';
    }
    out[i] = '\0';
}

static unsigned char to_byte(double v) { return (unsigned char)lrint(255.0 * plm_clamp(v, 0.0, 1.0)); }

/* A texture of the asset from 8-bit pixels: PNG bytes, and for a .gltf the
 * file name beside it (STEM.MATERIAL.KIND.png). */
static plm_result add_texture(builder *b, const char *material, const char *kind, int w, int h, int channels,
                              const unsigned char *px, plm_error *err)
{
    int t = b->a.texture_count;
    plm_asset_texture *tex = &b->a.textures[t];
    memset(tex, 0, sizeof *tex);
    plm_result rc = plm_image_encode_png(w, h, channels, PLM_PIXEL_UINT8, px, &b->pngs[t], &tex->png_size, err);
    if (rc != PLM_OK)
        return rc;
    tex->png = b->pngs[t];
    b->a.texture_count++;
    char ext[16];
    if (strcmp(plm_path_extension(b->path, ext, sizeof ext), "gltf") != 0)
        return PLM_OK;
    const char *slash = strrchr(b->path, '/'), *base = slash ? slash + 1 : b->path;
    char name[PLM_NAME_MAX];
    safe_name(material, name, sizeof name);
    int n = snprintf(tex->uri, sizeof tex->uri, "%.*s.%s.%s.png", (int)(strlen(base) - 5), base, name, kind);
    if (n >= (int)sizeof tex->uri)
        return plm_fail(err, PLM_ERR_INVALID, "%s: the texture file name for material %s is too long", b->path,
                        material);
    return PLM_OK;
}

/* The base colour texture of a feather material: per texel the baked vane
 * colour times the pigment, the rachis colour on rachis texels, alpha a on
 * the vane, 1 on the rachis and 0 on the background (which takes the vane's
 * colour so that filtering at the outline does not darken it). sRGB. */
static plm_result bake_texture(builder *b, const plm_material *m, const plm_bake_albedo *al, rgb tint, plm_error *err)
{
    const plm_feather_texture *t = &m->texture;
    size_t count = (size_t)t->width * t->height;
    unsigned char *px = malloc(4 * count), *dir = malloc(3 * count);
    if (!px || !dir) {
        free(px), free(dir);
        return grow_fail(err);
    }
    for (size_t i = 0; i < count; ++i) {
        int region = t->region[i];
        vec2 uv = v2(((double)(i % t->width) + 0.5) / t->width, 1.0 - ((double)(i / t->width) + 0.5) / t->height);
        rgb c = region == PLM_REGION_RACHIS ? m->reflectance : al->colour;
        if (region == PLM_REGION_VANE)
            c = rgb_mul(c, plm_material_pigment(m, uv));
        c = rgb_mul(c, tint);
        double alpha = region == PLM_REGION_VANE ? al->alpha : region == PLM_REGION_RACHIS ? 1.0 : 0.0;
        px[4 * i] = to_byte(plm_srgb_encode(c.r));
        px[4 * i + 1] = to_byte(plm_srgb_encode(c.g));
        px[4 * i + 2] = to_byte(plm_srgb_encode(c.b));
        px[4 * i + 3] = to_byte(alpha);
        for (int k = 0; k < 3; ++k) /* the orientation texture: the feather texture's channels as they are */
            dir[3 * i + k] = to_byte(t->pixels[3 * i + k]);
    }
    plm_result rc = add_texture(b, m->name, "albedo", t->width, t->height, 4, px, err);
    if (rc == PLM_OK)
        rc = add_texture(b, m->name, "orientation", t->width, t->height, 3, dir, err);
    free(px);
    free(dir);
    return rc;
}

/* What a material's far field depends on beyond itself: its feather or
 * fiber parameters, which variants of a species share (NULL: none). */
static const void *optics_of(const plm_material *m)
{
    return m->type == PLM_MATERIAL_FEATHER ? (const void *)m->feather
           : m->type == PLM_MATERIAL_FIBER ? (const void *)m->fiber
                                           : NULL;
}

/* The albedo of m, baked once per feather or fiber optics (variants share
 * theirs), with the fiber tables rendering would build (render/world.c). */
static plm_result albedo_of(builder *b, int mi, plm_bake_albedo *baked, const void **done, plm_bake_albedo *out,
                            plm_error *err)
{
    const plm_material *m = &b->scene->materials[mi];
    const void *optics = optics_of(m);
    for (int j = 0; j < mi; ++j)
        if (optics && done[j] == optics) {
            *out = baked[j];
            return PLM_OK;
        }
    plm_prepared_material prepared;
    plm_material_prepare(m, &prepared);
    /* Tens of MiB per optics, needed for nothing else here: one set at a time. */
    plm_fiber_table_set tables;
    plm_fiber_table_set_init(&tables, &(plm_fiber_table_options){.threads = b->o->table_threads,
                                                                 .budget_mib = b->scene->film.fiber_table_mib});
    plm_result rc = plm_material_prepare_tables(m, &tables, &prepared, err);
    if (rc == PLM_OK)
        rc = plm_bake_albedo_of(m, &prepared, &b->o->bake, out, err);
    plm_fiber_table_set_free(&tables);
    baked[mi] = *out;
    done[mi] = optics;
    return rc;
}

/* One asset material per scene material used, in the order of first use;
 * feather materials also get their orientation material. */
static plm_result build_materials(builder *b, plm_error *err)
{
    const plm_scene *s = b->scene;
    int n = s->material_count;
    plm_bake_albedo *baked = calloc((size_t)n + 1, sizeof *baked);
    const void **done = calloc((size_t)n + 1, sizeof *done);
    plm_result rc = baked && done ? PLM_OK : grow_fail(err);
    for (int mi = 0; mi < n && rc == PLM_OK; ++mi) {
        if (b->material_of[mi] < 0)
            continue;
        const plm_material *m = &s->materials[mi];
        rgb tint = rgb_scale(b->tint_sum[mi], 1.0 / b->tint_count[mi]);
        plm_bake_albedo al;
        if ((rc = albedo_of(b, mi, baked, done, &al, err)) != PLM_OK)
            break;
        plm_asset_material *am = &b->a.materials[b->material_of[mi]];
        memset(am, 0, sizeof *am);
        snprintf(am->name, sizeof am->name, "%s", m->name);
        am->double_sided = 1;
        am->texture = -1;
        am->blend = al.alpha < 1.0;
        if (m->type != PLM_MATERIAL_FEATHER) {
            rgb c = rgb_mul(al.colour, tint);
            am->base_color[0] = (float)c.r, am->base_color[1] = (float)c.g, am->base_color[2] = (float)c.b;
            am->base_color[3] = (float)al.alpha;
            continue;
        }
        am->base_color[0] = am->base_color[1] = am->base_color[2] = am->base_color[3] = 1.0f;
        am->blend = 1;
        am->texture = b->a.texture_count;
        if ((rc = bake_texture(b, m, &al, tint, err)) != PLM_OK)
            break;
        plm_asset_material *orient = &b->a.materials[b->a.material_count++];
        memset(orient, 0, sizeof *orient);
        snprintf(orient->name, sizeof orient->name, "%.100s.orientation", m->name);
        orient->base_color[0] = orient->base_color[1] = orient->base_color[2] = orient->base_color[3] = 1.0f;
        orient->texture = am->texture + 1;
        orient->unlit = 1;
        orient->double_sided = 1;
    }
    free(baked);
    free(done);
    return rc;
}

/* Which scene materials the kept instances use, and their mean tints. */
static void use_materials(builder *b)
{
    const plm_scene *s = b->scene;
    for (int i = 0; i < s->instance_count; ++i) {
        const plm_instance *in = &s->instances[i];
        if (!keep(b, in))
            continue;
        if (b->material_of[in->material] < 0)
            b->material_of[in->material] = b->a.material_count++;
        b->tint_sum[in->material] = rgb_add(b->tint_sum[in->material], in->tint);
        b->tint_count[in->material]++;
    }
}

static plm_result builder_init(builder *b, const plm_scene *s, const char *path, const plm_gltf_options *o,
                               plm_error *err)
{
    memset(b, 0, sizeof *b);
    b->scene = s, b->path = path, b->o = o;
    size_t ni = (size_t)s->instance_count + 1, nm = (size_t)s->material_count + 1;
    b->a.meshes = calloc(ni, sizeof *b->a.meshes);
    b->a.nodes = calloc(ni + 1, sizeof *b->a.nodes);
    b->a.materials = calloc(2 * nm, sizeof *b->a.materials);
    b->a.textures = calloc(2 * nm, sizeof *b->a.textures);
    b->pngs = calloc(2 * nm, sizeof *b->pngs);
    b->material_of = malloc(nm * sizeof *b->material_of);
    b->tint_sum = calloc(nm, sizeof *b->tint_sum);
    b->tint_count = calloc(nm, sizeof *b->tint_count);
    b->node_of_feather = malloc(((size_t)s->feather_count + 1) * sizeof *b->node_of_feather);
    b->source_mesh = calloc(ni, sizeof *b->source_mesh);
    b->line_points = calloc(ni, sizeof *b->line_points);
    b->line_indices = calloc(ni, sizeof *b->line_indices);
    if (!b->a.meshes || !b->a.nodes || !b->a.materials || !b->a.textures || !b->pngs || !b->material_of ||
        !b->tint_sum || !b->tint_count || !b->node_of_feather || !b->source_mesh || !b->line_points ||
        !b->line_indices)
        return grow_fail(err);
    for (size_t i = 0; i < nm; ++i)
        b->material_of[i] = -1;
    for (int i = 0; i <= s->feather_count; ++i)
        b->node_of_feather[i] = -1;
    return PLM_OK;
}

static void builder_free(builder *b)
{
    for (int i = 0; b->pngs && i < b->a.texture_count; ++i)
        free(b->pngs[i]);
    free(b->pngs);
    free(b->a.meshes);
    free(b->a.nodes);
    free(b->a.materials);
    free(b->a.textures);
    free(b->material_of);
    free(b->tint_sum);
    free(b->tint_count);
    free(b->node_of_feather);
    for (int i = 0; b->line_points && b->line_indices && i <= b->a.mesh_count; ++i)
        free(b->line_points[i]), free(b->line_indices[i]);
    free(b->source_mesh);
    free(b->line_points);
    free(b->line_indices);
}

plm_result plm_gltf_export(const plm_scene *scene, const char *path, const plm_gltf_options *o, plm_gltf_report *report,
                           plm_error *err)
{
    plm_gltf_report r = {0};
    builder b;
    plm_result rc = builder_init(&b, scene, path, o, err);
    if (rc == PLM_OK) {
        use_materials(&b);
        rc = build_nodes(&b, &r, err);
    }
    if (rc == PLM_OK) {
        if (r.instances == 0)
            rc = plm_fail(err, PLM_ERR_INVALID, "%s: the scene has nothing to export (%d instances, %d left out)",
                          path, scene->instance_count, r.left_out);
    }
    double t0 = plm_seconds();
    if (rc == PLM_OK)
        rc = build_materials(&b, err);
    double t1 = plm_seconds();
    if (rc == PLM_OK)
        rc = plm_asset_write_gltf(path, &b.a, err);
    r.bake_seconds = t1 - t0;
    r.write_seconds = plm_seconds() - t1;
    r.nodes = b.a.node_count;
    r.meshes = b.a.mesh_count;
    r.materials = b.a.material_count;
    r.textures = b.a.texture_count;
    for (int i = 0; i < b.a.mesh_count; ++i)
        if (b.a.meshes[i].lines)
            r.line_meshes++, r.segments += b.a.meshes[i].index_count / 2;
    builder_free(&b);
    if (report)
        *report = r;
    return rc;
}
