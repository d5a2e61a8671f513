#include "cli/outputs.h"

#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "common/fileio.h"

/* A new file can be made in the folder: one is, and removed again. Asking
 * the file system rather than the permission bits also catches read-only
 * mounts, and works for root, whom the bits do not stop. */
static int takes_a_file(const char *folder, char *why, size_t size)
{
    char probe[PLM_OUTPUTS_PATH + 64];
    snprintf(probe, sizeof probe, "%s/.plumage-check-%ld.tmp", folder, (long)getpid());
    int fd = open(probe, O_WRONLY | O_CREAT | O_EXCL, 0644);
    if (fd < 0) {
        snprintf(why, size, "cannot write into %s: %s", folder, strerror(errno));
        return 0;
    }
    close(fd);
    unlink(probe);
    return 1;
}

/* Makes and checks folder; messages show the option's value `shown`. */
static int check_folder(plm_outputs *o, const char *option, const char *shown, const char *folder)
{
    if (o->count == PLM_OUTPUTS_MAX) {
        fprintf(stderr, "internal error: more than %d outputs checked\n", PLM_OUTPUTS_MAX);
        return 0;
    }
    char *made = o->at[o->count].made, clean[PLM_OUTPUTS_PATH];
    /* Without trailing slashes: undo walks up the path one name at a time. */
    size_t len = strlen(folder);
    while (len > 1 && folder[len - 1] == '/')
        --len;
    if (len >= sizeof clean) {
        fprintf(stderr, "error: %s %s: the path is too long\n", option, shown);
        return 0;
    }
    snprintf(clean, sizeof clean, "%.*s", (int)len, folder);
    folder = clean;
    plm_error err;
    char why[PLM_OUTPUTS_PATH + 128];
    if (plm_make_dirs_noting(folder, made, PLM_OUTPUTS_PATH, &err) != PLM_OK)
        snprintf(why, sizeof why, "%s", err.message);
    else if (takes_a_file(folder, why, sizeof why)) {
        snprintf(o->at[o->count++].folder, PLM_OUTPUTS_PATH, "%s", folder);
        return 1;
    }
    fprintf(stderr, "error: %s %s: %s\n", option, shown, why);
    if (made[0]) { /* undo what this check made */
        snprintf(o->at[o->count].folder, PLM_OUTPUTS_PATH, "%s", folder);
        ++o->count;
        plm_outputs_undo(o);
    }
    return 0;
}

int plm_outputs_folder(plm_outputs *o, const char *option, const char *folder)
{
    return check_folder(o, option, folder, folder);
}

/* The folder of path ("." for a bare name); 0 after a message if too long. */
static int folder_of(const char *option, const char *path, char folder[PLM_OUTPUTS_PATH])
{
    const char *slash = strrchr(path, '/');
    if (!slash)
        snprintf(folder, PLM_OUTPUTS_PATH, ".");
    else if (slash == path)
        snprintf(folder, PLM_OUTPUTS_PATH, "/");
    else if (snprintf(folder, PLM_OUTPUTS_PATH, "%.*s", (int)(slash - path), path) >= PLM_OUTPUTS_PATH) {
        fprintf(stderr, "error: %s %s: the path is too long\n", option, path);
        return 0;
    }
    return 1;
}

int plm_outputs_file(plm_outputs *o, const char *option, const char *path)
{
    struct stat st;
    if (!path[0] || path[strlen(path) - 1] == '/' || (stat(path, &st) == 0 && S_ISDIR(st.st_mode))) {
        fprintf(stderr, "error: %s %s: names a folder, not a file\n", option, path);
        return 0;
    }
    if (stat(path, &st) == 0 && !S_ISREG(st.st_mode)) { /* a device or a pipe: written as it is */
        if (access(path, W_OK) == 0)
            return 1;
        fprintf(stderr, "error: %s %s: cannot write: %s\n", option, path, strerror(errno));
        return 0;
    }
    char folder[PLM_OUTPUTS_PATH];
    return folder_of(option, path, folder) && check_folder(o, option, path, folder);
}

int plm_images_prefix_ok(const char *prefix)
{
    char folder[PLM_OUTPUTS_PATH];
    plm_outputs outputs = {0};
    return folder_of("--images", prefix, folder) && check_folder(&outputs, "--images", prefix, folder);
}

void plm_outputs_undo(plm_outputs *o)
{
    for (int i = o->count - 1; i >= 0; --i) {
        if (!o->at[i].made[0])
            continue;
        char dir[PLM_OUTPUTS_PATH];
        snprintf(dir, sizeof dir, "%s", o->at[i].folder);
        size_t made_len = strlen(o->at[i].made);
        /* From the folder checked up to the outermost one made: all were made here
         * (the inner ones may not exist if making them failed). */
        while (strlen(dir) >= made_len && (rmdir(dir) == 0 || errno == ENOENT)) {
            char *slash = strrchr(dir, '/');
            if (!slash || strlen(dir) == made_len)
                break;
            *slash = '\0';
        }
        o->at[i].made[0] = '\0';
    }
}
