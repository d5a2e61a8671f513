/* PLY and OBJ readers behind plm_mesh_read (common/mesh.h).
 *
 * plumage reads meshes itself rather than through OpenMesh: fuzzing found
 * OpenMesh's readers crash on small malformed files (a PLY header with a
 * broken "element" line, an OBJ face naming vertices that do not exist), and
 * a scene file may name any file. These readers accept what plumage and the
 * common tools write and check every count and index against the bytes that
 * are really there before allocating (docs/robustness.md).
 *
 * PLY: ascii, binary_little_endian and binary_big_endian; vertex properties
 * x y z, nx ny nz, u v (or s t, texture_u texture_v, texture_s texture_t),
 * tx ty tz (plumage's tangents), density (a pelt's relative feather
 * density); faces as a "vertex_indices" (or
 * "vertex_index") list; polygons become triangle fans; other elements and
 * properties are skipped. OBJ: v, vt, vn and f (with negative indices);
 * other statements are ignored. An OBJ corner is a (v, vt, vn) triple; each
 * distinct triple becomes one mesh vertex, the first one seen for a position
 * keeping that position's index. */
#include <ctype.h>
#include <limits.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "common/fileio.h"
#include "common/mesh.h"

typedef struct grow {
    void *data;
    size_t count, capacity, elem;
} grow;

/* Room for n more elements; 0 when out of memory or past PLM_MESH_MAX_ELEMENTS. */
static int grow_reserve(grow *g, size_t n)
{
    if (g->count + n <= g->capacity)
        return 1;
    if (g->count + n > PLM_MESH_MAX_ELEMENTS)
        return 0;
    size_t cap = g->capacity ? 2 * g->capacity : 256;
    while (cap < g->count + n)
        cap *= 2;
    void *p = realloc(g->data, cap * g->elem);
    if (!p)
        return 0;
    g->data = p;
    g->capacity = cap;
    return 1;
}

/* What both formats produce before the final plm_mesh is assembled. */
typedef struct mesh_builder {
    const char *path;
    plm_error *err;
    grow positions, normals, uvs, tangents, density; /* floats */
    grow indices;                           /* uint32_t */
} mesh_builder;

static plm_result no_memory(mesh_builder *b)
{
    return plm_fail(b->err, PLM_ERR_NO_MEMORY, "%s: out of memory, or more than %d vertices or triangles", b->path,
                    PLM_MESH_MAX_ELEMENTS / 3);
}

static int push_floats(grow *g, const float *v, int n)
{
    if (!grow_reserve(g, (size_t)n))
        return 0;
    memcpy((float *)g->data + g->count, v, sizeof(float) * (size_t)n);
    g->count += (size_t)n;
    return 1;
}

static int push_triangle(grow *g, uint32_t a, uint32_t b, uint32_t c)
{
    if (!grow_reserve(g, 3))
        return 0;
    uint32_t *t = (uint32_t *)g->data + g->count;
    t[0] = a, t[1] = b, t[2] = c;
    g->count += 3;
    return 1;
}

static void builder_free(mesh_builder *b)
{
    free(b->positions.data);
    free(b->normals.data);
    free(b->uvs.data);
    free(b->tangents.data);
    free(b->density.data);
    free(b->indices.data);
}

static int all_finite(const grow *g)
{
    const float *v = g->data;
    for (size_t i = 0; i < g->count; ++i)
        if (!isfinite(v[i]))
            return 0;
    return 1;
}

/* Hands the arrays to out; optional attributes only when every vertex has them. */
static plm_result builder_finish(mesh_builder *b, plm_mesh *out)
{
    size_t nv = b->positions.count / 3;
    if (nv == 0 || b->indices.count == 0)
        return plm_fail(b->err, PLM_ERR_PARSE, "%s: the file holds no triangles", b->path);
    if (!all_finite(&b->positions) || !all_finite(&b->normals) || !all_finite(&b->uvs) ||
        !all_finite(&b->tangents) || !all_finite(&b->density))
        return plm_fail(b->err, PLM_ERR_PARSE, "%s: the file has a non-finite vertex attribute", b->path);
    out->vertex_count = (int)nv;
    out->triangle_count = (int)(b->indices.count / 3);
    out->positions = b->positions.data;
    out->indices = b->indices.data;
    b->positions.data = b->indices.data = NULL;
    grow *optional[4] = {&b->normals, &b->uvs, &b->tangents, &b->density};
    float **dest[4] = {&out->normals, &out->uvs, &out->tangents, &out->density};
    const size_t width[4] = {3, 2, 3, 1};
    for (int k = 0; k < 4; ++k)
        if (optional[k]->count == width[k] * nv) {
            *dest[k] = optional[k]->data;
            optional[k]->data = NULL;
        }
    return PLM_OK;
}

/* ---- text scanning shared by ASCII PLY and OBJ ---- */

typedef struct cursor {
    const char *p, *end;
    long line;
} cursor;

static void skip_blanks(cursor *c)
{
    while (c->p < c->end && (*c->p == ' ' || *c->p == '\t' || *c->p == '\r'))
        ++c->p;
}

/* Moves past the end of the current line. */
static void next_line(cursor *c)
{
    while (c->p < c->end && *c->p != '\n')
        ++c->p;
    if (c->p < c->end)
        ++c->p;
    ++c->line;
}

static int at_line_end(cursor *c)
{
    skip_blanks(c);
    return c->p >= c->end || *c->p == '\n' || *c->p == '#';
}

/* A number on the current line (the buffer ends in a NUL, so strtod stops). */
static int scan_double(cursor *c, double *out)
{
    if (at_line_end(c))
        return 0;
    char *e;
    *out = strtod(c->p, &e);
    if (e == c->p || e > c->end)
        return 0;
    c->p = e;
    return c->p >= c->end || isspace((unsigned char)*c->p) || *c->p == '\0';
}

/* The next word on the current line into buf (truncated to size). */
static int scan_word(cursor *c, char *buf, size_t size)
{
    if (at_line_end(c))
        return 0;
    size_t n = 0;
    while (c->p < c->end && !isspace((unsigned char)*c->p)) {
        if (n + 1 < size)
            buf[n++] = *c->p;
        ++c->p;
    }
    buf[n] = '\0';
    return 1;
}

/* ---- PLY ---- */

enum { PLY_MAX_ELEMENTS = 16, PLY_MAX_PROPERTIES = 64 };

typedef enum ply_type { PLY_NONE, PLY_I8, PLY_U8, PLY_I16, PLY_U16, PLY_I32, PLY_U32, PLY_F32, PLY_F64 } ply_type;

typedef struct ply_property {
    char name[32];
    ply_type type;       /* of the value, or of the list's entries */
    ply_type count_type; /* PLY_NONE unless a list */
} ply_property;

typedef struct ply_element {
    char name[32];
    long long count;
    int property_count;
    ply_property properties[PLY_MAX_PROPERTIES];
} ply_element;

typedef struct ply_file {
    mesh_builder *b;
    int format; /* 0 ascii, 1 little endian, 2 big endian */
    cursor text;
    const unsigned char *bin, *bin_end;
    int element_count;
    ply_element elements[PLY_MAX_ELEMENTS];
} ply_file;

static ply_type ply_type_of(const char *s)
{
    static const char *const names[][2] = {{"char", "int8"},     {"uchar", "uint8"},   {"short", "int16"},
                                           {"ushort", "uint16"}, {"int", "int32"},     {"uint", "uint32"},
                                           {"float", "float32"}, {"double", "float64"}};
    for (int i = 0; i < 8; ++i)
        if (strcmp(s, names[i][0]) == 0 || strcmp(s, names[i][1]) == 0)
            return (ply_type)(i + 1);
    return PLY_NONE;
}

static int ply_size(ply_type t)
{
    static const int sizes[] = {0, 1, 1, 2, 2, 4, 4, 4, 8};
    return sizes[t];
}

static plm_result ply_header_error(ply_file *f, const char *what)
{
    return plm_fail(f->b->err, PLM_ERR_PARSE, "%s: line %ld: %s", f->b->path, f->text.line, what);
}

static plm_result ply_read_header(ply_file *f)
{
    cursor *c = &f->text;
    char word[64];
    if (!scan_word(c, word, sizeof word) || strcmp(word, "ply") != 0)
        return ply_header_error(f, "not a PLY file (it must start with \"ply\")");
    next_line(c);
    int have_format = 0;
    for (;;) {
        if (c->p >= c->end)
            return ply_header_error(f, "the header has no end_header line");
        if (!scan_word(c, word, sizeof word)) {
            next_line(c);
            continue;
        }
        if (strcmp(word, "end_header") == 0) {
            next_line(c);
            break;
        }
        if (strcmp(word, "comment") == 0 || strcmp(word, "obj_info") == 0) {
            next_line(c);
            continue;
        }
        if (strcmp(word, "format") == 0) {
            static const char *const formats[] = {"ascii", "binary_little_endian", "binary_big_endian"};
            double version;
            f->format = -1;
            if (scan_word(c, word, sizeof word))
                for (int i = 0; i < 3; ++i)
                    if (strcmp(word, formats[i]) == 0)
                        f->format = i;
            if (f->format < 0 || !scan_double(c, &version) || version != 1.0 || !at_line_end(c))
                return ply_header_error(f, "format must be ascii, binary_little_endian or binary_big_endian 1.0");
            have_format = 1;
        } else if (strcmp(word, "element") == 0) {
            double count;
            if (f->element_count == PLY_MAX_ELEMENTS)
                return ply_header_error(f, "more than 16 elements");
            ply_element *e = &f->elements[f->element_count++];
            if (!scan_word(c, e->name, sizeof e->name) || !scan_double(c, &count) || !(count >= 0) ||
                count != floor(count) || count > PLM_MESH_MAX_ELEMENTS || !at_line_end(c))
                return ply_header_error(f, "expected \"element NAME COUNT\" with a count of at most 2^30");
            e->count = (long long)count;
        } else if (strcmp(word, "property") == 0) {
            if (f->element_count == 0)
                return ply_header_error(f, "a property before any element");
            ply_element *e = &f->elements[f->element_count - 1];
            if (e->property_count == PLY_MAX_PROPERTIES)
                return ply_header_error(f, "more than 64 properties in one element");
            ply_property *p = &e->properties[e->property_count++];
            if (!scan_word(c, word, sizeof word))
                return ply_header_error(f, "expected \"property TYPE NAME\"");
            if (strcmp(word, "list") == 0) {
                char count_type[16];
                if (!scan_word(c, count_type, sizeof count_type) || !scan_word(c, word, sizeof word))
                    return ply_header_error(f, "expected \"property list COUNT_TYPE TYPE NAME\"");
                p->count_type = ply_type_of(count_type);
                if (p->count_type == PLY_NONE || p->count_type >= PLY_F32)
                    return ply_header_error(f, "a list's count must have an integer type");
            }
            p->type = ply_type_of(word);
            if (p->type == PLY_NONE || !scan_word(c, p->name, sizeof p->name) || !at_line_end(c))
                return ply_header_error(f, "expected a type (char, uchar, short, ushort, int, uint, float, double) "
                                           "and a name");
        } else {
            return ply_header_error(f, "unknown header keyword");
        }
        next_line(c);
    }
    if (!have_format)
        return ply_header_error(f, "the header has no format line");
    return PLM_OK;
}

/* One value of type t; 0 at the end of the data or on a malformed number. */
static int ply_value(ply_file *f, ply_type t, double *out)
{
    if (f->format == 0) { /* values may continue on the next line */
        cursor *c = &f->text;
        for (; c->p < c->end && isspace((unsigned char)*c->p); ++c->p)
            c->line += *c->p == '\n';
        return scan_double(c, out);
    }
    int n = ply_size(t);
    if (f->bin_end - f->bin < n)
        return 0;
    unsigned char b[8];
    for (int i = 0; i < n; ++i) /* to little endian */
        b[i] = f->bin[f->format == 1 ? i : n - 1 - i];
    f->bin += n;
    uint32_t u32 = (uint32_t)b[0] | (uint32_t)b[1] << 8 | (uint32_t)b[2] << 16 | (uint32_t)b[3] << 24;
    switch (t) {
    case PLY_I8: *out = (int8_t)b[0]; break;
    case PLY_U8: *out = b[0]; break;
    case PLY_I16: *out = (int16_t)(b[0] | b[1] << 8); break;
    case PLY_U16: *out = (uint16_t)(b[0] | b[1] << 8); break;
    case PLY_I32: *out = (int32_t)u32; break;
    case PLY_U32: *out = u32; break;
    case PLY_F32: {
        float v;
        memcpy(&v, &u32, 4);
        *out = v;
        break;
    }
    default: {
        uint64_t u64 = u32 | (uint64_t)((uint32_t)b[4] | (uint32_t)b[5] << 8 | (uint32_t)b[6] << 16 |
                                        (uint32_t)b[7] << 24) << 32;
        memcpy(out, &u64, 8);
        break;
    }
    }
    return 1;
}

/* The least number of bytes one record of e takes, to check counts against the file. */
static size_t ply_min_record(const ply_file *f, const ply_element *e)
{
    size_t n = 0;
    for (int i = 0; i < e->property_count; ++i) {
        const ply_property *p = &e->properties[i];
        n += f->format == 0 ? 2 : (size_t)ply_size(p->count_type ? p->count_type : p->type);
    }
    return n;
}

static int ply_find(const ply_element *e, const char *const *names)
{
    for (; *names; ++names)
        for (int i = 0; i < e->property_count; ++i)
            if (e->properties[i].count_type == PLY_NONE && strcmp(e->properties[i].name, *names) == 0)
                return i;
    return -1;
}

static plm_result ply_data_error(ply_file *f, const ply_element *e, long long index, const char *what)
{
    return plm_fail(f->b->err, PLM_ERR_PARSE, "%s: %s %lld: %s", f->b->path, e->name, index, what);
}

/* Reads the records of e; vertex and face elements fill the builder. */
static plm_result ply_read_element(ply_file *f, const ply_element *e)
{
    static const char *const attr_names[][3][4] = {
        {{"x", NULL}, {"y", NULL}, {"z", NULL}},
        {{"nx", NULL}, {"ny", NULL}, {"nz", NULL}},
        {{"u", "s", "texture_u", "texture_s"}, {"v", "t", "texture_v", "texture_t"}},
        {{"tx", NULL}, {"ty", NULL}, {"tz", NULL}},
        {{"density", NULL}},
    };
    mesh_builder *b = f->b;
    int is_vertex = strcmp(e->name, "vertex") == 0, is_face = strcmp(e->name, "face") == 0;
    size_t remaining = f->format == 0 ? (size_t)(f->text.end - f->text.p) : (size_t)(f->bin_end - f->bin);
    size_t record = ply_min_record(f, e);
    if (e->count > 0 && (record == 0 || (size_t)e->count > remaining / record))
        return plm_fail(b->err, PLM_ERR_PARSE, "%s: %lld %s records cannot fit in the %zu bytes left", b->path,
                        e->count, e->name, remaining);
    /* Vertex attribute columns: [attribute][component] -> property index or -1. */
    int column[5][3], present[5] = {0};
    grow *dest[5] = {&b->positions, &b->normals, &b->uvs, &b->tangents, &b->density};
    const int width[5] = {3, 3, 2, 3, 1};
    for (int a = 0; a < 5; ++a) {
        present[a] = is_vertex;
        for (int k = 0; k < width[a]; ++k)
            present[a] &= (column[a][k] = ply_find(e, attr_names[a][k])) >= 0;
    }
    if (is_vertex && !present[0])
        return plm_fail(b->err, PLM_ERR_PARSE, "%s: the vertex element has no x, y and z", b->path);
    static const char *const index_names[] = {"vertex_indices", "vertex_index", NULL};
    int face_list = -1;
    for (int i = 0; is_face && i < e->property_count; ++i)
        for (const char *const *n = index_names; *n; ++n)
            if (e->properties[i].count_type != PLY_NONE && strcmp(e->properties[i].name, *n) == 0)
                face_list = i;
    if (is_face && face_list < 0)
        return plm_fail(b->err, PLM_ERR_PARSE, "%s: the face element has no vertex_indices list", b->path);
    long long vertex_count = (long long)(b->positions.count / 3);
    for (long long r = 0; r < e->count; ++r) {
        double values[PLY_MAX_PROPERTIES];
        uint32_t first = 0, prev = 0;
        for (int i = 0; i < e->property_count; ++i) {
            const ply_property *p = &e->properties[i];
            if (!p->count_type) {
                if (!ply_value(f, p->type, &values[i]))
                    return ply_data_error(f, e, r, "truncated or malformed value");
                continue;
            }
            double n;
            if (!ply_value(f, p->count_type, &n))
                return ply_data_error(f, e, r, "truncated or malformed list");
            /* Checked before the conversion to an integer (found by fuzz_mesh_ply: 6.7e95). */
            if (!(n >= 0 && n <= 1 << 30) || n != floor(n))
                return ply_data_error(f, e, r, "a list's count must be a whole number in [0, 2^30]");
            if (i == face_list && n < 3)
                return ply_data_error(f, e, r, "a face needs at least 3 vertices");
            for (long long k = 0; k < (long long)n; ++k) {
                double v;
                if (!ply_value(f, p->type, &v))
                    return ply_data_error(f, e, r, "truncated or malformed list");
                if (i != face_list)
                    continue;
                if (!(v >= 0 && v < vertex_count) || v != floor(v))
                    return ply_data_error(f, e, r, "a vertex index is not one of the vertices read before");
                uint32_t idx = (uint32_t)v;
                if (k == 0)
                    first = idx;
                else if (k >= 2 && !push_triangle(&b->indices, first, prev, idx))
                    return no_memory(b);
                prev = idx;
            }
        }
        for (int a = 0; a < 5; ++a) {
            if (!present[a])
                continue;
            float v[3];
            for (int k = 0; k < width[a]; ++k)
                v[k] = (float)values[column[a][k]];
            if (!push_floats(dest[a], v, width[a]))
                return no_memory(b);
        }
    }
    return PLM_OK;
}

static plm_result read_ply(mesh_builder *b, const char *data, size_t size)
{
    ply_file f;
    memset(&f, 0, sizeof f);
    f.b = b;
    f.text = (cursor){data, data + size, 1};
    plm_result rc = ply_read_header(&f);
    f.bin = (const unsigned char *)f.text.p;
    f.bin_end = (const unsigned char *)data + size;
    for (int i = 0; rc == PLM_OK && i < f.element_count; ++i) {
        if (strcmp(f.elements[i].name, "face") == 0 && b->positions.count == 0)
            return plm_fail(b->err, PLM_ERR_PARSE, "%s: faces come before the vertices", b->path);
        rc = ply_read_element(&f, &f.elements[i]);
    }
    return rc;
}

/* ---- OBJ ---- */

/* (v, vt, vn) triple -> mesh vertex, open addressing. */
typedef struct corner_key {
    int32_t v, vt, vn; /* v = -1: an empty slot */
} corner_key;

typedef struct corner_map {
    corner_key *keys;
    uint32_t *values;
    size_t capacity;
} corner_map;

typedef struct obj_file {
    mesh_builder *b;
    grow v, vt, vn;           /* floats as read */
    grow corner_v, corner_vt, corner_vn; /* int32 per triangle corner (-1: none) */
} obj_file;

/* An OBJ index (1-based, or negative from the end) into one of count items; -1 if invalid. */
static long obj_index(double v, size_t count)
{
    if (v != floor(v) || v == 0 || fabs(v) > (double)count)
        return -1;
    return v > 0 ? (long)v - 1 : (long)count + (long)v;
}

static int push_int(grow *g, int32_t v)
{
    if (!grow_reserve(g, 1))
        return 0;
    ((int32_t *)g->data)[g->count++] = v;
    return 1;
}

static plm_result obj_line_error(obj_file *o, const cursor *c, const char *what)
{
    return plm_fail(o->b->err, PLM_ERR_PARSE, "%s: line %ld: %s", o->b->path, c->line, what);
}

/* One corner "v", "v/vt", "v//vn" or "v/vt/vn". */
static int obj_corner(obj_file *o, cursor *c, long out[3])
{
    grow *lists[3] = {&o->v, &o->vt, &o->vn};
    const size_t width[3] = {3, 2, 3};
    for (int k = 0; k < 3; ++k) {
        out[k] = -1;
        if (k > 0) {
            if (c->p >= c->end || *c->p != '/')
                continue;
            ++c->p;
            if (c->p < c->end && (*c->p == '/' || isspace((unsigned char)*c->p)))
                continue; /* "v//vn" */
        }
        char *e;
        double v = strtod(c->p, &e);
        if (e == c->p || e > c->end)
            return 0;
        c->p = e;
        if ((out[k] = obj_index(v, lists[k]->count / width[k])) < 0)
            return 0;
    }
    return c->p >= c->end || isspace((unsigned char)*c->p) || *c->p == '\0';
}

static plm_result obj_face(obj_file *o, cursor *c)
{
    long first[3], prev[3], cur[3];
    int n = 0;
    for (; !at_line_end(c); ++n) {
        if (!obj_corner(o, c, cur))
            return obj_line_error(o, c, "a face corner must be v, v/vt, v//vn or v/vt/vn with indices of "
                                        "vertices defined above");
        if (n == 0)
            memcpy(first, cur, sizeof first);
        if (n >= 2) {
            const long *tri[3] = {first, prev, cur};
            for (int t = 0; t < 3; ++t)
                if (!push_int(&o->corner_v, (int32_t)tri[t][0]) || !push_int(&o->corner_vt, (int32_t)tri[t][1]) ||
                    !push_int(&o->corner_vn, (int32_t)tri[t][2]))
                    return no_memory(o->b);
        }
        memcpy(prev, cur, sizeof prev);
    }
    return n >= 3 ? PLM_OK : obj_line_error(o, c, "a face needs at least 3 corners");
}

static plm_result obj_parse(obj_file *o, const char *data, size_t size)
{
    cursor c = {data, data + size, 1};
    for (; c.p < c.end; next_line(&c)) {
        char word[8];
        if (!scan_word(&c, word, sizeof word))
            continue;
        int width = strcmp(word, "v") == 0 ? 3 : strcmp(word, "vn") == 0 ? 3 : strcmp(word, "vt") == 0 ? 2 : 0;
        if (strcmp(word, "f") == 0) {
            plm_result rc = obj_face(o, &c);
            if (rc != PLM_OK)
                return rc;
            continue;
        }
        if (!width)
            continue; /* o, g, s, usemtl, mtllib, l, p, ...: nothing plumage uses */
        float v[3];
        double d;
        for (int k = 0; k < width; ++k) {
            if (!scan_double(&c, &d))
                return obj_line_error(o, &c, width == 2 ? "vt needs 2 numbers" : "v and vn need 3 numbers");
            v[k] = (float)d;
        }
        grow *g = word[1] == 't' ? &o->vt : word[1] == 'n' ? &o->vn : &o->v;
        if (!push_floats(g, v, width))
            return no_memory(o->b);
    }
    return PLM_OK;
}

static size_t corner_slot(const corner_map *m, corner_key k)
{
    uint64_t h = ((uint64_t)(uint32_t)k.v * 0x9E3779B97F4A7C15ull) ^ ((uint64_t)(uint32_t)k.vt * 0xC2B2AE3D27D4EB4Full) ^
                 ((uint64_t)(uint32_t)k.vn * 0x165667B19E3779F9ull);
    size_t slot = (size_t)((h ^ (h >> 29)) % m->capacity);
    while (m->keys[slot].v != -1 && !(m->keys[slot].v == k.v && m->keys[slot].vt == k.vt && m->keys[slot].vn == k.vn))
        slot = (slot + 1) % m->capacity;
    return slot;
}

/* Assigns mesh vertices to corners: the first triple seen for position v is vertex v. */
static plm_result obj_build(obj_file *o)
{
    mesh_builder *b = o->b;
    size_t corners = o->corner_v.count, nv = o->v.count / 3, nt = o->vt.count / 2, nn = o->vn.count / 3;
    const int32_t *cv = o->corner_v.data, *ct = o->corner_vt.data, *cn = o->corner_vn.data;
    if (corners == 0)
        return plm_fail(b->err, PLM_ERR_PARSE, "%s: the file holds no faces", b->path);
    int uvs = nt > 0, normals = nn > 0;
    for (size_t i = 0; i < corners; ++i)
        uvs &= ct[i] >= 0, normals &= cn[i] >= 0;
    corner_map map = {NULL, NULL, 2 * corners + 16};
    map.keys = malloc(map.capacity * sizeof *map.keys);
    map.values = malloc(map.capacity * sizeof *map.values);
    unsigned char *claimed = calloc(nv + 1, 1);
    plm_result rc = PLM_OK;
    if (!map.keys || !map.values || !claimed || !grow_reserve(&b->positions, 3 * nv) ||
        (uvs && !grow_reserve(&b->uvs, 2 * nv)) || (normals && !grow_reserve(&b->normals, 3 * nv)) ||
        !grow_reserve(&b->indices, corners))
        rc = no_memory(b);
    if (rc == PLM_OK) {
        memset(map.keys, 0xff, map.capacity * sizeof *map.keys);
        /* Every position is a vertex (unused ones too), with zero uv and normal until a corner claims it. */
        memcpy(b->positions.data, o->v.data, 3 * nv * sizeof(float));
        b->positions.count = 3 * nv;
        if (uvs)
            memset(b->uvs.data, 0, 2 * nv * sizeof(float)), b->uvs.count = 2 * nv;
        if (normals)
            memset(b->normals.data, 0, 3 * nv * sizeof(float)), b->normals.count = 3 * nv;
    }
    for (size_t i = 0; rc == PLM_OK && i < corners; ++i) {
        int32_t t = uvs ? ct[i] : -1, n = normals ? cn[i] : -1;
        corner_key key = {cv[i], t, n};
        size_t slot = corner_slot(&map, key);
        if (map.keys[slot].v == -1) {
            uint32_t vertex = (uint32_t)cv[i];
            if (claimed[vertex]) { /* a second uv or normal for this position: a new vertex */
                vertex = (uint32_t)(b->positions.count / 3);
                if (!push_floats(&b->positions, (float *)o->v.data + 3 * (size_t)cv[i], 3) ||
                    (uvs && !push_floats(&b->uvs, (float *)o->vt.data, 2)) ||
                    (normals && !push_floats(&b->normals, (float *)o->vn.data, 3))) {
                    rc = no_memory(b);
                    break;
                }
            }
            claimed[cv[i]] = 1;
            if (uvs)
                memcpy((float *)b->uvs.data + 2 * (size_t)vertex, (float *)o->vt.data + 2 * (size_t)t, 2 * sizeof(float));
            if (normals)
                memcpy((float *)b->normals.data + 3 * (size_t)vertex, (float *)o->vn.data + 3 * (size_t)n,
                       3 * sizeof(float));
            map.keys[slot] = key;
            map.values[slot] = vertex;
        }
        ((uint32_t *)b->indices.data)[b->indices.count++] = map.values[slot];
    }
    free(map.keys);
    free(map.values);
    free(claimed);
    return rc;
}

static plm_result read_obj(mesh_builder *b, const char *data, size_t size)
{
    obj_file o;
    memset(&o, 0, sizeof o);
    o.b = b;
    o.v.elem = o.vt.elem = o.vn.elem = sizeof(float);
    o.corner_v.elem = o.corner_vt.elem = o.corner_vn.elem = sizeof(int32_t);
    plm_result rc = obj_parse(&o, data, size);
    if (rc == PLM_OK)
        rc = obj_build(&o);
    grow *all[] = {&o.v, &o.vt, &o.vn, &o.corner_v, &o.corner_vt, &o.corner_vn};
    for (size_t i = 0; i < sizeof all / sizeof all[0]; ++i)
        free(all[i]->data);
    return rc;
}

plm_result plm_mesh_read(const char *path, plm_mesh *out, plm_error *err)
{
    memset(out, 0, sizeof *out);
    char ext[16];
    plm_path_extension(path, ext, sizeof ext);
    int ply = strcmp(ext, "ply") == 0;
    if (!ply && strcmp(ext, "obj") != 0)
        return plm_fail(err, PLM_ERR_INVALID, "%s: unsupported mesh format '.%s' (use .ply or .obj)", path, ext);
    char *data;
    size_t size;
    plm_result rc = plm_read_file(path, PLM_MESH_FILE_MAX, &data, &size, err);
    if (rc != PLM_OK)
        return rc;
    mesh_builder b;
    memset(&b, 0, sizeof b);
    b.path = path;
    b.err = err;
    b.positions.elem = b.normals.elem = b.uvs.elem = b.tangents.elem = b.density.elem = sizeof(float);
    b.indices.elem = sizeof(uint32_t);
    rc = ply ? read_ply(&b, data, size) : read_obj(&b, data, size);
    free(data);
    if (rc == PLM_OK)
        rc = builder_finish(&b, out);
    builder_free(&b);
    if (rc != PLM_OK)
        plm_mesh_free(out);
    return rc;
}
