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

void plm_output_target(const char *path, char *target, size_t target_size)
{
    struct stat st;
    if (stat(path, &st) == 0 && !S_ISREG(st.st_mode) && !S_ISDIR(st.st_mode))
        snprintf(target, target_size, "%s", path);
    else
        plm_temp_path_for(path, target, target_size);
}

void plm_output_discard(const char *path, const char *target)
{
    if (target[0] && strcmp(path, target) != 0)
        remove(target);
}

plm_result plm_output_commit(const char *path, const char *target, plm_error *err)
{
    if (strcmp(path, target) == 0)
        return PLM_OK;
    if (rename(target, path) != 0) {
        int e = errno;
        remove(target);
        return plm_fail(err, PLM_ERR_IO, "%s: cannot rename into place: %s", path, strerror(e));
    }
    return PLM_OK;
}

plm_result plm_atomic_open(plm_atomic_file *f, const char *path, plm_error *err)
{
    memset(f, 0, sizeof *f);
    if (strlen(path) >= sizeof f->path - 64)
        return plm_fail(err, PLM_ERR_INVALID, "%s: path is too long", path);
    snprintf(f->path, sizeof f->path, "%s", path);
    plm_output_target(path, f->temp_path, sizeof f->temp_path);
    f->fp = fopen(f->temp_path, "wb");
    if (!f->fp)
        return plm_fail(err, PLM_ERR_IO, "%s: cannot create file: %s", path, strerror(errno));
    return PLM_OK;
}

plm_result plm_atomic_commit(plm_atomic_file *f, plm_error *err)
{
    int failed = ferror(f->fp);
    failed |= fflush(f->fp) != 0;
    int e = errno;
    failed |= fclose(f->fp) != 0;
    f->fp = NULL;
    if (failed) {
        plm_output_discard(f->path, f->temp_path);
        return plm_fail(err, PLM_ERR_IO, "%s: write failed: %s", f->path, strerror(e ? e : errno));
    }
    return plm_output_commit(f->path, f->temp_path, err);
}

void plm_atomic_abort(plm_atomic_file *f)
{
    if (f->fp)
        fclose(f->fp);
    f->fp = NULL;
    plm_output_discard(f->path, f->temp_path);
}

plm_result plm_write_file(const char *path, const void *data, size_t size, plm_error *err)
{
    plm_atomic_file f;
    plm_result rc = plm_atomic_open(&f, path, err);
    if (rc != PLM_OK)
        return rc;
    if (fwrite(data, 1, size, f.fp) != size) {
        int e = errno;
        plm_atomic_abort(&f);
        return plm_fail(err, PLM_ERR_IO, "%s: write failed: %s", path, strerror(e));
    }
    return plm_atomic_commit(&f, err);
}

plm_result plm_make_dirs_noting(const char *path, char *first_created, size_t size, plm_error *err)
{
    char buf[4096];
    if (first_created && size)
        first_created[0] = '\0';
    if (snprintf(buf, sizeof buf, "%s", path) >= (int)sizeof buf)
        return plm_fail(err, PLM_ERR_INVALID, "%s: path is too long", path);
    for (char *p = buf + 1;; ++p) {
        char c = *p;
        if (c == '/' || c == '\0') {
            *p = '\0';
            if (mkdir(buf, 0777) == 0) {
                if (first_created && size && !first_created[0])
                    snprintf(first_created, size, "%s", buf);
            } else if (errno != EEXIST) {
                return plm_fail(err, PLM_ERR_IO, "%s: cannot create directory: %s", buf, strerror(errno));
            }
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

plm_result plm_make_dirs(const char *path, plm_error *err) { return plm_make_dirs_noting(path, NULL, 0, err); }

plm_result plm_read_file(const char *path, size_t max_size, char **out, size_t *size, plm_error *err)
{
    *out = NULL;
    *size = 0;
    /* Checked before opening too: opening a FIFO would wait for a writer. */
    struct stat st;
    if (stat(path, &st) == 0 && !S_ISREG(st.st_mode))
        return plm_fail(err, PLM_ERR_IO, "%s: not a regular file", path);
    FILE *fp = fopen(path, "rb");
    if (!fp)
        return plm_fail(err, PLM_ERR_IO, "%s: cannot open: %s", path, strerror(errno));
    if (fstat(fileno(fp), &st) != 0 || !S_ISREG(st.st_mode)) {
        fclose(fp);
        return plm_fail(err, PLM_ERR_IO, "%s: not a regular file", path);
    }
    if ((unsigned long long)st.st_size > max_size) {
        fclose(fp);
        return plm_fail(err, PLM_ERR_INVALID, "%s: %lld bytes is more than the limit of %zu bytes for this kind of file",
                        path, (long long)st.st_size, max_size);
    }
    size_t n = (size_t)st.st_size;
    char *buf = malloc(n + 1);
    if (!buf) {
        fclose(fp);
        return plm_fail(err, PLM_ERR_NO_MEMORY, "%s: out of memory reading %zu bytes", path, n);
    }
    size_t got = fread(buf, 1, n, fp);
    int read_error = ferror(fp) || got != n;
    fclose(fp);
    if (read_error) {
        free(buf);
        return plm_fail(err, PLM_ERR_IO, "%s: read error", path);
    }
    buf[n] = '\0';
    *out = buf;
    *size = n;
    return PLM_OK;
}

plm_result plm_read_text_file(const char *path, char **out, plm_error *err)
{
    size_t size;
    return plm_read_file(path, PLM_TEXT_FILE_MAX, out, &size, err);
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
