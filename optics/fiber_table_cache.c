/* The fiber tables' disk cache: one file per (parameters, resolution, format
 * version), named by a hash of them. A file is trusted only if its header
 * (magic, version, the parameters themselves, the sizes) matches and its
 * size and checksum are right; anything else is rebuilt and replaced. Files
 * are written to a temporary name and renamed into place, so processes
 * building the same table at once each leave a complete file, and the last
 * rename wins. */
#include "optics/fiber_table.h"

#include <fcntl.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include "common/fileio.h"

typedef struct cache_header {
    char magic[8];
    uint32_t version, header_bytes;
    uint64_t key;
    int32_t theta_nodes, phi_nodes, h_cells, phi_bins, symmetry, grazing_nodes, grazing_cells, reserved;
    int32_t medulla[8]; /* the medulla part's resolution */
    double params[PLM_FIBER_TABLE_PARAM_WORDS];
    uint64_t floats, checksum;
    char pad[24]; /* to 256 bytes, so that a mapped file's data is as aligned as the header's size */
} cache_header;

_Static_assert(sizeof(cache_header) == 256, "the data follows the header at a 256-byte offset");

static const char cache_magic[8] = {'P', 'L', 'M', 'F', 'T', 'A', 'B', '\n'};

/* + 0.0 makes -0 and 0 alike. */
void plm_fiber_table_param_words(const plm_fiber_params *p, double w[PLM_FIBER_TABLE_PARAM_WORDS])
{
    const double v[PLM_FIBER_TABLE_PARAM_WORDS] = {p->eccentricity, p->eta, p->sigma_a.r, p->sigma_a.g, p->sigma_a.b,
                                   p->beta_m, p->beta_n, p->medulla_a, p->medulla_b, p->medulla_ca,
                                   p->medulla_cb, p->medulla_reflectance.r, p->medulla_reflectance.g,
                                   p->medulla_reflectance.b, (double)p->lobes, 0.0};
    for (int i = 0; i < PLM_FIBER_TABLE_PARAM_WORDS; ++i)
        w[i] = v[i] + 0.0;
}

/* FNV-1a, 64 bits, over bytes (the header and the key). */
static uint64_t fnv1a(uint64_t h, const void *data, size_t n)
{
    const unsigned char *b = data;
    for (size_t i = 0; i < n; ++i)
        h = (h ^ b[i]) * 0x100000001b3ull;
    return h;
}

/* The data's checksum: FNV-1a's step over 64-bit words (8 times fewer steps
 * than bytes, so checking a 32 MiB table costs milliseconds), then the tail. */
static uint64_t checksum(uint64_t h, const float *data, size_t floats)
{
    size_t words = floats / 2;
    for (size_t i = 0; i < words; ++i) {
        uint64_t w;
        memcpy(&w, data + 2 * i, sizeof w);
        h = (h ^ w) * 0x100000001b3ull;
        h ^= h >> 29;
    }
    return fnv1a(h, data + 2 * words, sizeof(float) * (floats - 2 * words));
}

static const uint64_t fnv_basis = 0xcbf29ce484222325ull;

/* The header a table with this layout must have (checksum left 0). */
static void expected_header(const plm_fiber_table *t, cache_header *h)
{
    memset(h, 0, sizeof *h);
    memcpy(h->magic, cache_magic, sizeof h->magic);
    h->version = PLM_FIBER_TABLE_VERSION;
    h->header_bytes = sizeof *h;
    h->theta_nodes = t->theta_nodes;
    h->phi_nodes = t->phi_nodes;
    h->h_cells = t->h_cells;
    h->phi_bins = t->phi_bins;
    h->symmetry = t->symmetry;
    h->grazing_nodes = t->grazing_nodes;
    h->grazing_cells = t->grazing_cells;
    const plm_fiber_medulla_resolution *r = &t->medulla.res;
    const int32_t medulla[8] = {r->theta_nodes, r->phi_nodes, r->h_cells,  r->theta_bins,
                                r->phi_bins,  r->directions, r->points, r->records};
    memcpy(h->medulla, medulla, sizeof medulla);
    plm_fiber_table_param_words(&t->params, h->params);
    h->floats = t->floats;
    h->key = fnv1a(fnv_basis, h, offsetof(cache_header, key));
    h->key = fnv1a(h->key, &h->theta_nodes, offsetof(cache_header, checksum) - offsetof(cache_header, theta_nodes));
}

static int cache_dir(const plm_fiber_table_options *o, char *dir, size_t size)
{
    const char *env;
    int n;
    if (o && o->no_cache)
        return 0;
    if (o && o->cache_dir && o->cache_dir[0])
        n = snprintf(dir, size, "%s", o->cache_dir);
    else if ((env = getenv("PLUMAGE_CACHE_DIR")) && env[0])
        n = snprintf(dir, size, "%s", env);
    else if ((env = getenv("XDG_CACHE_HOME")) && env[0])
        n = snprintf(dir, size, "%s/plumage", env);
    else if ((env = getenv("HOME")) && env[0])
        n = snprintf(dir, size, "%s/.cache/plumage", env);
    else
        return 0;
    return n > 0 && (size_t)n < size;
}

static int path_for(const plm_fiber_table *t, const plm_fiber_table_options *o, char *path, size_t size)
{
    char dir[4000];
    if (!cache_dir(o, dir, sizeof dir))
        return 0;
    cache_header h;
    expected_header(t, &h);
    int n = snprintf(path, size, "%s/fiber-v%d-%016llx.bin", dir, PLM_FIBER_TABLE_VERSION,
                     (unsigned long long)h.key);
    return n > 0 && (size_t)n < size;
}

int plm_fiber_table_cache_path(const plm_fiber_params *p, const plm_fiber_table_options *o, char *path, size_t size)
{
    plm_fiber_table t;
    plm_fiber_table_layout(p, o, &t);
    return path_for(&t, o, path, size);
}

/* Maps path read-only as t->data if the file is complete and is this
 * table's. A mapping costs no copy and no fresh pages: processes that read
 * the same table share the page cache's copy. */
static int map(plm_fiber_table *t, const char *path)
{
    int fd = open(path, O_RDONLY);
    if (fd < 0)
        return 0;
    size_t bytes = sizeof(cache_header) + sizeof(float) * t->floats;
    struct stat st;
    int flags = MAP_PRIVATE;
#ifdef MAP_POPULATE
    flags |= MAP_POPULATE; /* every page is read by the checksum at once */
#endif
    void *m = fstat(fd, &st) == 0 && (size_t)st.st_size == bytes ? mmap(NULL, bytes, PROT_READ, flags, fd, 0)
                                                                  : MAP_FAILED;
    close(fd);
    if (m == MAP_FAILED)
        return 0;
    cache_header want, got;
    expected_header(t, &want);
    memcpy(&got, m, sizeof got);
    const float *data = (const float *)((const char *)m + sizeof got);
    if (memcmp(&got, &want, offsetof(cache_header, checksum)) != 0 ||
        checksum(fnv_basis, data, t->floats) != got.checksum) {
        munmap(m, bytes);
        return 0;
    }
    t->mapping = m;
    t->mapping_bytes = bytes;
    t->data = (float *)data; /* never written: the mapping is read-only */
    return 1;
}

void plm_fiber_table_release_data(plm_fiber_table *t)
{
    if (t->mapping)
        munmap(t->mapping, t->mapping_bytes);
    else
        free(t->data);
    t->mapping = NULL;
    t->mapping_bytes = 0;
    t->data = NULL;
}

static plm_result save(const plm_fiber_table *t, const char *path, plm_error *err)
{
    char dir[4096];
    snprintf(dir, sizeof dir, "%s", path);
    char *slash = strrchr(dir, '/');
    if (slash && slash != dir) {
        *slash = '\0';
        plm_result rc = plm_make_dirs(dir, err);
        if (rc != PLM_OK)
            return rc;
    }
    cache_header h;
    expected_header(t, &h);
    h.checksum = checksum(fnv_basis, t->data, t->floats);
    plm_atomic_file f;
    plm_result rc = plm_atomic_open(&f, path, err);
    if (rc != PLM_OK)
        return rc;
    if (fwrite(&h, sizeof h, 1, f.fp) != 1 || fwrite(t->data, sizeof(float), t->floats, f.fp) != t->floats) {
        plm_atomic_abort(&f);
        return plm_fail(err, PLM_ERR_IO, "%s: write failed", path);
    }
    return plm_atomic_commit(&f, err);
}

plm_result plm_fiber_table_get(const plm_fiber_params *p, const plm_fiber_table_options *o, plm_fiber_table **out,
                               plm_error *err)
{
    *out = NULL;
    plm_result rc = plm_fiber_params_validate(p, err);
    if (rc != PLM_OK)
        return rc;
    if (p->lobes > PLM_FIBER_SET_MAX_LOBES) /* the table keeps each lobe's place per h cell bound */
        return plm_fail(err, PLM_ERR_INVALID, "fiber table: lobes %d is out of range [1, %d]", p->lobes,
                        PLM_FIBER_SET_MAX_LOBES);
    plm_fiber_table *t = malloc(sizeof *t);
    if (!t)
        return plm_fail(err, PLM_ERR_NO_MEMORY, "fiber table: out of memory");
    plm_fiber_table_layout(p, o, t);
    char path[4096];
    int cached = path_for(t, o, path, sizeof path);
    t->from_cache = cached && map(t, path);
    if ((rc = plm_fiber_table_alloc(t, err)) != PLM_OK) {
        free(t);
        return rc;
    }
    if (!t->from_cache && (rc = plm_fiber_table_build(t, o, err)) != PLM_OK) {
        plm_fiber_table_free(t);
        return rc;
    }
    plm_fiber_table_bound_energies(t);
    plm_error save_err;
    /* A cache that cannot be written costs a rebuild next time, nothing more. */
    if (cached && !t->from_cache && save(t, path, &save_err) != PLM_OK && !(o && o->quiet))
        fprintf(stderr, "warning: fiber table not cached: %s\n", save_err.message);
    *out = t;
    return PLM_OK;
}
