#include "common/fileio.h"

#include <ctype.h>
#include <errno.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

void plm_temp_path_for(const char *path, char *out, size_t out_size)
{
    static atomic_uint counter;
    unsigned n = atomic_fetch_add(&counter, 1u);
    const char *slash = strrchr(path, '/');
    const char *base = slash ? slash + 1 : path;
    const char *dot = strrchr(base, '.');
    int dir_len = (int)(base - path);
    int stem_len = dot && dot != base ? (int)(dot - base) : (int)strlen(base);
    const char *ext = dot && dot != base ? dot : "";
    snprintf(out, out_size, "%.*s.%.*s.tmp%ld-%u%s", dir_len, path, stem_len, base, (long)getpid(), n, ext);
}

plm_result plm_atomic_open(plm_atomic_file *f, const char *path, plm_error *err)
{
    memset(f, 0, sizeof *f);
    if (strlen(path) >= sizeof f->path - 64)
        return plm_fail(err, PLM_ERR_INVALID, "%s: path is too long", path);
    snprintf(f->path, sizeof f->path, "%s", path);
    plm_temp_path_for(path, f->temp_path, sizeof f->temp_path);
    f->fp = fopen(f->temp_path, "wb");
    if (!f->fp)
        return plm_fail(err, PLM_ERR_IO, "%s: cannot create file: %s", path, strerror(errno));
    return PLM_OK;
}

plm_result plm_atomic_commit(plm_atomic_file *f, plm_error *err)
{
    int failed = ferror(f->fp);
    failed |= fclose(f->fp) != 0;
    f->fp = NULL;
    if (failed) {
        remove(f->temp_path);
        return plm_fail(err, PLM_ERR_IO, "%s: write failed", f->path);
    }
    if (rename(f->temp_path, f->path) != 0) {
        int e = errno;
        remove(f->temp_path);
        return plm_fail(err, PLM_ERR_IO, "%s: cannot rename into place: %s", f->path, strerror(e));
    }
    return PLM_OK;
}

void plm_atomic_abort(plm_atomic_file *f)
{
    if (f->fp)
        fclose(f->fp);
    f->fp = NULL;
    if (f->temp_path[0])
        remove(f->temp_path);
}

plm_result plm_make_dirs(const char *path, plm_error *err)
{
    char buf[4096];
    if (snprintf(buf, sizeof buf, "%s", path) >= (int)sizeof buf)
        return plm_fail(err, PLM_ERR_INVALID, "%s: path is too long", path);
    for (char *p = buf + 1;; ++p) {
        char c = *p;
        if (c == '/' || c == '\0') {
            *p = '\0';
            if (mkdir(buf, 0777) != 0 && errno != EEXIST)
                return plm_fail(err, PLM_ERR_IO, "%s: cannot create directory: %s", buf, strerror(errno));
            *p = c;
        }
        if (c == '\0')
            break;
    }
    struct stat st;
    if (stat(path, &st) != 0 || !S_ISDIR(st.st_mode))
        return plm_fail(err, PLM_ERR_IO, "%s: not a directory", path);
    return PLM_OK;
}

plm_result plm_read_text_file(const char *path, char **out, plm_error *err)
{
    *out = NULL;
    FILE *fp = fopen(path, "rb");
    if (!fp)
        return plm_fail(err, PLM_ERR_IO, "%s: cannot open: %s", path, strerror(errno));
    size_t cap = 1 << 16, len = 0;
    char *buf = NULL;
    for (;;) {
        char *bigger = realloc(buf, cap);
        if (!bigger) {
            free(buf);
            fclose(fp);
            return plm_fail(err, PLM_ERR_NO_MEMORY, "%s: out of memory reading the file", path);
        }
        buf = bigger;
        len += fread(buf + len, 1, cap - len - 1, fp);
        if (len < cap - 1)
            break;
        cap *= 2;
    }
    int read_error = ferror(fp);
    fclose(fp);
    if (read_error) {
        free(buf);
        return plm_fail(err, PLM_ERR_IO, "%s: read error", path);
    }
    buf[len] = '\0';
    *out = buf;
    return PLM_OK;
}

const char *plm_path_extension(const char *path, char *buf, size_t buf_size)
{
    const char *slash = strrchr(path, '/');
    const char *dot = strrchr(slash ? slash : path, '.');
    size_t i = 0;
    if (dot)
        for (const char *p = dot + 1; *p && i + 1 < buf_size; ++p)
            buf[i++] = (char)tolower((unsigned char)*p);
    buf[i] = '\0';
    return buf;
}
